// flagella_discovery_bench: the detection table. For each hidden-effect case and seed it
// generates a data set, hands the identification only the data and the baseline config, and
// prints whether the named cause is the hidden one and the held-out gain.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>

#include "flagella_identify/discovery_cases.h"
#include "flagella_identify/identify.h"
#include "flagella_identify/model.h"
#include "flagella_sim/runtime/tool_main.h"

using namespace flagella;
using namespace flagella::identify;

namespace {

/// Correct when the named set equals the hidden set; for null and unknown cases, when
/// nothing is named (and, for unknown, the verdict is an unexplained residual).
bool correct(const DiscoveryCase& c, const IdentifyResult& r) {
  if (c.unknown) return r.verdict == Verdict::kUnexplained;
  // "cannot tell", with every hidden effect among the suggested measurements' models
  if (r.verdict == Verdict::kCannotTell && !c.hidden.empty())
    return std::all_of(c.hidden.begin(), c.hidden.end(), [&](const std::string& h) {
      return std::any_of(
          r.suggestions.begin(), r.suggestions.end(),
          [&](const SuggestedMeasurement& s) { return s.candidate == h || s.reference == h; });
    });
  std::vector<std::string> named = r.named, hidden = c.hidden;
  std::sort(named.begin(), named.end());
  std::sort(hidden.begin(), hidden.end());
  return named == hidden;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"flagella_discovery_bench: detection table of the model-discovery tool"};
  std::vector<std::string> cases;
  int first_seed = 1, seeds = 3, jobs = 2;
  std::string config = FLAGELLA_CONFIG_DIR "/identification/granular_design1_coarse.yaml";
  bool verbose = false, before = false;
  app.add_option("--cases", cases, "cases (default: all)")->delimiter(',');
  app.add_option("--first-seed", first_seed)->capture_default_str();
  app.add_option("--seeds", seeds, "seeds per case")->capture_default_str();
  app.add_option("--jobs", jobs)->capture_default_str();
  app.add_option("--config", config)->capture_default_str();
  std::vector<std::string> candidates;
  app.add_option("--candidates", candidates, "candidate effects (default: the standard list)")
      ->delimiter(',');
  app.add_flag("--verbose", verbose, "progress of every identification");
  app.add_flag("--without-small-data-methods", before,
               "without cross validation, power check and continuation fits (the pipeline "
               "before them, for a before/after table)");
  if (const auto exit_code = flagella::cli::parseArguments(app, argc, argv)) return *exit_code;
  if (cases.empty())
    for (const DiscoveryCase& c : discoveryCases()) cases.push_back(c.name);
  return flagella::cli::runGuarded([&] {
    const YAML::Node baseline = loadConfigTree(config, {});
    struct Tally {
      int runs = 0, correct = 0, false_names = 0;
      double seconds = 0.0;
      std::vector<double> gains;
      std::vector<std::string> outcomes;
    };
    std::map<std::string, Tally> tally;
    for (const std::string& name : cases) {
      const DiscoveryCase& c = discoveryCaseByName(name);
      for (int seed = first_seed; seed < first_seed + seeds; ++seed) {
        const auto start = std::chrono::steady_clock::now();
        EvaluatorOptions eo;
        eo.jobs = jobs;
        GeneratedCase g = generateCase(c, baseline, config, seed, eo);
        IdentifyOptions o;
        o.free = caseFreeParameters();
        o.candidates = candidates;
        o.evaluator.jobs = jobs;
        o.cross_validation = o.power_check = o.continuation = !before;
        if (verbose) o.progress = [](const std::string& l) { std::cout << "    " << l << "\n"; };
        Identification id(g.data, baseline, config, o);
        const IdentifyResult r = id.run();
        const double seconds =
            std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        Tally& t = tally[name];
        ++t.runs;
        const bool ok = correct(c, r);
        t.correct += ok;
        t.seconds += seconds;
        for (const std::string& n : r.named)
          if (std::find(c.hidden.begin(), c.hidden.end(), n) == c.hidden.end()) ++t.false_names;
        std::string named;
        for (const std::string& n : r.named) named += (named.empty() ? "" : "+") + n;
        if (r.verdict == Verdict::kNamedCause) t.gains.push_back(r.gain);
        std::printf(
            "%-26s seed %2d: %-5s %-28s named [%s] gain %5.1f %%  before RMS z %.2f  "
            "(%.0f s)\n",
            name.c_str(), seed, ok ? "OK" : "WRONG", verdictText(r.verdict).c_str(), named.c_str(),
            100.0 * r.gain, r.baseline_diagnosis.rms_z, seconds);
        if (!ok || verbose)
          std::printf("    truth: %s\n    %s\n", g.description.c_str(), r.summary.c_str());
        std::fflush(stdout);
      }
    }
    std::printf(
        "\n| case | runs | right | false names | median gain | mean time |\n"
        "|---|---|---|---|---|---|\n");
    for (const std::string& name : cases) {
      Tally& t = tally[name];
      std::sort(t.gains.begin(), t.gains.end());
      const std::string gain =
          t.gains.empty()
              ? "-"
              : std::to_string(static_cast<int>(std::lround(100.0 * t.gains[t.gains.size() / 2]))) +
                    " %";
      std::printf("| %s | %d | %d | %d | %s | %.0f s |\n", name.c_str(), t.runs, t.correct,
                  t.false_names, gain.c_str(), t.seconds / std::max(1, t.runs));
    }
    return 0;
  });
}
