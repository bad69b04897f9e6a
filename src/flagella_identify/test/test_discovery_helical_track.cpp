// Discovery on the helical robot's 3-D head track
// (config/identification/helical_shore32_coarse.yaml on 30 mm edges,
// support/helical_test_baseline.h), the fast cases of the bench's helical series cases: one effect
// hidden at the weak end of its single-flagellum range in a track at two motor rates below the
// threshold, the head's drag factors also off by 15 %. The tool gets only the data and the baseline
// config; it must name the hidden effect and not its competitor, which also bends the track: a head
// close to a free surface (interface_lateral_force) against the gravity couple of a centre-of-mass
// offset, and the other way round; a flagellum denser than the liquid (tail_weight) against the COM
// offset. On a track with nothing hidden it must name nothing; on one with an effect outside the
// candidate list (a motor-rate ripple) it must report an unexplained residual and name nothing. The
// full cases (40 s tracks, every candidate) run in flagella_discovery_bench.
#include <gtest/gtest.h>

#include <iostream>

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

/// 30 s of track: 15 s at 40 rpm, then 15 s at 80 rpm (below the threshold), video, IMU and
/// counted turns with the bench's noise.
SeriesPlan fastTrack() {
  SeriesPlan p;
  p.command_rpm = {{0.0, 40.0}, {15.0, 80.0}};
  p.duration = 30.0;
  p.sample_interval = 0.5;
  p.position_noise = 2e-4;
  p.orientation_noise = 0.01;
  p.turns_noise = 0.1;
  return p;
}

/// The baseline with its head's drag factors off by 15 % (C_t high, C_r low).
Model perturbedBaseline(const YAML::Node& baseline) { return helicalTruth(baseline, 1.15, 0.85); }

/// The two candidates that bend a head track sideways (the default competitors).
const std::vector<std::string> kSurfaceAndCom = {"interface_lateral_force", "com_offset"};

IdentifyResult identify(const TimeSeries& track, const YAML::Node& baseline,
                        const std::vector<std::string>& candidates = kSurfaceAndCom) {
  MeasuredData data;
  data.series.push_back(track);
  return identifyHelical(data, baseline, candidates);
}

/// The perturbed baseline with the candidate `name` hidden at the weak end of its realistic
/// strength on this robot.
Model withHiddenEffect(const YAML::Node& baseline, const std::string& name) {
  return helicalTruth(baseline, 1.15, 0.85, name,
                      typicalStrengths(candidateByName(name), baseline).at(0).low);
}

/// Identifies a track of the perturbed baseline with `hidden` at the weak end of its strength.
IdentifyResult identifyHidden(const std::string& hidden, int seed,
                              const std::vector<std::string>& candidates = kSurfaceAndCom) {
  const YAML::Node baseline = fastHelicalBaseline();
  const Model truth = withHiddenEffect(baseline, hidden);
  return identify(generateSeries(truth, fastTrack(), seed), baseline, candidates);
}

TEST(DiscoveryHelicalTrack, SurfaceForceNamedOnAHeadTrack) {
  const IdentifyResult r = identifyHidden("interface_lateral_force", 5);
  EXPECT_EQ(r.verdict, Verdict::kNamedCause) << r.summary;
  EXPECT_EQ(r.named, std::vector<std::string>{"interface_lateral_force"}) << r.summary;
  EXPECT_GE(r.gain, 0.5) << r.summary;
}

// The converse: a centre-of-mass offset hidden, the surface force the competitor.
TEST(DiscoveryHelicalTrack, ComOffsetNamedOnAHeadTrack) {
  const IdentifyResult r = identifyHidden("com_offset", 7);
  EXPECT_EQ(r.verdict, Verdict::kNamedCause) << r.summary;
  EXPECT_EQ(r.named, std::vector<std::string>{"com_offset"}) << r.summary;
  EXPECT_GE(r.gain, 0.5) << r.summary;
}

// A flagellum denser than the liquid (its weight, docs/model.md 7.6) hidden, the COM offset's
// gravity couple the competitor. At the weak end of its strength the baseline misses by little
// (held-out RMS z about 1.5), so the held-out gain cannot reach the other cases' 50 %: the test
// asks instead that the named model leaves only the noise (its noise test not significant).
TEST(DiscoveryHelicalTrack, TailWeightNamedOnAHeadTrack) {
  const IdentifyResult r = identifyHidden("tail_weight", 8, {"tail_weight", "com_offset"});
  EXPECT_EQ(r.verdict, Verdict::kNamedCause) << r.summary;
  EXPECT_EQ(r.named, std::vector<std::string>{"tail_weight"}) << r.summary;
  EXPECT_GT(r.baseline_diagnosis.noise_z, kSignificanceZ) << r.summary;
  EXPECT_LT(r.chosen_diagnosis.noise_z, kSignificanceZ) << r.summary;
}

// An effect outside the candidate list (the bench's unknown_ripple, at the weak end of its range):
// the motor's real rate ripples by 20 % with a 12 s period while the data record the steady
// command. The surface force and the COM offset bend the track but cannot make its speed and
// head rate pulse with the ripple, so the tool must report an unexplained residual and name
// neither.
TEST(DiscoveryHelicalTrack, RippleOutsideTheListLeavesAnUnexplainedResidual) {
  const YAML::Node baseline = fastHelicalBaseline();
  SeriesPlan plan = fastTrack();
  plan.ripple_fraction = 0.2;
  plan.ripple_period = 12.0;
  const IdentifyResult r = identify(generateSeries(perturbedBaseline(baseline), plan, 9), baseline);
  EXPECT_EQ(r.verdict, Verdict::kUnexplained) << r.summary;
  EXPECT_TRUE(r.named.empty()) << r.summary;
  EXPECT_GT(r.baseline_diagnosis.noise_z, kSignificanceZ) << r.summary;
}

TEST(DiscoveryHelicalTrack, NothingNamedOnATrackWithNothingHidden) {
  const YAML::Node baseline = fastHelicalBaseline();
  const IdentifyResult r =
      identify(generateSeries(perturbedBaseline(baseline), fastTrack(), 6), baseline);
  EXPECT_EQ(r.verdict, Verdict::kNoDiscrepancy) << r.summary;
  EXPECT_TRUE(r.named.empty()) << r.summary;
}

}  // namespace
}  // namespace identify
}  // namespace flagella
