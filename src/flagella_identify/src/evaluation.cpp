#include "flagella_identify/evaluation.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <nlohmann/json.hpp>
#include <numeric>
#include <type_traits>

#include "flagella_sim/actuation/motor_command.h"
#include "flagella_sim/analysis/buckling_probe.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/runtime/distributed_for.h"
#include "flagella_sim/runtime/exact_json.h"
#include "flagella_sim/runtime/parallel_for.h"
#include "flagella_sim/simulation/simulation.h"
#include "interpolate.h"
#include "series_features.h"

namespace flagella {
namespace identify {

namespace {

constexpr double kTwoPi = 2.0 * M_PI;
/// A model circle that does not close is reported as this radius (effectively straight) [m].
constexpr double kStraightRadius = 1e3;
/// Samples of the steady window used for the summary fits.
constexpr int kWindowSamples = 50;

double orZero(double v) { return std::isfinite(v) ? v : 0.0; }

/// A job's evaluation as text, for the ranks of an MPI run (distributed_for.h).
std::string encodeEvaluation(const Evaluation& e) {
  nlohmann::json points = nlohmann::json::array();
  for (const ResidualPoint& p : e.points)
    points.push_back({p.output, p.from_series, p.source, p.row, exactJson(p.omega_T),
                      exactJson(p.session_time), exactJson(p.run_time), exactJson(p.data),
                      exactJson(p.model), exactJson(p.sigma)});
  return nlohmann::json{{"ok", e.ok}, {"failure", e.failure}, {"points", points}}.dump();
}

Evaluation decodeEvaluation(const std::string& text) {
  const nlohmann::json j = nlohmann::json::parse(text);
  Evaluation e;
  e.ok = j.at("ok").get<bool>();
  e.failure = j.at("failure").get<std::string>();
  for (const nlohmann::json& p : j.at("points")) {
    ResidualPoint r;
    r.output = p[0].get<std::string>();
    r.from_series = p[1].get<bool>();
    r.source = p[2].get<int>();
    r.row = p[3].get<int>();
    r.omega_T = exactNumber(p[4]);
    r.session_time = exactNumber(p[5]);
    r.run_time = exactNumber(p[6]);
    r.data = exactNumber(p[7]);
    r.model = exactNumber(p[8]);
    r.sigma = exactNumber(p[9]);
    e.points.push_back(std::move(r));
  }
  return e;
}

/// Motor command held from each sample to the next (the data's convention).
class HeldCommand : public MotorCommand {
 public:
  explicit HeldCommand(const TimeSeries& s) : t_(s.t), omega_(s.omega_cmd) {}
  /// `t` is simulated time, which starts at the first sample.
  double omega(double t) const override {
    const auto it = std::upper_bound(t_.begin(), t_.end(), t + t_.front());
    const size_t i = it == t_.begin() ? 0 : static_cast<size_t>(it - t_.begin()) - 1;
    return omega_[std::min(i, omega_.size() - 1)];
  }

