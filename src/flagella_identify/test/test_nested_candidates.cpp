// Nested candidate fits start at the simpler model's optimum with the new effect off, so they can
// only improve its training cost: every candidate's "off" values lie in its fit range, leave the
// effect out of the config there (the nested model is the baseline exactly), and next to them,
// with the effect switched on at its weakest, give the baseline's predictions (the baseline
// model has no code of the effect at all: the step at "off" is negligible), on a null table and
// a null time series of the design-1 robot (of the helical robot for the candidates that act only
// there). That the fits then never end above the baseline is
// asserted on every case the discovery tests run (support/discovery_check.h).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <vector>

#include "flagella_identify/calibration.h"
#include "flagella_identify/candidates.h"
#include "flagella_identify/discovery_cases.h"
#include "flagella_identify/evaluation.h"
#include "flagella_identify/model.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace flagella::identify {
namespace {

const std::string kBaseline = FLAGELLA_CONFIG_DIR "/identification/granular_design1_coarse.yaml";
const std::string kHelicalBaseline =
    FLAGELLA_CONFIG_DIR "/identification/helical_shore32_coarse.yaml";

TEST(NestedCandidates, OffValuesLieInTheFitRange) {
  for (const Candidate& c : standardCandidates()) {
    ASSERT_EQ(c.off.size(), c.variables.size()) << c.name;
    for (size_t i = 0; i < c.off.size(); ++i) {
      EXPECT_GE(c.off[i], c.variables[i].lower) << c.variables[i].name;
      EXPECT_LE(c.off[i], c.variables[i].upper) << c.variables[i].name;
    }
  }
}

TEST(NestedCandidates, EveryCandidateOffGivesTheBaselinePredictions) {
  EvaluatorOptions options;
  options.jobs = 1;
  std::set<std::string> checked;
  // each candidate on the first of these robots it can act on (candidates.h): design 1, else the
  // helical swimmer (the hook's stiffness and the head's tilt drag)
  std::vector<const Candidate*> left;
  for (const Candidate& c : standardCandidates()) left.push_back(&c);
  for (const std::string& path : {kBaseline, kHelicalBaseline}) {
    const YAML::Node baseline = loadConfigTree(path);
    std::vector<const Candidate*> here, elsewhere;
    for (const Candidate* c : left) {
      // tail_weight is not tried on design 1 (no Stokeslets), yet it acts on its tails
      const bool acts = notApplicableReason(*c, baseline).empty() ||
                        (path == kBaseline && c->name == "tail_weight");
      (acts ? here : elsewhere).push_back(c);
    }
    left = elsewhere;
    for (const char* name : {"null_table", "null_series"}) {
      // design 1: every candidate on both kinds of data; the helical robot, where a table
      // costs 12 runs, only on the kind of data each candidate is fitted to
      const bool table = std::string(name) == "null_table";
      std::vector<const Candidate*> run;
      for (const Candidate* c : here)
        if (path == kBaseline || c->steady_table_data == table) run.push_back(c);
      if (run.empty()) continue;
      const GeneratedCase generated =
          generateCase(discoveryCaseByName(name), baseline, path, 21, options);
      const Evaluator evaluator(generated.data, trainingOnlySplit(generated.data), options);
      const Model base(baseline, path, caseFreeParameters(baseline));
      const Evaluation reference = evaluator.evaluate(base, base.values(), Part::kAll);
      ASSERT_TRUE(reference.ok) << reference.failure;
      const double reference_chi_square = chiSquare(reference);
      for (const Candidate* c : run) {
        Model nested(baseline, path, caseFreeParameters(baseline));
        nested.addCandidate(*c);
        std::vector<double> values = base.values();
        values.insert(values.end(), c->off.begin(), c->off.end());
        // At the off values the config is the baseline's, to the letter.
        nested.setValues(values);
        EXPECT_EQ(YAML::Dump(nested.extendedConfig()), YAML::Dump(base.extendedConfig()))
            << c->name;
        // Next to them (inside the range) the effect is on, at its weakest.
        for (size_t i = 0; i < c->off.size(); ++i) {
          double& v = values[base.values().size() + i];
          v = c->off[i] == c->variables[i].upper ? v * (1.0 - 1e-6) - 1e-12
                                                 : v * (1.0 + 1e-6) + 1e-12;
        }
        const Evaluation e = evaluator.evaluate(nested, values, Part::kAll);
        ASSERT_TRUE(e.ok) << c->name << ": " << e.failure;
        ASSERT_EQ(e.points.size(), reference.points.size()) << c->name;
        // Residuals agree point by point to well inside one noise sigma; chi^2 to 0.1 %.
        double largest = 0.0;
        for (size_t k = 0; k < e.points.size(); ++k)
          largest = std::max(largest, std::abs(e.points[k].z() - reference.points[k].z()));
        EXPECT_LT(largest, 0.05) << name << ", " << c->name;
        EXPECT_NEAR(chiSquare(e), reference_chi_square, 1e-3 * reference_chi_square + 1e-6)
            << name << ", " << c->name;
        checked.insert(c->name);
      }
    }
  }
  for (const Candidate* c : left) ADD_FAILURE() << c->name << " acts on neither robot";
  EXPECT_EQ(checked.size(), standardCandidates().size());
}

}  // namespace
}  // namespace flagella::identify
