// Discovery on the helical robot (config/identification/helical_shore32_coarse.yaml), the fast
// case of the bench's helical table cases: a DC motor that slows under load hidden in a speed and
// head-rate table below the buckling threshold, the head's drag factors also off by 10-20 %. The
// tool gets only the data and the baseline config; it must name the motor, and skip the
// candidates that cannot act on a single-flagellum swimmer in a liquid, saying why. The full
// cases (20-90 rpm, null and viscosity drift included) run in flagella_discovery_bench.
#include <gtest/gtest.h>

#include <iostream>
#include <map>

#include "flagella_identify/candidates.h"
#include "flagella_identify/dataset_generator.h"
#include "flagella_identify/discovery_cases.h"
#include "flagella_identify/identify.h"
#include "flagella_identify/model.h"

namespace flagella {
namespace identify {
namespace {

const std::string kBaseline = FLAGELLA_CONFIG_DIR "/identification/helical_shore32_coarse.yaml";

/// 12 rates of 40-95 rpm (below the threshold; the head turns in 2.3 s or less at 40 rpm, so a
/// 5 s window spans two turns), the bench's noise.
TablePlan fastPlan() {
  TablePlan p;
  for (int k = 0; k < 12; ++k) p.omega_rpm.push_back(40.0 + 5.0 * k);
  p.settle_time = 3.0;
  p.window = 5.0;
  p.session_hours = 4.0;
  p.v_noise = 3e-6;
  p.omega_noise = 0.05;
  return p;
}

TEST(DiscoveryHelical, DcMotorNamedOnASpeedAndHeadRateTable) {
  const YAML::Node baseline = loadConfigTree(kBaseline, {});
  const std::vector<std::string> free = caseFreeParameters(baseline);
  ASSERT_EQ(free, (std::vector<std::string>{"effects.stokes_head.C_t", "effects.stokes_head.C_r"}));
  Model truth(baseline, kBaseline, free);
  truth.addCandidate(candidateByName("dc_motor"));
  std::vector<double> values = truth.values();
  values[static_cast<size_t>(truth.indexOf("effects.stokes_head.C_t"))] *= 1.15;
  values[static_cast<size_t>(truth.indexOf("effects.stokes_head.C_r"))] *= 0.85;
  // 1 / stall torque [1/(N m)]: the weak end of the typical range (80-230)
  values[static_cast<size_t>(truth.indexOf("dc_motor.inverse_stall_torque"))] = 100.0;
  truth.setValues(values);
  MeasuredData data;
  data.tables.push_back(generateTable(truth, fastPlan(), 3));

  IdentifyOptions options;
  options.free = free;
  options.candidates = {"dc_motor", "granular_yield", "granular_jamming", "fabrication_asymmetry"};
  options.evaluator.jobs = 1;  // ctest runs the suites side by side
  Identification identification(data, baseline, kBaseline, options);
  const IdentifyResult r = identification.run();
  std::cout << verdictText(r.verdict) << ": " << r.summary << std::endl;

  EXPECT_EQ(r.verdict, Verdict::kNamedCause) << r.summary;
  EXPECT_EQ(r.named, std::vector<std::string>{"dc_motor"}) << r.summary;
  EXPECT_GE(r.gain, 0.5) << r.summary;
  std::map<std::string, std::string> notes;
  for (const ModelOutcome& m : r.candidates) notes[m.label] = m.fitted ? "" : m.note;
  EXPECT_EQ(notes.at("dc_motor"), "");
  for (const std::string name : {"granular_yield", "granular_jamming", "fabrication_asymmetry"})
    EXPECT_EQ(notes.at(name).rfind("does not apply to this robot: ", 0), 0u)
        << name << ": " << notes.at(name);
}

}  // namespace
}  // namespace identify
}  // namespace flagella
