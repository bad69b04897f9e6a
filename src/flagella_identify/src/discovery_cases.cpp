#include "flagella_identify/discovery_cases.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <random>
#include <sstream>
#include <stdexcept>

#include "flagella_identify/dataset_generator.h"
#include "flagella_identify/model.h"
#include "flagella_sim/core/units.h"

namespace flagella {
namespace identify {

namespace {

/// Realistic strength ranges for the baseline's robot (README "Model discovery"): low end
/// clearly above the noise of the plans below, high end still a plausible robot. An effect's
/// come from its descriptor (DiscoveryHints::typical, typical_single_flagellum).
std::vector<TypicalStrength> rangesOf(const Candidate& c, const YAML::Node& baseline,
                                      std::mt19937_64& rng) {
  if (c.name == "fabrication_asymmetry") {
    // one tail shorter, or one tail stiffer
    if (std::uniform_int_distribution<int>(0, 1)(rng) == 0)
      return {{"fabrication_asymmetry.length_ratio", 0.7, 0.85, false},
              {"fabrication_asymmetry.stiffness_ratio", 1.0, 1.0, false}};
    return {{"fabrication_asymmetry.length_ratio", 1.0, 1.0, false},
            {"fabrication_asymmetry.stiffness_ratio", 1.8, 3.0, false}};
  }
  const std::vector<TypicalStrength>& typical = typicalStrengths(c, baseline);
  if (typical.empty())
    throw std::invalid_argument("no typical strength for effect '" + c.name + "'");
  return typical;
}

/// The truth's model of case `c`: the baseline (at the case's tail count) with its hidden effects.
Model truthModel(const DiscoveryCase& c, const YAML::Node& baseline, const std::string& source) {
  YAML::Node robot = YAML::Clone(baseline);
  if (c.tails > 0) robot["robot"]["n_tails"] = c.tails;
  Model truth(robot, source, caseFreeParameters(baseline));
  for (const std::string& effect : c.hidden) truth.addCandidate(candidateByName(effect));
  return truth;
}

double logUniform(std::mt19937_64& rng, double low, double high) {
  return std::exp(std::uniform_real_distribution<double>(std::log(low), std::log(high))(rng));
}

TablePlan tailedRobotTablePlan() {
  TablePlan p;
  p.omega_rpm = {40, 70, 100, 130, 160, 200, 250};
  p.n_tails = {2, 3};
  p.settle_time = 5.0;
  p.window = 10.0;
  p.session_hours = 4.0;
  p.v_noise = 3e-6;      // 0.003 mm/s: video tracking over the window
  p.omega_noise = 0.05;  // 0.48 rpm: counted turns over a minute-long trial
  return p;
}

/// A single-flagellum swimmer (config/identification/helical_shore32_coarse.yaml): one robot,
/// 12 motor rates below its buckling threshold (over 100 rpm; above it the flagellum whirls and
/// a steady speed is no longer a property of the robot). Steady within 5 s; the window spans two
/// or more turns of the head (its speed wobbles once per turn: 4.6 s at 20 rpm).
TablePlan singleFlagellumTablePlan() {
  TablePlan p;
  p.omega_rpm = {20, 25, 30, 35, 40, 45, 50, 55, 60, 70, 80, 90};
  p.n_tails = {};  // the baseline's robot
  p.settle_time = 5.0;
  p.window = 10.0;
  p.session_hours = 4.0;
  p.v_noise = 3e-6;      // 0.003 mm/s: video tracking over the window
  p.omega_noise = 0.05;  // 0.48 rpm: counted head turns
  // the flagellum's axis fitted to its video outline, averaged over the window (docs/model.md
  // 8.4.4, 7.6)
  p.tilt_noise = units::degToRad(0.2);
  return p;
}

TablePlan tablePlanFor(const YAML::Node& baseline) {
  return isSingleFlagellum(baseline) ? singleFlagellumTablePlan() : tailedRobotTablePlan();
}

SeriesPlan tailedRobotSeriesPlan() {
  SeriesPlan p;
  p.command_rpm = {{0.0, 120.0}, {30.0, 240.0}, {60.0, -180.0}};
  p.duration = 90.0;
  p.sample_interval = 0.5;
  p.position_noise = 2e-4;  // 0.2 mm video tracking
  p.orientation_noise = 0.01;
  p.turns_noise = 0.1;
  return p;
}

/// A single-flagellum swimmer's 3-D head track: two motor rates below its buckling threshold
/// (docs/model.md 7.6), 20 s each, so that a drift that grows with the rate differs from one
/// that grows with time; same video, IMU and counting noise as the tailed robots' series.
SeriesPlan singleFlagellumSeriesPlan() {
  SeriesPlan p = tailedRobotSeriesPlan();
  p.command_rpm = {{0.0, 40.0}, {20.0, 80.0}};
  p.duration = 40.0;
  return p;
}

SeriesPlan seriesPlanFor(const YAML::Node& baseline) {
  return isSingleFlagellum(baseline) ? singleFlagellumSeriesPlan() : tailedRobotSeriesPlan();
}

}  // namespace

const std::vector<std::string>& caseFreeParameters() {
  static const std::vector<std::string> free = {"medium.viscosity", "effects.stokes_head.C_t",
                                                "effects.stokes_head.C_r"};
  return free;
}

std::vector<std::string> caseFreeParameters(const YAML::Node& baseline) {
  if (!isSingleFlagellum(baseline)) return caseFreeParameters();
  // docs/model.md 7.6: a nearly rigid flagellum swims at a given motor rate with speeds that
  // do not depend on the viscosity (Stokes flow), so only the head's drag factors are fitted
  return {"effects.stokes_head.C_t", "effects.stokes_head.C_r"};
}

static std::vector<DiscoveryCase> makeDiscoveryCases() {
  std::vector<DiscoveryCase> cases = {{"null_table", {}, false, true, 0, 1.0, {}},
                                      {"null_series", {}, false, false, 0, 1.0, {}}};
  // one case per candidate, in the data its descriptor asks for
  for (const Candidate& c : standardCandidates())
    cases.push_back({c.name, {c.name}, false, c.steady_table_data, 0, 1.0, {}});
  cases.push_back(
      {"granular_yield+dc_motor", {"granular_yield", "dc_motor"}, false, true, 0, 1.0, {}});
  cases.push_back({"unknown_ripple", {}, true, false, 0, 1.0, {}});
  // docs/model.md 7.6: small tables, cross-validated; a yield only the fastest rows show, a
  // yield no row shows (the right verdict: "cannot tell", with the yield suggested), none
  cases.push_back(
      {"sparse_yield_5_rows", {"granular_yield"}, false, true, 0, 1.5, {40, 70, 100, 160, 250}});
  cases.push_back(
      {"sparse_yield_3_fast_rows", {"granular_yield"}, false, true, 0, 1.0, {200, 230, 260}});
  cases.push_back({"sparse_null_4_rows", {}, false, true, 0, 1.0, {60, 120, 180, 240}});
  // docs/model.md 7.6: lateral forces strong enough to run a position-fitted baseline off its
  // map, on robots of 2 to 5 tails
  for (int tails = 2; tails <= 5; ++tails)
    cases.push_back({"strong_lateral_" + std::to_string(tails) + "_tails",
                     {"interface_lateral_force"},
                     false,
                     false,
                     tails,
                     40.0,
                     {}});
  return cases;
}

const std::vector<DiscoveryCase>& discoveryCases() {
  static const std::vector<DiscoveryCase> cases = makeDiscoveryCases();
  return cases;
}

const DiscoveryCase& discoveryCaseByName(const std::string& name) {
  for (const DiscoveryCase& c : discoveryCases())
    if (c.name == name) return c;
  throw std::invalid_argument("unknown discovery case '" + name + "'");
}

std::string caseNotApplicableReason(const DiscoveryCase& c, const YAML::Node& baseline) {
  for (const std::string& effect : c.hidden) {
    const std::string reason = notApplicableReason(candidateByName(effect), baseline);
    if (!reason.empty()) return effect + " " + reason;
  }
  if (!isSingleFlagellum(baseline)) return "";
  if (c.tails > 0 || !c.sparse_rpm.empty())
    return "its plan (tail counts, or sparse rates of 40-260 rpm) is made for the tailed robots; "
           "a single-flagellum robot has the table at 20-90 rpm and the track at 40 and 80 rpm";
  return "";
}

GeneratedCase generateCase(const DiscoveryCase& c, const YAML::Node& baseline,
                           const std::string& baseline_source, std::uint64_t seed,
                           const EvaluatorOptions& options) {
  const std::string not_applicable = caseNotApplicableReason(c, baseline);
  if (!not_applicable.empty())
    throw std::invalid_argument("discovery case '" + c.name + "' does not apply to " +
                                baseline_source + ": " + not_applicable);
  std::mt19937_64 rng(seed * 7919 + 17);
  GeneratedCase out;
  Model truth = truthModel(c, baseline, baseline_source);
  // the drawn baseline values first, then each hidden effect's strengths (the draws' order)
  std::vector<double> values = truth.values();
  for (int i = 0; i < truth.baselineCount(); ++i) {
    values[i] *= logUniform(rng, 0.8, 1.25);
    out.truth[truth.parameters()[i].name] = values[i];
  }
  std::ostringstream description;
  description << "case " << c.name << ", seed " << seed << ": ";
  for (const std::string& effect : c.hidden) {
    const Candidate& candidate = candidateByName(effect);
    for (const TypicalStrength& r : rangesOf(candidate, baseline, rng)) {
      double v = (r.low == r.high ? r.low : logUniform(rng, r.low, r.high)) * c.strength_scale;
      if (r.random_sign && std::uniform_int_distribution<int>(0, 1)(rng) == 1) v = -v;
      // by name: the ranges need not list an effect's variables in the candidate's order
      const int index = truth.indexOf(r.variable);
      if (index < 0)
        throw std::logic_error("strength range for unknown variable '" + r.variable + "'");
      values[static_cast<size_t>(index)] = v;
      out.truth[r.variable] = v;
    }
  }
  out.truth_values = values;
  out.truth_without_hidden = values;
  size_t offset = static_cast<size_t>(truth.baselineCount());
  for (const std::string& effect : c.hidden) {
    const Candidate& candidate = candidateByName(effect);
    const std::vector<double>& off = candidate.off;
    if (off.size() != candidate.variables.size())
      throw std::logic_error("effect '" + effect + "' has no off value for each variable");
    std::copy(off.begin(), off.end(), out.truth_without_hidden.begin() + offset);
    offset += off.size();
  }
  truth.setValues(values);
  out.truth_config = truth.extendedConfig();
  if (c.table) {
    TablePlan plan = tablePlanFor(baseline);
    if (!c.sparse_rpm.empty()) {
      plan.omega_rpm = c.sparse_rpm;
      plan.n_tails = {2};
    }
    out.data.tables.push_back(generateTable(truth, plan, seed, options));
    out.data.tables.back().source = "<" + c.name + " seed " + std::to_string(seed) + ">";
  } else {
    SeriesPlan plan = seriesPlanFor(baseline);
    if (c.unknown) {
      plan.ripple_fraction = std::uniform_real_distribution<double>(0.2, 0.35)(rng);
      plan.ripple_period = std::uniform_real_distribution<double>(8.0, 16.0)(rng);
      out.truth["motor_ripple.fraction"] = plan.ripple_fraction;
      out.truth["motor_ripple.period"] = plan.ripple_period;
    }
    out.data.series.push_back(generateSeries(truth, plan, seed, options));
    if (c.tails > 0)
      out.data.series.back().overrides = {{"robot.n_tails", std::to_string(c.tails)}};
    out.data.series.back().source = "<" + c.name + " seed " + std::to_string(seed) + ">";
  }
  for (const auto& [name, v] : out.truth) description << name << " = " << v << "; ";
  out.description = description.str();
  return out;
}

HiddenSignature hiddenSignature(const DiscoveryCase& c, const GeneratedCase& g,
                                const YAML::Node& baseline, const std::string& baseline_source,
                                const EvaluatorOptions& options) {
  HiddenSignature out;
  if (c.hidden.empty()) return out;
  const Model truth = truthModel(c, baseline, baseline_source);
  const Evaluator evaluator(g.data, makeSplit(g.data), options);
  // The truth, the truth without the hidden effects, and the latter with each baseline
  // parameter stepped (they are fitted on a log scale): a forward-difference Jacobian.
  constexpr double kLogStep = 1e-3;
  const int baseline_count = truth.baselineCount();
  std::vector<std::vector<double>> values = {g.truth_values, g.truth_without_hidden};
  for (int k = 0; k < baseline_count; ++k) {
    values.push_back(g.truth_without_hidden);
    values.back()[static_cast<size_t>(k)] *= std::exp(kLogStep);
  }
  // Column 0: the hidden effects' change of every residual, in noise units (the data cancel);
  // then d z / d ln p of each baseline parameter.
  const auto columns = [&](Part part) {
    const std::vector<Evaluation> e = evaluator.evaluateMany(truth, values, part);
    for (const Evaluation& each : e)
      if (!each.ok || each.points.size() != e[0].points.size())
        throw std::runtime_error("case " + c.name +
                                 ": the truth model failed on its own data: " + each.failure);
    Eigen::MatrixXd d(static_cast<Eigen::Index>(e[0].points.size()), 1 + baseline_count);
    for (Eigen::Index i = 0; i < d.rows(); ++i) {
      const double without = e[1].points[static_cast<size_t>(i)].z();
      d(i, 0) = e[0].points[static_cast<size_t>(i)].z() - without;
      for (int k = 0; k < baseline_count; ++k)
        d(i, 1 + k) = (e[2 + k].points[static_cast<size_t>(i)].z() - without) / kLogStep;
    }
    return d;
  };
  const Eigen::MatrixXd train = columns(Part::kTrain), held = columns(Part::kHeldOut);
  out.train_count = static_cast<int>(train.rows());
  out.held_out_count = static_cast<int>(held.rows());
  out.train_chi_square = train.col(0).squaredNorm();
  out.held_out_chi_square = held.col(0).squaredNorm();
  // what a baseline fit on the training rows absorbs, to first order (linear least squares)
  Eigen::VectorXd shift = Eigen::VectorXd::Zero(baseline_count);
  if (baseline_count > 0 && train.rows() > 0)
    shift = train.rightCols(baseline_count).colPivHouseholderQr().solve(train.col(0));
  out.train_unabsorbed = (train.col(0) - train.rightCols(baseline_count) * shift).squaredNorm();
  out.held_out_unabsorbed = (held.col(0) - held.rightCols(baseline_count) * shift).squaredNorm();
  out.defined = true;
  return out;
}

}  // namespace identify
}  // namespace flagella
