// The pieces of the identification against independent truth: chi-square quantiles, the
// split, signatures in residuals built by hand, candidates written into configs, and a
// calibration that recovers drawn truth values within its stated uncertainty.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <map>
#include <random>
#include <stdexcept>

#include "flagella_identify/calibration.h"
#include "flagella_identify/candidates.h"
#include "flagella_identify/diagnosis.h"
#include "flagella_identify/discovery_cases.h"
#include "flagella_identify/fit.h"
#include "flagella_identify/identify.h"
#include "flagella_identify/model.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/effects/effect_registry.h"
#include "support/discovery_check.h"

namespace flagella {
namespace identify {
namespace {

bool hasSignature(const Diagnosis& d, const std::string& kind, const std::string& output) {
  for (const Signature& s : d.signatures)
    if (s.kind == kind && s.output == output) return true;
  return false;
}

ResidualPoint tablePoint(const std::string& output, double omega_rpm, double data, double model,
                         double session_time = NAN) {
  ResidualPoint p;
  p.output = output;
  p.omega_T = units::rpmToRadPerSec(omega_rpm);
  p.data = data;
  p.model = model;
  p.sigma = 1.0;
  p.session_time = session_time;
  return p;
}

TEST(NoiseTest, MatchesChiSquareQuantiles) {
  // chi-square quantiles (tables): N = 100: median 99.334, p = 0.999: 149.449;
  // N = 1000: p = 0.999: 1143.917. One-sided normal z at 0.999 is 3.0902.
  EXPECT_NEAR(noiseZScore(99.334, 100), 0.0, 0.02);
  EXPECT_NEAR(noiseZScore(149.449, 100), 3.0902, 0.03);
  EXPECT_NEAR(noiseZScore(1143.917, 1000), 3.0902, 0.02);
}

TEST(NoiseTest, PureNoiseIsNotADiscrepancy) {
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n(0.0, 1.0);
  Evaluation e;
  for (int i = 0; i < 600; ++i)
    e.points.push_back(tablePoint("v", 40 + i % 7 * 30, n(rng), 0.0, i * 10.0));
  const Diagnosis d = diagnose(e, MeasuredData{});
  EXPECT_FALSE(d.significant) << d.noise_z;
  EXPECT_TRUE(d.signatures.empty());
}

TEST(Split, HeldOutRowsSpanTheSpeedRangeAndSeriesHoldOutTheirEnd) {
  MeasuredData data;
  SteadyStateTable t;
  for (double rpm : {90, 10, 50, 70, 30, 80, 20, 60, 40}) {
    SteadyStateRow r;
    r.omega_T = units::rpmToRadPerSec(rpm);
    t.rows.push_back(r);
  }
  data.tables.push_back(t);
  TimeSeries s;
  s.t = {2.0, 4.0, 6.0, 12.0};
  data.series.push_back(s);
  const Split split = makeSplit(data);
  std::vector<double> held;
  for (size_t i = 0; i < t.rows.size(); ++i)
    if (split.table_row_held_out[0][i]) held.push_back(units::radPerSecToRpm(t.rows[i].omega_T));
  std::sort(held.begin(), held.end());
  EXPECT_EQ(held, (std::vector<double>{20, 50, 80}));  // one per third of the speed range
  EXPECT_NEAR(split.series_split_time[0], 2.0 + 0.6 * 10.0, 1e-12);
}

TEST(Signatures, ThresholdWhereTheDataStandStill) {
  Evaluation e;
  for (int rep = 0; rep < 2; ++rep)
    for (double rpm = 20; rpm <= 200; rpm += 20) {
      const double model = rpm;  // the model moves at every speed
      const double data = rpm <= 60 ? 0.3 : rpm + (rep ? 0.5 : -0.5);
      e.points.push_back(tablePoint("v", rpm, data, model));
    }
  const Diagnosis d = diagnose(e, MeasuredData{});
  EXPECT_TRUE(d.significant);
  EXPECT_TRUE(hasSignature(d, "threshold", "v"));
  EXPECT_FALSE(hasSignature(d, "asymmetry", "v"));
}

TEST(Signatures, AsymmetryWithTheSignOfRotation) {
  Evaluation e;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int i = 0; i < 20; ++i) {
    e.points.push_back(tablePoint("omega_h", 50 + i, 10.0, 10.0 + 3.0 + n(rng)));
    e.points.push_back(tablePoint("omega_h", -50 - i, 10.0, 10.0 - 3.0 + n(rng)));
  }
  const Diagnosis d = diagnose(e, MeasuredData{});
  EXPECT_TRUE(hasSignature(d, "asymmetry", "omega_h"));
}

TEST(Signatures, DriftWithSessionTimeAtEqualSpeed) {
  Evaluation e;
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  std::uniform_real_distribution<double> when(0.0, 14400.0);
  for (int i = 0; i < 40; ++i) {
    const double t = when(rng);
    e.points.push_back(tablePoint("v", 40 + (i % 8) * 30, 0.0, 4.0 * t / 14400.0 + n(rng), t));
  }
  EXPECT_TRUE(hasSignature(diagnose(e, MeasuredData{}), "drift", "v"));
}

TEST(Signatures, OscillationPeriodInASeries) {
  Evaluation e;
  std::mt19937_64 rng(9);
  std::normal_distribution<double> n(0.0, 1.0);
  for (int i = 0; i < 240; ++i) {
    ResidualPoint p;
    p.output = "head_turns";
    p.from_series = true;
    p.row = i;
    p.run_time = 0.5 * i;
    p.data = 0.0;
    p.model = 5.0 * std::sin(2.0 * M_PI * p.run_time / 10.0) + n(rng);
    e.points.push_back(p);
  }
  const Diagnosis d = diagnose(e, MeasuredData{});
  ASSERT_TRUE(hasSignature(d, "oscillation", "head_turns"));
  for (const Signature& s : d.signatures) {
    if (s.kind == "oscillation") {
      EXPECT_NE(s.text.find("period of 10.0 s"), std::string::npos) << s.text;
    }
  }
}

TEST(Candidates, WrittenIntoTheConfigOfAnExperiment) {
  const YAML::Node baseline = loadConfigTree(testing::baselinePath(), {});
  Model model(baseline, "baseline", {"medium.viscosity"});
  model.addCandidate(candidateByName("granular_yield"));
  model.addCandidate(candidateByName("fabrication_asymmetry"));
  const SimulationConfig c = model.configFor({{"robot.n_tails", "3"}}, 0.0, {5.0, 4e-4, 0.8, 1.5});
  EXPECT_DOUBLE_EQ(c.medium.viscosity(), 5.0);
  bool yield = false;
  for (const EffectSpec& e : c.effects)
    if (e.name == "granular_yield")
      for (const auto& [name, value] : e.parameters)
        if (name == "yield_force") yield = value == 4e-4;
  EXPECT_TRUE(yield);
  EXPECT_EQ(c.robotGeometry<MultiTailGeometry>().tail_length_scale,
            (std::vector<double>{0.8, 1.0, 1.0}));
  EXPECT_EQ(c.robotGeometry<MultiTailGeometry>().tail_stiffness_scale,
            (std::vector<double>{1.5, 1.0, 1.0}));
}

TEST(Candidates, NotIdentifiableWithoutTheirObservables) {
  MeasuredData speed_only;
  SteadyStateTable t;
  SteadyStateRow r;
  r.measured["v"] = 1e-4;
  t.rows.push_back(r);
  speed_only.tables.push_back(t);
  const unsigned o = observablesOf(speed_only);
  EXPECT_NE(notIdentifiableReason(candidateByName("dc_motor"), o).find("rotation"),
            std::string::npos);
  EXPECT_EQ(notIdentifiableReason(candidateByName("granular_yield"), o), "");
  EXPECT_NE(notIdentifiableReason(candidateByName("viscosity_drift"), o).find("session"),
            std::string::npos);
}

// The candidate list is the registry's: every effect with DiscoveryHints, in order, with the
// descriptor's variables, ranges and starts, plus the one robot-field candidate; every candidate
// has a hidden-effect case in the data its descriptor asks for.
TEST(Candidates, AreTheRegistrysFittableEffects) {
  std::vector<std::string> expected;
  for (const EffectDescriptor* d : effectRegistry()) {
    if (!d->discovery) continue;
    expected.push_back(d->name);
    const Candidate& c = candidateByName(d->name);
    const DiscoveryHints& h = *d->discovery;
    EXPECT_EQ(c.needs, h.needs) << d->name;
    EXPECT_EQ(c.starts, h.starts) << d->name;
    ASSERT_EQ(c.variables.size(), h.variables.size()) << d->name;
    for (size_t i = 0; i < h.variables.size(); ++i) {
      EXPECT_EQ(c.variables[i].name, d->name + "." + h.variables[i].variable);
      EXPECT_EQ(c.variables[i].lower, h.variables[i].lower) << c.variables[i].name;
      EXPECT_EQ(c.variables[i].upper, h.variables[i].upper) << c.variables[i].name;
      EXPECT_EQ(c.variables[i].log_scale, h.variables[i].log_scale) << c.variables[i].name;
    }
    EXPECT_EQ(discoveryCaseByName(d->name).table, h.steady_table_data) << d->name;
  }
  // then the candidates that scale robot or effect fields of the baseline
  for (const char* name : {"fabrication_asymmetry", "hook_stiffness", "head_tilt_drag"})
    expected.push_back(name);
  std::vector<std::string> names;
  for (const Candidate& c : standardCandidates()) names.push_back(c.name);
  EXPECT_EQ(names, expected);
}

// A candidate writes its variables into the effect's parameters as the descriptor says (the
// reciprocal for dc_motor), and the session start time where the effect has one; the config
// it writes passes the one validated reader.
TEST(Candidates, WriteTheDescriptorsParameters) {
  const YAML::Node baseline = loadConfigTree(testing::baselinePath(), {});
  for (const Candidate& c : standardCandidates()) {
    const EffectDescriptor* d = findEffectDescriptor(c.name);
    if (!d) continue;  // fabrication_asymmetry: robot fields (tested above)
    YAML::Node tree = YAML::Clone(baseline);
    // A start point: the effect on (at its off values `apply` leaves it out, checked below).
    const std::vector<double> values = c.starts.front();
    c.apply(tree, values, 1234.0);
    const SimulationConfig config = parseSimulationConfig(tree, "<candidate " + c.name + ">");
    std::map<std::string, double> written;
    for (const EffectSpec& e : config.effects)
      if (e.name == c.name)
        for (const auto& [name, value] : e.parameters) written[name] = value;
    const DiscoveryHints& h = *d->discovery;
    for (size_t i = 0; i < h.variables.size(); ++i) {
      const FittableParameter& v = h.variables[i];
      ASSERT_TRUE(written.count(v.parameter)) << c.name << "." << v.parameter;
      EXPECT_DOUBLE_EQ(written[v.parameter], v.reciprocal ? 1.0 / values[i] : values[i]);
    }
    if (!h.session_time_parameter.empty()) {
      EXPECT_EQ(written[h.session_time_parameter], 1234.0) << c.name;
    }
    YAML::Node off_tree = YAML::Clone(baseline);
    c.apply(off_tree, c.off, 1234.0);
    EXPECT_EQ(YAML::Dump(off_tree), YAML::Dump(baseline)) << c.name << " at its off values";
  }
}

TEST(DiscoveryCases, TheTruthModelRunsTheDrawnValues) {
  // Every drawn effect strength must reach the truth model's config under its own name (the
  // strength ranges list granular_jamming's variables in another order than the candidate).
  const YAML::Node baseline = loadConfigTree(testing::baselinePath(), {});
  for (const char* name : {"granular_jamming", "com_offset", "granular_yield"}) {
    const GeneratedCase g =
        generateCase(discoveryCaseByName(name), baseline, testing::baselinePath(), 3);
    int checked = 0;
    for (const auto& [variable, value] : g.truth) {
      const std::string path =
          variable.find('.') != variable.rfind('.') || variable.rfind("medium.", 0) == 0
              ? variable
              : "effects." + variable;
      EXPECT_DOUBLE_EQ(configField(g.truth_config, path).as<double>(), value) << path;
      ++checked;
    }
    EXPECT_GE(checked, 4) << name;  // three baseline parameters and the effect's
  }
}

TEST(DiscoveryCases, HiddenSignatureIsQuadraticInASmallEffect) {
  // A weak viscosity drift changes every prediction in proportion to its rate (docs/model.md
  // 7.6: speeds scale as 1/mu(t)), so its signature in noise units, raw and what the baseline
  // parameters leave of it, grows with the square of the rate: x4 for twice the rate.
  const YAML::Node baseline = loadConfigTree(testing::baselinePath(), {});
  DiscoveryCase weak = discoveryCaseByName("viscosity_drift");
  DiscoveryCase twice = weak;
  weak.strength_scale = 0.05;
  twice.strength_scale = 0.1;
  const std::string source = testing::baselinePath();
  const HiddenSignature a =
      hiddenSignature(weak, generateCase(weak, baseline, source, 2), baseline, source);
  const HiddenSignature b =
      hiddenSignature(twice, generateCase(twice, baseline, source, 2), baseline, source);
  ASSERT_TRUE(a.defined && b.defined);
  EXPECT_EQ(a.train_count + a.held_out_count, 3 * 14);  // v, omega_h, omega_t of 14 rows
  EXPECT_GT(a.train_unabsorbed, 0.0);
  EXPECT_NEAR(b.train_chi_square / a.train_chi_square, 4.0, 0.2);
  EXPECT_NEAR(b.held_out_chi_square / a.held_out_chi_square, 4.0, 0.2);
  EXPECT_NEAR(b.train_unabsorbed / a.train_unabsorbed, 4.0, 0.2);
  // absorbing the baseline parameters can only lower the training part
  EXPECT_LE(a.train_unabsorbed, a.train_chi_square * (1.0 + 1e-9));
  // no hidden candidate: nothing to measure
  EXPECT_FALSE(hiddenSignature(discoveryCaseByName("null_table"),
                               generateCase(discoveryCaseByName("null_table"), baseline, source, 2),
                               baseline, source)
                   .defined);
}

TEST(DiscoveryCases, AYieldNoRowCanShowIsAbsorbedByTheBaseline) {
  // sparse_yield_3_fast_rows: 200-260 rpm, where the yield's constant resistance is
  // indistinguishable from a stiffer medium (docs/model.md 7.6). Its raw signature is large, but
  // the baseline's viscosity, C_t and C_r absorb it below the one-parameter bar (chi^2 10.8 at
  // p = 1e-3); the same yield in the full plan (40-250 rpm, 2 and 3 tails) is not absorbed.
  const YAML::Node baseline = loadConfigTree(testing::baselinePath(), {});
  const std::string source = testing::baselinePath();
  for (const char* name : {"sparse_yield_3_fast_rows", "granular_yield"}) {
    const DiscoveryCase& c = discoveryCaseByName(name);
    const HiddenSignature s =
        hiddenSignature(c, generateCase(c, baseline, source, 2), baseline, source);
    ASSERT_TRUE(s.defined) << name;
    EXPECT_GT(s.train_chi_square, 100.0) << name;
    if (std::string(name) == "granular_yield")
      EXPECT_GT(s.train_unabsorbed, 10.83) << name;
    else
      EXPECT_LT(s.train_unabsorbed, 10.83) << name;
  }
}

TEST(FitOptions, BadOptionsAreRefusedNamingTheField) {
  EXPECT_NO_THROW(validateFitOptions(FitOptions{}));
  // each field out of range, and the text its message must hold
  struct Bad {
    std::string field, message;
    std::function<void(FitOptions&)> spoil;
  };
  const std::vector<Bad> bad = {
      {"max_iterations", "got 0", [](FitOptions& o) { o.max_iterations = 0; }},
      {"function_tolerance", "got 0", [](FitOptions& o) { o.function_tolerance = 0.0; }},
      {"function_tolerance", "in (0, 1)",
       [](FitOptions& o) { o.function_tolerance = std::nan(""); }},
      {"max_line_search_trials", "must be >= 0 (0: no line search), got -1",
       [](FitOptions& o) { o.max_line_search_trials = -1; }},
      {"log_step", "got -0.001", [](FitOptions& o) { o.log_step = -1e-3; }},
      {"linear_step", "got 1", [](FitOptions& o) { o.linear_step = 1.0; }},
      {"bracket_step", "got 0", [](FitOptions& o) { o.bracket_step = 0.0; }},
      {"bracket_tolerance", "got -0.1", [](FitOptions& o) { o.bracket_tolerance = -0.1; }}};
  for (const Bad& b : bad) {
    FitOptions o;
    b.spoil(o);
    try {
      validateFitOptions(o);
      ADD_FAILURE() << b.field << " out of range was accepted";
    } catch (const std::invalid_argument& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("FitOptions::" + b.field), std::string::npos) << what;
      EXPECT_NE(what.find(b.message), std::string::npos) << what;
    }
  }
  // fitModel refuses them before any simulation
  const YAML::Node baseline = loadConfigTree(testing::baselinePath(), {});
  const GeneratedCase g =
      generateCase(discoveryCaseByName("null_table"), baseline, testing::baselinePath(), 21);
  const Evaluator evaluator(g.data, makeSplit(g.data));
  Model model(baseline, testing::baselinePath(), caseFreeParameters());
  FitOptions o;
  o.max_line_search_trials = -2;
  EXPECT_THROW(fitModel(model, evaluator, o), std::invalid_argument);
}

TEST(Calibration, RecoversDrawnTruthWithinItsUncertainty) {
  const YAML::Node baseline = loadConfigTree(testing::baselinePath(), {});
  const GeneratedCase g =
      generateCase(discoveryCaseByName("null_table"), baseline, testing::baselinePath(), 21);
  const Evaluator evaluator(g.data, makeSplit(g.data));
  Model model(baseline, testing::baselinePath(), caseFreeParameters());
  const FitResult fit = fitModel(model, evaluator, FitOptions{});
  ASSERT_TRUE(fit.ok) << fit.message;
  for (size_t i = 0; i < model.parameters().size(); ++i) {
    const FitParameter& p = model.parameters()[i];
    const double truth = g.truth.at(p.name);
    ASSERT_TRUE(std::isfinite(p.uncertainty)) << p.name;
    EXPECT_GT(p.uncertainty, 0.0) << p.name;
    EXPECT_LT(std::abs(p.value - truth), 4.0 * p.uncertainty)
        << p.name << ": fitted " << p.value << " +- " << p.uncertainty << ", truth " << truth;
  }
  // the training residual is pure noise at the optimum
  EXPECT_LT(noiseZScore(fit.chi_square, fit.residual_count), kSignificanceZ);
}

}  // namespace
}  // namespace identify
}  // namespace flagella

