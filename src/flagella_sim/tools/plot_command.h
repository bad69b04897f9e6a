// Runs a matplotlib plot script on a CSV table (the tools' sweep plots): prints where the plot
// went, or a warning if plotting failed (the table is still there).
#pragma once

#include <cstdio>
#include <cstdlib>
#include <string>

namespace flagella::cli {

/// `shown` is the path printed for the plot (default `png`; a run's plot is drawn in a staging
/// folder and moved).
inline void plotTable(const std::string& script, const std::string& table, const std::string& png,
                      const char* what = "sweep plot", const std::string& shown = "") {
  if (script.empty()) return;
  const std::string cmd = "/usr/bin/python3 '" + script + "' '" + table + "' '" + png + "'";
  if (std::system(cmd.c_str()) == 0)
    std::printf("%s: %s\n", what, (shown.empty() ? png : shown).c_str());
  else
    std::fprintf(stderr, "warning: plotting failed (%s)\n", cmd.c_str());
}

}  // namespace flagella::cli
