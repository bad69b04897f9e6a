// Candidate fits two at a time (docs/model.md 7.6, IdentifyOptions::concurrent_fits) are the
// same computation as one at a time: every fit of the singles, the pair and the pair rule's
// refits (two effects at once, each from two starts at once: fits inside fits) ends with the
// same parameters, chi^2, iterations and evaluations, the verdict is the same, and the progress
// reads line for line as in the sequential run (concurrent fits' lines would interleave if they
// were not held).
#include <mutex>

#include "support/discovery_check.h"

namespace flagella {
namespace identify {
namespace testing {
namespace {

struct LoggedRun {
  IdentifyResult result;
  std::vector<std::string> lines;  ///< every progress line, in the order printed
};

LoggedRun runWithJobs2(bool concurrent) {
  // A hidden DC motor, the single fits capped at one iteration so that the pair and the pair
  // rule's refits run too (test_pair_rule); two candidates keep it at 43 s, both ways.
  const std::string name = "dc_motor";
  const YAML::Node baseline = loadConfigTree(baselinePath(), {});
  const GeneratedCase generated =
      generateCase(discoveryCaseByName(name), baseline, baselinePath(), 2);
  LoggedRun run;
  std::mutex mutex;
  IdentifyOptions options;
  options.free = caseFreeParameters();
  options.candidates = {"dc_motor", "viscosity_drift"};
  options.single_fit_max_iterations = 1;
  options.evaluator.jobs = 2;
  options.concurrent_fits = concurrent;
  const auto log = [&](const std::string& line) {
    std::lock_guard<std::mutex> lock(mutex);
    run.lines.push_back(line);
  };
  options.progress = log;
  options.fit.progress = log;
  Identification identification(generated.data, baseline, baselinePath(), options);
  run.result = identification.run();
  return run;
}

void expectSameFits(const std::vector<ModelOutcome>& a, const std::vector<ModelOutcome>& b,
                    const std::string& list) {
  ASSERT_EQ(a.size(), b.size()) << list;
  for (size_t i = 0; i < a.size(); ++i) {
    SCOPED_TRACE(list + " " + a[i].label);
    EXPECT_EQ(a[i].label, b[i].label);
    EXPECT_EQ(a[i].fitted, b[i].fitted);
    EXPECT_EQ(a[i].skipped, b[i].skipped);
    EXPECT_EQ(a[i].train_chi_square, b[i].train_chi_square);
    EXPECT_EQ(a[i].held_out_chi_square, b[i].held_out_chi_square);
    EXPECT_EQ(a[i].iterations, b[i].iterations);
    EXPECT_EQ(a[i].evaluations, b[i].evaluations);
    ASSERT_EQ(a[i].parameters.size(), b[i].parameters.size());
    for (size_t p = 0; p < a[i].parameters.size(); ++p)
      EXPECT_EQ(a[i].parameters[p].value, b[i].parameters[p].value) << a[i].parameters[p].name;
  }
}

TEST(ConcurrentFits, SameFitsVerdictAndProgressAsOneAtATime) {
  const LoggedRun one = runWithJobs2(false);
  const LoggedRun two = runWithJobs2(true);
  // The concurrent path was taken (the two candidates' fits, the refits), the other not.
  EXPECT_EQ(one.result.fits_at_once, 1);
  EXPECT_EQ(two.result.fits_at_once, 2);
  EXPECT_EQ(two.result.verdict, one.result.verdict) << two.result.summary;
  EXPECT_EQ(two.result.named, one.result.named);
  EXPECT_EQ(two.result.summary, one.result.summary);
  EXPECT_EQ(two.result.total_evaluations, one.result.total_evaluations);
  expectSameFits(one.result.candidates, two.result.candidates, "single");
  expectSameFits(one.result.combinations, two.result.combinations, "pair");
  expectSameFits(one.result.pair_refits, two.result.pair_refits, "refit");
  ASSERT_EQ(two.result.pair_refits.size(), 2u) << two.result.pair_check;
  for (size_t i = 0; i < 2; ++i)
    EXPECT_EQ(two.result.pair_refits[i].starts, one.result.pair_refits[i].starts);
  EXPECT_EQ(two.result.pair_check, one.result.pair_check);
  EXPECT_EQ(two.lines, one.lines);
  std::cout << one.result.candidates.size() << " single fits, " << one.result.combinations.size()
            << " pairs, " << one.result.total_evaluations << " model evaluations; verdict "
            << verdictText(two.result.verdict) << std::endl;
}

}  // namespace
}  // namespace testing
}  // namespace identify
}  // namespace flagella
