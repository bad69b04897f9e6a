// What the helical discovery tests (test_discovery_helical, test_discovery_helical_track) share:
// a truth model of the suite's fast helix with the head's drag factors off and one effect hidden,
// and one identification of generated data against the baseline, printed as the bench prints it.
#pragma once

#include <gtest/gtest.h>

#include <iostream>
#include <string>
#include <vector>

#include "flagella_identify/candidates.h"
#include "flagella_identify/discovery_cases.h"
#include "flagella_identify/identify.h"
#include "flagella_identify/model.h"
#include "support/helical_test_baseline.h"

namespace flagella {
namespace identify {
namespace testing {

/// The baseline (its drag factors the free parameters) with C_t and C_r scaled by these factors,
/// and `hidden` (if any) added with its single realistic-strength variable at `strength`.
inline Model helicalTruth(const YAML::Node& baseline, double c_t_factor, double c_r_factor,
                          const std::string& hidden = "", double strength = 0.0) {
  Model truth(baseline, helicalBaselinePath(), caseFreeParameters(baseline));
  if (!hidden.empty()) truth.addCandidate(candidateByName(hidden));
  std::vector<double> values = truth.values();
  values[static_cast<size_t>(truth.indexOf("effects.stokes_head.C_t"))] *= c_t_factor;
  values[static_cast<size_t>(truth.indexOf("effects.stokes_head.C_r"))] *= c_r_factor;
  if (!hidden.empty()) {
    const std::vector<TypicalStrength>& typical =
        typicalStrengths(candidateByName(hidden), baseline);
    EXPECT_EQ(typical.size(), 1u) << hidden;
    values[static_cast<size_t>(truth.indexOf(typical.at(0).variable))] = strength;
  }
  truth.setValues(values);
  return truth;
}

/// Identifies `data` against the baseline, its drag factors free, on one core (ctest runs the
/// suites side by side); prints the verdict and summary.
inline IdentifyResult identifyHelical(const MeasuredData& data, const YAML::Node& baseline,
                                      const std::vector<std::string>& candidates,
                                      bool power_check = true) {
  IdentifyOptions options;
  options.free = caseFreeParameters(baseline);
  options.candidates = candidates;
  options.power_check = power_check;
  options.evaluator.jobs = 1;
  Identification identification(data, baseline, helicalBaselinePath(), options);
  const IdentifyResult r = identification.run();
  std::cout << verdictText(r.verdict) << ": " << r.summary << std::endl;
  return r;
}

}  // namespace testing
}  // namespace identify
}  // namespace flagella
