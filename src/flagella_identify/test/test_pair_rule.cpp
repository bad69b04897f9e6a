// The pair rule (docs/model.md 7.6): a pair is named only when neither of its effects, fitted
// again alone (from the pair's optimum with the other effect off, and from its own first fit),
// comes within the selection's bar of it. A single effect's fit stopped short of its optimum (an
// iteration cap) leaves a residual that a second effect absorbs: without the rule that pair is
// named, with it the hidden effect alone is.
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "flagella_identify/report.h"
#include "support/discovery_check.h"

namespace flagella {
namespace identify {
namespace testing {
namespace {

/// One line per fit: label, held-out chi^2, iterations, convergence, largest gradient.
void printFits(const std::string& title, const std::vector<ModelOutcome>& fits) {
  for (const ModelOutcome& m : fits)
    std::cout << "  " << title << " " << m.label << ": "
              << (m.fitted ? "held-out chi^2 " + std::to_string(m.held_out_chi_square) +
                                 ", training chi^2 " + std::to_string(m.train_chi_square) + ", " +
                                 std::to_string(m.iterations) + " iterations, " +
                                 (m.converged ? "converged" : "not converged") + ", max gradient " +
                                 std::to_string(m.gradient_max_norm)
                           : "not fitted: " + m.note)
              << std::endl;
}

/// The identification and its report (report.json parsed, report.md as text).
struct CappedRun {
  IdentifyResult result;
  nlohmann::json report;
  std::string markdown;
};

CappedRun runCapped(const std::string& name, int seed, int cap, bool pair_rule,
                    const std::vector<std::string>& candidates) {
  const auto start = std::chrono::steady_clock::now();
  const YAML::Node baseline = loadConfigTree(baselinePath(), {});
  const GeneratedCase generated =
      generateCase(discoveryCaseByName(name), baseline, baselinePath(), seed);
  IdentifyOptions options;
  options.free = caseFreeParameters();
  options.evaluator.jobs = 1;
  options.single_fit_max_iterations = cap;
  options.pair_rule = pair_rule;
  options.candidates = candidates;
  Identification identification(generated.data, baseline, baselinePath(), options);
  CappedRun run{identification.run(), {}, {}};
  const IdentifyResult& result = run.result;
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::cout << generated.description << " (single fits capped at " << cap << ", pair rule "
            << (pair_rule ? "on" : "off") << ", " << seconds << " s)\n  -> "
            << verdictText(result.verdict) << ": " << result.summary << std::endl;
  printFits("single", result.candidates);
  printFits("pair", result.combinations);
  printFits("refit", result.pair_refits);
  const std::string directory =
      (std::filesystem::temp_directory_path() / ("test_pair_rule_" + std::to_string(::getpid())))
          .string();
  const std::vector<std::string> files =
      writeReport(identification, result, {{"<generated>"}, baselinePath(), "test"}, directory);
  std::ifstream json_file(files[1]);
  run.report = nlohmann::json::parse(json_file);
  std::ostringstream markdown;
  markdown << std::ifstream(files[0]).rdbuf();
  run.markdown = markdown.str();
  std::filesystem::remove_all(directory);
  return run;
}

TEST(PairRule, ASingleFitStoppedShortDoesNotMakeAPair) {
  // A hidden DC motor; every single fit capped at one iteration. Two candidates keep it fast
  // (viscosity_drift fits in a few seconds; with the standard list, granular_yield's refits take
  // 80 s and the verdict without the rule is "cannot tell between dc_motor + granular_yield and
  // dc_motor + viscosity_drift").
  const std::string name = "dc_motor";
  const std::vector<std::string> candidates = {"dc_motor", "viscosity_drift"};
  const std::vector<std::string>& hidden = discoveryCaseByName(name).hidden;
  const CappedRun run_without = runCapped(name, 2, 1, false, candidates);
  const CappedRun run_with = runCapped(name, 2, 1, true, candidates);
  const IdentifyResult& without = run_without.result;
  const IdentifyResult& with = run_with.result;
  // Without the rule the capped single fit leaves a residual the second effect absorbs: the
  // pair is named, not the hidden effect.
  ASSERT_TRUE(without.chosen.has_value()) << without.summary;
  EXPECT_EQ(without.chosen->effects.size(), 2u) << without.summary;
  EXPECT_EQ(without.verdict, Verdict::kNamedCause) << without.summary;
  EXPECT_NE(without.named, hidden) << without.summary;
  // With it the hidden effect alone is named, on a fit that met its convergence test.
  EXPECT_EQ(with.verdict, Verdict::kNamedCause) << with.summary;
  EXPECT_EQ(with.named, hidden) << with.summary;
  ASSERT_TRUE(with.chosen.has_value()) << with.summary;
  EXPECT_TRUE(with.chosen->converged) << with.summary;
  EXPECT_NE(with.pair_check.find("not named"), std::string::npos) << with.pair_check;
  EXPECT_NE(with.summary.find("Pair check"), std::string::npos) << with.summary;
  // Both effects of the pair were fitted again alone, each from two starts.
  ASSERT_EQ(with.pair_refits.size(), 2u);
  for (const ModelOutcome& refit : with.pair_refits) EXPECT_EQ(refit.starts.size(), 2u);
  // The report says so, and how every fit ended.
  const nlohmann::json& report = run_with.report;
  EXPECT_EQ(report["pair_check"], with.pair_check);
  ASSERT_EQ(report["pair_refits"].size(), 2u);
  for (const char* list : {"candidates", "combinations", "pair_refits"})
    for (const nlohmann::json& fit : report[list]) {
      EXPECT_TRUE(fit["fit_iterations"].is_number_integer()) << fit.dump();
      EXPECT_TRUE(fit["fit_converged"].is_boolean()) << fit.dump();
      EXPECT_FALSE(fit["fit_starts"].empty()) << fit.dump();
    }
  EXPECT_NE(run_with.markdown.find("Pair check"), std::string::npos);
  EXPECT_NE(run_with.markdown.find("(refit alone, pair rule)"), std::string::npos);
}

TEST(PairRule, SingleFitCapOutsideItsRangeIsRefusedNamingTheField) {
  const YAML::Node baseline = loadConfigTree(baselinePath(), {});
  SteadyStateTable table;
  table.source = "<test>";
  table.noise["v"] = 1e-5;
  for (double omega : {5.0, 10.0, 15.0}) {
    SteadyStateRow row;
    row.omega_T = omega;
    row.measured["v"] = 0.0;
    table.rows.push_back(row);
  }
  MeasuredData data;
  data.tables.push_back(table);
  IdentifyOptions options;
  options.free = caseFreeParameters();
  for (int cap : {-1, options.fit.max_iterations + 1}) {
    options.single_fit_max_iterations = cap;
    try {
      Identification identification(data, baseline, baselinePath(), options);
      ADD_FAILURE() << "single_fit_max_iterations = " << cap << " was accepted";
    } catch (const ConfigError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("single_fit_max_iterations"), std::string::npos) << what;
      EXPECT_NE(what.find("[1, " + std::to_string(options.fit.max_iterations) + "]"),
                std::string::npos)
          << what;
      EXPECT_NE(what.find("got " + std::to_string(cap)), std::string::npos) << what;
    }
  }
  for (int cap : {0, 1, options.fit.max_iterations}) {
    options.single_fit_max_iterations = cap;
    EXPECT_NO_THROW(Identification(data, baseline, baselinePath(), options)) << cap;
  }
}

}  // namespace
}  // namespace testing
}  // namespace identify
}  // namespace flagella
