// Discovery on the helical robot (config/identification/helical_shore32_coarse.yaml on edges of
// 30 mm, support/helical_test_baseline.h), the fast cases of the bench's helical table cases: a
// hook softer than the filament hidden in a table of speed, head rate and the flagellum's tilt
// below the buckling threshold, the head's drag factors also off by 10 %. The tool gets only the
// data and the baseline config; it must name the hook over the DC motor, and skip the candidates
// that cannot act on a single-flagellum swimmer in a liquid, saying why; on the same table with
// nothing hidden it must name nothing. The full cases (20-90 rpm; null, DC motor, viscosity drift
// and hook included) run in flagella_discovery_bench. A DC motor hidden in the speed and head rate
// was this test's case until the hook's (named, gain 91 %, 182 s); the bench names it (gain 90.1
// %). Tried on 2026-12-07 as a third case here (the weak end of its stall torque, the hook its
// competitor): named, gain 89 %, but 165 s alone on one core, too long for the suite.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>
#include <map>

#include "flagella_identify/candidates.h"
#include "flagella_identify/dataset_generator.h"
#include "flagella_identify/discovery_cases.h"
#include "flagella_identify/identify.h"
#include "flagella_identify/model.h"
#include "support/helical_identify.h"

namespace flagella {
namespace identify {
namespace {

using testing::fastHelicalBaseline;
using testing::helicalTruth;
using testing::identifyHelical;

// On the suite's 30 mm edges (support/helical_test_baseline.h) the soft hook also shows in the
// tail's rate (the baseline over-predicts omega_t by 1.2 rpm, more so at higher rates), the DC
// motor's own signature, besides the tilt (2.1 deg): the DC motor's fit removes none of it
// (training chi^2 1011 before and after), the hook's leaves the noise (held-out RMS z 5.74 ->
// 0.87). On the config's 15 mm edges only the tilt shows (0.7 deg); the bench runs that case.

/// 12 rates of 40-95 rpm (below the threshold; the head turns in 2.3 s or less at 40 rpm, so a
/// 5 s window spans two turns), the bench's noise. Tried and not kept: 10 rates of 50-95 rpm
/// with a 2 s settle and a 3 s window: the DC motor's and the hook's identifications had not
/// ended after 7.7 min of CPU each (3-4 min with this plan; both on the config's 15 mm edges).
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

/// The baseline with C_t 10 % low and C_r 10 % high, and `hidden` (if any) at `strength`.
Model truthWith(const YAML::Node& baseline, const std::string& hidden = "", double strength = 0.0) {
  return helicalTruth(baseline, 0.9, 1.1, hidden, strength);
}

/// Identifies a table of `truth` (the fast plan, with the tilt) against the baseline.
IdentifyResult identifyTable(const YAML::Node& baseline, const Model& truth, int seed,
                             const std::vector<std::string>& candidates, bool power_check = true) {
  TablePlan plan = fastPlan();
  plan.tilt_noise = 0.2 * M_PI / 180.0;  // the bench's single-flagellum plan
  MeasuredData data;
  data.tables.push_back(generateTable(truth, plan, seed));
  return identifyHelical(data, baseline, candidates, power_check);
}

// A hook softer than the filament (the weak end of its realistic range, 0.3-0.5) hidden in a
// table that also measures the flagellum's tilt (docs/model.md 7.6, 8.4.4). It must be named over
// the DC motor, whose signature (a tail rate short of the command, more so under load) the data
// show too, but which cannot move the tilt.
TEST(DiscoveryHelical, SoftHookNamedOverTheDcMotor) {
  const YAML::Node baseline = fastHelicalBaseline();
  ASSERT_EQ(caseFreeParameters(baseline),
            (std::vector<std::string>{"effects.stokes_head.C_t", "effects.stokes_head.C_r"}));
  const IdentifyResult r = identifyTable(baseline, truthWith(baseline, "hook_stiffness", 0.5), 5,
                                         {"hook_stiffness", "dc_motor", "granular_yield",
                                          "granular_jamming", "fabrication_asymmetry"});
  EXPECT_EQ(r.verdict, Verdict::kNamedCause) << r.summary;
  EXPECT_EQ(r.named, std::vector<std::string>{"hook_stiffness"}) << r.summary;
  EXPECT_GE(r.gain, 0.5) << r.summary;
  std::map<std::string, std::string> notes;
  for (const ModelOutcome& m : r.candidates) notes[m.label] = m.fitted ? "" : m.note;
  EXPECT_EQ(notes.at("hook_stiffness"), "");
  EXPECT_EQ(notes.at("dc_motor"), "");
  for (const std::string name : {"granular_yield", "granular_jamming", "fabrication_asymmetry"})
    EXPECT_EQ(notes.at(name).rfind("does not apply to this robot: ", 0), 0u)
        << name << ": " << notes.at(name);
}

// The same table with nothing hidden (the bench's null_table): the drag factors alone, fitted,
// must explain it, and no effect may be named. Without the power check (60 s of the test's 90 on
// one core; the bench's null_table runs it), so "no significant discrepancy" is the one verdict.
TEST(DiscoveryHelical, NothingNamedOnATableWithNothingHidden) {
  const YAML::Node baseline = fastHelicalBaseline();
  const IdentifyResult r =
      identifyTable(baseline, truthWith(baseline), 6, {"hook_stiffness", "dc_motor"}, false);
  EXPECT_EQ(r.verdict, Verdict::kNoDiscrepancy) << r.summary;
  EXPECT_TRUE(r.named.empty()) << r.summary;
  EXPECT_LT(r.baseline_diagnosis.noise_z, kSignificanceZ) << r.summary;
}

}  // namespace
}  // namespace identify
}  // namespace flagella
