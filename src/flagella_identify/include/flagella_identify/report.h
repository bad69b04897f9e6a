// The identification report: report.json (everything, machine-readable), report.md (for a
// reader), extended_config.yaml (the baseline plus the named effects with fitted values,
// runnable by flagella_run), and plot_data.csv (data vs baseline vs extended model, one row per
// residual) for scripts/plot_identification.py.
#pragma once

#include <string>
#include <vector>

#include "flagella_identify/identify.h"

namespace flagella {
namespace identify {

struct ReportInputs {
  std::vector<std::string> data_files;
  std::string baseline_config;
  std::string command_line;
};

/// Writes the four files into `directory` (created if missing); returns their paths.
std::vector<std::string> writeReport(const Identification& identification,
                                     const IdentifyResult& result, const ReportInputs& inputs,
                                     const std::string& directory);

}  // namespace identify
}  // namespace flagella
