// flagella_discovery_bench: the detection table. For each hidden-effect case and seed it
// generates a data set, hands the identification only the data and the baseline config, and
// prints whether the named cause is the hidden one and the held-out gain.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <iostream>
#include <map>

#include "flagella_identify/chi_square.h"
#include "flagella_identify/diagnosis.h"
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

/// The command line's values.
struct BenchArgs {
  std::vector<std::string> cases, candidates;
  int first_seed = 1, seeds = 3, jobs = 2;
  std::string config = FLAGELLA_CONFIG_DIR "/identification/granular_design1_coarse.yaml";
  bool verbose = false, before = false, signature_only = false, sequential_fits = false;
};

/// A case's hidden signature in words, and whether the data could show the effect to this tool.
struct SignatureText {
  std::string text = "no hidden candidate";
  /// what the baseline leaves in training is under chi^2_1(p = 1e-3): no fit can establish it
  bool under_bar = false;
  /// the noise test that gates every candidate fit would not fire at the held-out part's
  /// expected chi^2 (noise N plus what the hidden effects leave)
  bool under_gate = false;
  bool invisible() const { return under_bar || under_gate; }
};

SignatureText describe(const HiddenSignature& s) {
  SignatureText out;
  if (!s.defined) return out;
  const double expected_noise_z =
      noiseZScore(s.held_out_count + s.held_out_unabsorbed, s.held_out_count);
  out.under_bar = s.train_unabsorbed < chiSquareCritical(1);
  out.under_gate = expected_noise_z < kSignificanceZ;
  char line[320];
  std::snprintf(line, sizeof line,
                "hidden signature: training chi^2 %.3g over %d (%.3g left by the baseline "
                "parameters), held-out %.3g over %d (%.3g left; expected noise test z %.2f, "
                "significant above %.1f)",
                s.train_chi_square, s.train_count, s.train_unabsorbed, s.held_out_chi_square,
                s.held_out_count, s.held_out_unabsorbed, expected_noise_z, kSignificanceZ);
  out.text = line;
  return out;
}

/// Declares the command-line options, bound to `a`.
void addOptions(CLI::App& app, BenchArgs& a) {
  app.add_option("--cases", a.cases,
                 "cases (default: every case that applies to the robot of --config)")
      ->delimiter(',');
  app.add_option("--first-seed", a.first_seed)->capture_default_str();
  app.add_option("--seeds", a.seeds, "seeds per case")->capture_default_str();
  app.add_option("--jobs", a.jobs)->capture_default_str();
  app.add_option("--config", a.config)->capture_default_str();
  app.add_option("--candidates", a.candidates, "candidate effects (default: the standard list)")
      ->delimiter(',');
  app.add_flag("--verbose", a.verbose, "progress of every identification");
  app.add_flag("--signature-only", a.signature_only,
               "only how far each case's hidden effects move the truth's predictions of its data "
               "(training and held-out chi^2 against the truth without them), no identification");
  app.add_flag("--sequential-fits", a.sequential_fits,
               "fit the candidates one at a time (default with --jobs 2 or more: two at a time, "
               "same fits and verdicts)");
  app.add_flag("--without-small-data-methods", a.before,
               "without cross validation, power check and continuation fits (the pipeline "
               "before them, for a before/after table)");
}

/// One case's runs so far.
struct Tally {
  int runs = 0, correct = 0, false_names = 0;
  /// runs whose hidden signature is under the bar in training or under the noise test's gate
  int invisible = 0;
  double seconds = 0.0;
  std::vector<double> gains;
  std::vector<std::string> outcomes;
};

/// Generates and identifies case `c` with one seed, prints its line and adds it to its tally.
void runSeed(const BenchArgs& a, const DiscoveryCase& c, const std::string& name, int seed,
             const YAML::Node& baseline, std::map<std::string, Tally>& tally) {
  const auto start = std::chrono::steady_clock::now();
  EvaluatorOptions eo;
  eo.jobs = a.jobs;
  GeneratedCase g = generateCase(c, baseline, a.config, seed, eo);
  Tally& t = tally[name];
  if (a.signature_only) {
    const SignatureText s = describe(hiddenSignature(c, g, baseline, a.config, eo));
    ++t.runs;
    t.invisible += s.invisible();
    std::printf("%-26s seed %2d: %s%s\n", name.c_str(), seed, s.text.c_str(),
                s.under_bar    ? " (under the bar in training)"
                : s.under_gate ? " (under the noise test's gate in held-out)"
                               : "");
    std::fflush(stdout);
    return;
  }
  IdentifyOptions o;
  o.free = caseFreeParameters(baseline);
  o.candidates = a.candidates;
  o.evaluator.jobs = a.jobs;
  o.concurrent_fits = !a.sequential_fits;
  o.cross_validation = o.power_check = o.continuation = !a.before;
  if (a.verbose) o.progress = [](const std::string& l) { std::cout << "    " << l << "\n"; };
  Identification id(g.data, baseline, a.config, o);
  const IdentifyResult r = id.run();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  // after the timed part: the case's time is its generation and identification
  const SignatureText signature = describe(hiddenSignature(c, g, baseline, a.config, eo));
  ++t.runs;
  const bool ok = correct(c, r);
  t.correct += ok;
  t.invisible += signature.invisible();
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
  if (!ok || a.verbose)
    std::printf("    truth: %s\n    %s\n    %s\n", g.description.c_str(), signature.text.c_str(),
                r.summary.c_str());
  std::fflush(stdout);
}

/// Prints the detection table (markdown), one row per case.
void printTable(const std::vector<std::string>& cases, std::map<std::string, Tally>& tally) {
  std::printf(
      "\n| case | runs | right | false names | median gain | mean time | hidden effect under the "
      "bar in training or the noise gate |\n"
      "|---|---|---|---|---|---|---|\n");
  for (const std::string& name : cases) {
    Tally& t = tally[name];
    std::sort(t.gains.begin(), t.gains.end());
    const std::string gain =
        t.gains.empty()
            ? "-"
            : std::to_string(static_cast<int>(std::lround(100.0 * t.gains[t.gains.size() / 2]))) +
                  " %";
    std::printf("| %s | %d | %d | %d | %s | %.0f s | %d |\n", name.c_str(), t.runs, t.correct,
                t.false_names, gain.c_str(), t.seconds / std::max(1, t.runs), t.invisible);
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"flagella_discovery_bench: detection table of the model-discovery tool"};
  BenchArgs a;
  addOptions(app, a);
  if (const auto exit_code = flagella::cli::parseArguments(app, argc, argv)) return *exit_code;
  return flagella::cli::runGuarded([&] {
    const YAML::Node baseline = loadConfigTree(a.config, {});
    if (a.cases.empty())  // every case that applies to this robot
      for (const DiscoveryCase& c : discoveryCases()) {
        const std::string reason = caseNotApplicableReason(c, baseline);
        if (reason.empty())
          a.cases.push_back(c.name);
        else
          std::printf("case %s left out: %s\n", c.name.c_str(), reason.c_str());
      }
    std::map<std::string, Tally> tally;
    for (const std::string& name : a.cases) {
      const DiscoveryCase& c = discoveryCaseByName(name);
      for (int seed = a.first_seed; seed < a.first_seed + a.seeds; ++seed)
        runSeed(a, c, name, seed, baseline, tally);
    }
    printTable(a.cases, tally);
    return 0;
  });
}