 private:
  std::vector<double> t_, omega_;
};

/// Indices of at most `max_points` samples, evenly spread, with t in [t0, t1).
std::vector<int> selectSamples(const TimeSeries& s, double t0, double t1, int max_points) {
  std::vector<int> all;
  for (size_t i = 1; i < s.t.size(); ++i)
    if (s.t[i] >= t0 && s.t[i] < t1) all.push_back(static_cast<int>(i));
  if (static_cast<int>(all.size()) <= max_points) return all;
  std::vector<int> picked;
  for (int k = 0; k < max_points; ++k)
    picked.push_back(all[static_cast<size_t>(
        std::llround(k * (all.size() - 1.0) / std::max(1, max_points - 1)))]);
  picked.erase(std::unique(picked.begin(), picked.end()), picked.end());
  return picked;
}

std::vector<ConfigOverride> allOverrides(const std::vector<ConfigOverride>& a,
                                         const std::vector<ConfigOverride>& b) {
  std::vector<ConfigOverride> all = a;
  all.insert(all.end(), b.begin(), b.end());
  return all;
}

/// The model's buckling threshold [rad/s] for a measured one (docs/model.md 8.4.4, 8.4.5): the
/// rate where the growth rate of the flagellum's slow tilt changes sign (findGrowthThreshold,
/// runs of GrowthProbeOptions' default length in motor turns), bracketed from the measured value
/// x/ kThresholdBracketRatio and narrowed to kThresholdTolerance. It moves smoothly with the
/// model and does not depend on a run length chosen by the table (settle_time_s and window_s do
/// not enter it).
double predictedThreshold(const SimulationConfig& cfg, double measured, int /*threads*/) {
  const double rpm = std::abs(measured) * units::kRpmPerRadPerSec;
  GrowthThresholdOptions search;
  search.low = rpm / kThresholdBracketRatio;
  search.high = rpm * kThresholdBracketRatio;
  search.min_rate = std::min(search.min_rate, search.low);
  search.max_rate = std::max(search.max_rate, search.high);
  search.tolerance = kThresholdTolerance;
  const GrowthProbeOptions probe;
  const GrowthThreshold g =
      findGrowthThreshold([&](double rate) { return runGrowthProbe(cfg, rate, probe); }, search);
  if (!g.found) throw std::runtime_error("buckling threshold: " + g.message);
  return g.threshold * units::kRadPerSecPerRpm;
}

/// The model's value of a steady-state output from the simulation summary; false for an output
/// the table cannot hold.
bool predictedOutput(const SummaryMetrics& m, const std::string& name, double& predicted) {
  if (name == "v")
    predicted = m.speed;
  else if (name == "omega_h")
    predicted = m.omega_h;
  else if (name == "omega_t")
    predicted = m.omega_t;
  else if (name == "omega_yr")
    predicted = m.yaw_rate;
  else if (name == "R_yr")
    predicted = m.circle_valid ? m.circle_radius : kStraightRadius;
  else if (name == "tilt")
    predicted = m.flagellum_tilt_mean;  // docs/model.md 8.4.4 (helical robot; checked on input)
  else
    return false;
  return true;
}

/// The residuals of sample `i` of series `s` (index `source`) against the simulated `trace`:
/// position (shifted by `offset`), head axis and counted turns, as far as the data has them.
void appendSampleResiduals(const TimeSeries& s, int source, int i,
                           const Evaluator::SeriesTrace& trace, const Vec3& offset,
                           Evaluation& out) {
  const auto at = [&](double t, auto member) { return interpolateAt(trace.t, t, member); };
  static const char* kAxes[3] = {"x", "y", "z"};
  static const char* kAxisNames[3] = {"axis_x", "axis_y", "axis_z"};
  const double t = s.t[i];
  ResidualPoint base;
  base.from_series = true;
  base.source = source;
  base.row = i;
  base.omega_T = s.omega_cmd[i];
  base.session_time = s.session_time + t;
  base.run_time = t;
  const Vec3 pos = at(t, [&](size_t k) { return trace.position[k]; }) + offset;
  for (int a = 0; a < (s.has_z ? 3 : 2); ++a) {
    ResidualPoint p = base;
    p.output = kAxes[a];
    p.data = s.position[i](a);
    p.model = pos(a);
    p.sigma = s.position_noise;
    out.points.push_back(p);
  }
  if (!s.orientation.empty()) {
    const Vec3 axis_data = s.orientation[i] * Vec3::UnitZ();
    const Vec3 axis_model = at(t, [&](size_t k) { return trace.axis[k]; }).normalized();
    for (int a = 0; a < 3; ++a) {
      ResidualPoint p = base;
      p.output = kAxisNames[a];
      p.data = axis_data(a);
      p.model = axis_model(a);
      p.sigma = s.orientation_noise;
      out.points.push_back(p);
    }
  }
  const std::vector<double>* counted[2] = {&s.head_turns, &s.tail_turns};
  const std::vector<double>* simulated[2] = {&trace.head_turns, &trace.tail_turns};
  static const char* kTurnNames[2] = {"head_turns", "tail_turns"};
  for (int k = 0; k < 2; ++k) {
    if (counted[k]->empty()) continue;
    ResidualPoint p = base;
    p.output = kTurnNames[k];
    p.data = (*counted[k])[i];
    p.model = at(t, [&](size_t j) { return (*simulated[k])[j]; });
    p.sigma = s.turns_noise;
    out.points.push_back(p);
  }
}

}  // namespace

Split makeSplit(const MeasuredData& data, int stride, double held_out_fraction) {
  Split split;
  for (const SteadyStateTable& table : data.tables) {
    std::vector<int> order(table.rows.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
      return std::abs(table.rows[a].omega_T) < std::abs(table.rows[b].omega_T);
    });
    std::vector<bool> held(table.rows.size(), false);
    for (size_t k = 0; k < order.size(); ++k) held[order[k]] = (k % stride) == 1;
    split.table_row_held_out.push_back(held);
  }
  for (const TimeSeries& s : data.series)
    split.series_split_time.push_back(s.t.front() +
                                      (1.0 - held_out_fraction) * (s.t.back() - s.t.front()));
  return split;
}

double chiSquare(const Evaluation& e) {
  double sum = 0.0;
  for (const ResidualPoint& p : e.points) sum += p.z() * p.z();
  return sum;
}

Evaluator::Evaluator(const MeasuredData& data, const Split& split, EvaluatorOptions options)
    : data_(data), split_(split), options_(options) {}

Evaluation Evaluator::evaluate(const Model& model, const std::vector<double>& values,
                               Part part) const {
  return evaluateMany(model, {values}, part).front();
}

std::vector<Evaluation> Evaluator::evaluateMany(const Model& model,
                                                const std::vector<std::vector<double>>& values,
                                                Part part) const {
  std::vector<Job> jobs;
  for (int m = 0; m < static_cast<int>(values.size()); ++m) {
    for (int t = 0; t < static_cast<int>(data_.tables.size()); ++t)
      for (int r = 0; r < static_cast<int>(data_.tables[t].rows.size()); ++r) {
        const bool held = split_.table_row_held_out[t][r];
        if (part == Part::kAll || held == (part == Part::kHeldOut))
          jobs.push_back({m, false, t, r});
      }
    for (int s = 0; s < static_cast<int>(data_.series.size()); ++s) jobs.push_back({m, true, s, 0});
  }
  // Threads the jobs leave idle go to the runs of a job's threshold window.
  for (Job& job : jobs) job.threads = std::max(1, options_.jobs / std::max<int>(1, jobs.size()));
  // On this process's threads, or spread over mpirun's ranks: every rank gets every job's
  // evaluation, so every rank's fit goes on identically (distributed_for.h).
  const std::vector<std::string> encoded =
      distributedFor(static_cast<int>(jobs.size()), options_.jobs, [&](int j) {
        Evaluation e;
        runJob(model, values[jobs[j].model_index], jobs[j], part, e);
        return encodeEvaluation(e);
      });
  std::vector<Evaluation> per_job;
  for (const std::string& text : encoded) per_job.push_back(decodeEvaluation(text));
  std::vector<Evaluation> out(values.size());
  for (size_t j = 0; j < jobs.size(); ++j) {
    Evaluation& e = out[jobs[j].model_index];
    if (!per_job[j].ok && e.ok) {
      e.ok = false;
      e.failure = per_job[j].failure;
    }
    e.points.insert(e.points.end(), per_job[j].points.begin(), per_job[j].points.end());
  }
  return out;
}

void Evaluator::runJob(const Model& model, const std::vector<double>& values, const Job& job,
                       Part part, Evaluation& out) const {
  try {
    if (!job.is_series)
      runTableJob(model, values, job, out);
    else
      runSeriesJob(model, values, job, part, out);
  } catch (const std::exception& e) {
    out.ok = false;
    out.failure = e.what();
  }
}

void Evaluator::runTableJob(const Model& model, const std::vector<double>& values, const Job& job,
                            Evaluation& out) const {
  const SteadyStateTable& table = data_.tables[job.source];
  const SteadyStateRow& row = table.rows[job.row];
  const double session = orZero(row.time);
  SimulationConfig cfg =
      model.configFor(allOverrides(table.overrides, row.overrides), session, values);
  cfg.motor.mode = "constant";
  cfg.motor.omega = row.omega_T;
  cfg.duration = table.settle_time + table.window;
  cfg.steady_fraction = table.window / cfg.duration;
  cfg.output_interval = std::max(cfg.dt, table.window / kWindowSamples);
  cfg.solver.residual_tolerance =
      std::min(cfg.solver.residual_tolerance, options_.solver_tolerance);
  const bool has_steady = std::any_of(row.measured.begin(), row.measured.end(), [](const auto& m) {
    return m.first != "buckling_threshold" && std::isfinite(m.second);
  });
  SummaryMetrics m;
  if (has_steady) {
    Simulation sim(cfg);
    sim.run(cfg.duration);
    m = sim.summary();
  }
  for (const auto& [name, measured] : row.measured) {
    if (!std::isfinite(measured)) continue;
    double predicted = 0.0;
    if (name == "buckling_threshold")
      predicted = predictedThreshold(cfg, measured, job.threads);
    else if (!predictedOutput(m, name, predicted))
      continue;
    ResidualPoint p;
    p.output = name;
    p.source = job.source;
    p.row = job.row;
    p.omega_T = row.omega_T;
    p.session_time = row.time;
    p.data = measured;
    p.model = predicted;
    p.sigma = row.sigmaOf(name, table.noise);
    p.buckled = has_steady && m.buckled;
    out.points.push_back(p);
  }
}

void Evaluator::runSeriesJob(const Model& model, const std::vector<double>& values, const Job& job,
                             Part part, Evaluation& out) const {
  const TimeSeries& s = data_.series[job.source];
  const double split = split_.series_split_time[job.source];
  const double t_end = part == Part::kTrain ? split : s.t.back();
  const SeriesTrace trace = traceSeries(model, values, job.source, t_end);
  if (options_.series_features) {
    if (part != Part::kHeldOut)
      appendFeatureResiduals(s, job.source, s.t.front(), split, trace, trace.up, out);
    if (part != Part::kTrain)
      appendFeatureResiduals(s, job.source, split, s.t.back() + 1.0, trace, trace.up, out);
    return;
  }
  const int budget = options_.max_series_points;
  const std::vector<int> train = selectSamples(s, s.t.front(), split, budget * 6 / 10);
  const std::vector<int> held = selectSamples(s, split, s.t.back() + 1.0, budget * 4 / 10);
  // The start of the track is a nuisance: offset = mean(data - model) over the training part.
  Vec3 offset = Vec3::Zero();
  for (int i : train)
    offset +=
        s.position[i] - interpolateAt(trace.t, s.t[i], [&](size_t k) { return trace.position[k]; });
  if (!train.empty()) offset /= static_cast<double>(train.size());
  std::vector<int> chosen;
  if (part != Part::kHeldOut) chosen.insert(chosen.end(), train.begin(), train.end());
  if (part != Part::kTrain) chosen.insert(chosen.end(), held.begin(), held.end());
  for (int i : chosen) appendSampleResiduals(s, job.source, i, trace, offset, out);
}

Evaluator::SeriesTrace Evaluator::traceSeries(const Model& model, const std::vector<double>& values,
                                              int series, double t_end) const {
  const TimeSeries& s = data_.series.at(series);
  SimulationConfig cfg = model.configFor(s.overrides, s.session_time, values);
  cfg.output_interval = cfg.dt;
  cfg.solver.residual_tolerance =
      std::min(cfg.solver.residual_tolerance, options_.solver_tolerance);
  Simulation sim(cfg);
  std::shared_ptr<const MotorCommand> motor = std::make_shared<HeldCommand>(s);
  if (cfg.motor.ramp_time > 0.0) motor = std::make_shared<RampedMotor>(motor, cfg.motor.ramp_time);
  sim.setMotor(motor);
  sim.run(std::min(t_end, s.t.back()) - s.t.front() + cfg.dt);
  SeriesTrace trace;
  trace.up = cfg.medium.up;
  const TrajectorySample& first = sim.trajectory().front();
  for (const TrajectorySample& sample : sim.trajectory()) {
    trace.t.push_back(s.t.front() + sample.time);
    trace.position.push_back(sample.head_position);
    trace.axis.push_back(sample.head_axis);
    trace.head_turns.push_back((sample.head_angle - first.head_angle) / kTwoPi);
    trace.tail_turns.push_back((sample.tail_angle - first.tail_angle) / kTwoPi);
  }
  return trace;
}

}  // namespace identify
}  // namespace flagella