namespace flagella::identify {
namespace {

TEST(Evaluation, ARowsOwnUncertaintyNormalisesItsResiduals) {
  // Two experiments alike but for the uncertainty: the second row's own sigma is 8x the table's
  // noise, so its residual in sigmas is the first's / 8 (the model is the same run).
  const std::string config = FLAGELLA_CONFIG_DIR "/identification/granular_design1_coarse.yaml";
  SteadyStateTable table;
  table.settle_time = 2.0;
  table.window = 2.0;
  table.noise["v"] = 1e-5;
  for (int i = 0; i < 2; ++i) {
    SteadyStateRow row;
    row.omega_T = units::rpmToRadPerSec(150.0);
    row.measured["v"] = 0.0;
    if (i == 1) row.sigma["v"] = 8e-5;
    table.rows.push_back(row);
  }
  MeasuredData data;
  data.tables.push_back(table);
  const Model model(loadConfigTree(config), config, {});
  const Evaluator evaluator(data, makeSplit(data, 1000), {});
  const Evaluation e = evaluator.evaluate(model, model.values(), Part::kAll);
  ASSERT_TRUE(e.ok) << e.failure;
  ASSERT_EQ(e.points.size(), 2u);
  EXPECT_DOUBLE_EQ(e.points[0].sigma, 1e-5);
  EXPECT_DOUBLE_EQ(e.points[1].sigma, 8e-5);
  ASSERT_GT(std::abs(e.points[0].z()), 1.0);  // the robot moves: a residual to compare
  EXPECT_NEAR(e.points[1].z(), e.points[0].z() / 8.0, 1e-12 * std::abs(e.points[0].z()));
}

/// A fitted, significant outcome of `effects` with held-out chi^2 `chi` and penalty `penalty`
/// that removes `explained` of the baseline's excess.
ModelOutcome outcome(std::vector<std::string> effects, double chi, double penalty,
                     double explained) {
  ModelOutcome m;
  m.effects = effects;
  for (const std::string& e : effects) m.label += (m.label.empty() ? "" : " + ") + e;
  m.fitted = true;
  m.significant = true;
  m.held_out_chi_square = chi;
  m.penalty = penalty;
  m.explained = explained;
  return m;
}

TEST(CannotTellBetween, ARivalIsWithinTheOneParameterCriticalValue) {
  // The chi-square critical value at p = 1e-3, one degree of freedom, is 10.828 (tables);
  // selection score = held-out chi^2 + penalty.
  IdentifyResult r;
  r.candidates = {outcome({"a"}, 100.0, 5.0, 0.97), outcome({"b"}, 110.7, 5.0, 0.95),
                  outcome({"c"}, 108.0, 8.0, 0.95), outcome({"d"}, 101.0, 5.0, 0.80)};
  ModelOutcome unfitted = outcome({"e"}, 100.5, 5.0, 0.99);
  unfitted.fitted = false;
  ModelOutcome insignificant = outcome({"f"}, 100.5, 5.0, 0.99);
  insignificant.significant = false;
  r.candidates.push_back(unfitted);
  r.candidates.push_back(insignificant);
  r.combinations = {outcome({"a", "d"}, 100.2, 10.0, 0.99)};
  const ModelOutcome chosen = r.candidates[0];
  // b: 10.7 above (a rival); c: 11.0 above (told apart); d explains too little; e, f and the
  // pair (more effects) are no rivals
  const ModelOutcome* rival = closestRival(r, chosen);
  ASSERT_NE(rival, nullptr);
  EXPECT_EQ(rival->label, "b");
  r.candidates[1].held_out_chi_square = 110.9;
  EXPECT_EQ(closestRival(r, chosen), nullptr);
  // the closer of two rivals
  r.candidates[1].held_out_chi_square = 102.0;  // score 107
  r.candidates[2].held_out_chi_square = 101.0;  // score 109
  ASSERT_NE(closestRival(r, chosen), nullptr);
  EXPECT_EQ(closestRival(r, chosen)->label, "b");
  // pairs are told from pairs
  r.combinations.push_back(outcome({"a", "b"}, 95.0, 10.0, 0.99));
  ASSERT_NE(closestRival(r, r.combinations[0]), nullptr);
  EXPECT_EQ(closestRival(r, r.combinations[0])->label, "a + b");
}

TEST(CannotTellBetween, SeparatingMeasurementsAreTheTwoModelsPredictions) {
  const std::string config = FLAGELLA_CONFIG_DIR "/identification/granular_design1_coarse.yaml";
  const YAML::Node baseline = loadConfigTree(config);
  SteadyStateTable table;
  table.settle_time = 3.0;
  table.window = 4.0;
  table.noise["v"] = 2e-5;
  for (double rpm : {120.0, 240.0}) {
    SteadyStateRow row;
    row.omega_T = units::rpmToRadPerSec(rpm);
    row.measured["v"] = 0.0;
    table.rows.push_back(row);
  }
  MeasuredData data;
  data.tables.push_back(table);
  Model with_yield(baseline, config, {}), with_motor(baseline, config, {});
  with_yield.addCandidate(candidateByName("granular_yield"));
  with_motor.addCandidate(candidateByName("dc_motor"));
  const std::vector<double> yield_values{6e-4}, motor_values{150.0};
  EvaluatorOptions options;
  options.jobs = 1;
  const std::vector<SuggestedMeasurement> s =
      separatingMeasurements({"granular_yield", &with_yield, yield_values},
                             {"dc_motor", &with_motor, motor_values}, data, options);
  ASSERT_FALSE(s.empty());
  EXPECT_LE(s.size(), static_cast<size_t>(kSuggestionsPerCandidate));
  for (size_t i = 0; i < s.size(); ++i) {
    EXPECT_EQ(s[i].reference, "granular_yield");
    EXPECT_EQ(s[i].candidate, "dc_motor");
    EXPECT_EQ(s[i].output, "v");
    EXPECT_DOUBLE_EQ(s[i].sigma, 2e-5);
    // on the grid: a quarter of the slowest row's rate to twice the fastest's
    const double rpm = s[i].omega_T * units::kRpmPerRadPerSec;
    EXPECT_GE(rpm, 30.0 * (1.0 - 1e-9));
    EXPECT_LE(rpm, 480.0 * (1.0 + 1e-9));
    EXPECT_GE(s[i].separation, kDecisiveSeparation);
    if (i > 0) {
      EXPECT_LE(s[i].separation, s[i - 1].separation);
    }
    // each prediction is that model's own steady speed at that rate, simulated alone
    SteadyStateTable one = table;
    one.rows.resize(1);
    one.rows[0].omega_T = s[i].omega_T;
    MeasuredData single;
    single.tables.push_back(one);
    const Evaluator evaluator(single, trainingOnlySplit(single), options);
    const Evaluation y = evaluator.evaluate(with_yield, yield_values, Part::kAll);
    const Evaluation m = evaluator.evaluate(with_motor, motor_values, Part::kAll);
    ASSERT_TRUE(y.ok && m.ok);
    EXPECT_NEAR(s[i].reference_value, y.points[0].model, 1e-9 + 1e-6 * std::abs(y.points[0].model));
    EXPECT_NEAR(s[i].candidate_value, m.points[0].model, 1e-9 + 1e-6 * std::abs(m.points[0].model));
    EXPECT_NEAR(s[i].separation, std::abs(m.points[0].model - y.points[0].model) / 2e-5, 1e-6);
  }
  // a model cannot be told from itself
  EXPECT_TRUE(separatingMeasurements({"granular_yield", &with_yield, yield_values},
                                     {"same", &with_yield, yield_values}, data, options)
                  .empty());
}

TEST(CannotTellBetween, WithoutATableTheSeriesInstrumentsMeasureASteadyRun) {
  // A series only: 8 s at 120 rpm then 12 s at -240 rpm, positions tracked to 0.2 mm and turns
  // counted to 0.1 turn. The steady run is as long as the longest stretch (12 s; 3 s to settle,
  // a 9 s window): sigma_v = sqrt(2) 2e-4 / 9, sigma_omega = 2 pi sqrt(2) 0.1 / 9.
  const std::string config = FLAGELLA_CONFIG_DIR "/identification/granular_design1_coarse.yaml";
  const YAML::Node baseline = loadConfigTree(config);
  TimeSeries s;
  s.position_noise = 2e-4;
  s.turns_noise = 0.1;
  s.has_z = true;
  for (int k = 0; k <= 40; ++k) {
    s.t.push_back(0.5 * k);
    s.omega_cmd.push_back(units::rpmToRadPerSec(s.t.back() < 8.0 ? 120.0 : -240.0));
    s.position.push_back(Vec3::Zero());
    s.head_turns.push_back(0.0);
    s.tail_turns.push_back(0.0);
  }
  MeasuredData data;
  data.series.push_back(s);
  Model with_yield(baseline, config, {}), with_motor(baseline, config, {});
  with_yield.addCandidate(candidateByName("granular_yield"));
  with_motor.addCandidate(candidateByName("dc_motor"));
  EvaluatorOptions options;
  options.jobs = 1;
  const std::vector<SuggestedMeasurement> m = separatingMeasurements(
      {"granular_yield", &with_yield, {6e-4}}, {"dc_motor", &with_motor, {150.0}}, data, options);
  ASSERT_FALSE(m.empty());
  const std::map<std::string, double> sigma = {
      {"v", std::sqrt(2.0) * 2e-4 / 9.0},
      {"omega_h", 2.0 * M_PI * std::sqrt(2.0) * 0.1 / 9.0},
      {"omega_t", 2.0 * M_PI * std::sqrt(2.0) * 0.1 / 9.0}};
  for (const SuggestedMeasurement& x : m) {
    ASSERT_TRUE(sigma.count(x.output)) << x.output;
    EXPECT_NEAR(x.sigma, sigma.at(x.output), 1e-12 * sigma.at(x.output)) << x.output;
    // the series' range, a quarter of its slowest command to twice its fastest, the fastest's
    // sign
    const double rpm = x.omega_T * units::kRpmPerRadPerSec;
    EXPECT_LE(rpm, -30.0 * (1.0 - 1e-9));
    EXPECT_GE(rpm, -480.0 * (1.0 + 1e-9));
    EXPECT_GE(x.separation, kDecisiveSeparation);
  }
}

}  // namespace
}  // namespace flagella::identify
