// Runs the identification on a generated hidden-effect case, handing it only the data and the
// baseline config, and returns the result with the case's truth for the assertions.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <string>
#include <vector>

#include "flagella_identify/discovery_cases.h"
#include "flagella_identify/identify.h"
#include "flagella_identify/model.h"

namespace flagella {
namespace identify {
namespace testing {

inline std::string baselinePath() {
  return FLAGELLA_CONFIG_DIR "/identification/granular_design1_coarse.yaml";
}

struct CaseOutcome {
  GeneratedCase generated;
  IdentifyResult result;
};

inline CaseOutcome runCase(const std::string& name, int seed) {
  const YAML::Node baseline = loadConfigTree(baselinePath(), {});
  CaseOutcome out;
  out.generated = generateCase(discoveryCaseByName(name), baseline, baselinePath(), seed);
  IdentifyOptions options;
  options.free = caseFreeParameters();
  options.evaluator.jobs = 1;  // ctest runs the suites side by side
  // Only the data and the baseline config go in: the truth stays in `out.generated.truth`.
  Identification identification(out.generated.data, baseline, baselinePath(), options);
  out.result = identification.run();
  // Nested fits start at the baseline's optimum with the effect off and never end above their
  // start (fit.h), so no fitted candidate may end above the calibrated baseline.
  for (const ModelOutcome& m : out.result.candidates) {
    if (m.fitted) {
      EXPECT_LE(m.train_chi_square, out.result.baseline.train_chi_square * (1.0 + 1e-9))
          << m.label << " ended above the baseline it contains (" << name << ", seed " << seed
          << ")";
    }
  }
  std::cout << out.generated.description << "\n  -> " << verdictText(out.result.verdict) << ": "
            << out.result.summary << std::endl;
  return out;
}

inline std::vector<std::string> sorted(std::vector<std::string> v) {
  std::sort(v.begin(), v.end());
  return v;
}

/// The named causes are exactly the hidden ones and the held-out gain is at least 50 %.
inline void expectFound(const std::string& name, int seed) {
  const CaseOutcome o = runCase(name, seed);
  const DiscoveryCase& c = discoveryCaseByName(name);
  EXPECT_EQ(o.result.verdict, Verdict::kNamedCause) << o.result.summary;
  EXPECT_EQ(sorted(o.result.named), sorted(c.hidden)) << o.generated.description;
  EXPECT_GE(o.result.gain, 0.5) << o.result.summary;
}

}  // namespace testing
}  // namespace identify
}  // namespace flagella
