#include "flagella_identify/dataset_generator.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include "flagella_sim/core/units.h"

namespace flagella {
namespace identify {

namespace {

/// The times k dt in [0, duration], on a nanosecond lattice: no drift from summing dt, so a
/// command step at a multiple of the spacing falls on the same sample in every grid.
std::vector<double> gridTimes(double dt, double duration) {
  std::vector<double> times;
  for (int k = 0;; ++k) {
    const double t = std::round(k * dt * 1e9) * 1e-9;
    if (t > duration + 1e-9) return times;
    times.push_back(t);
  }
}

double commandAt(const SeriesPlan& plan, double t) {
  double omega = plan.command_rpm.front().second;
  for (const auto& [start, rpm] : plan.command_rpm)
    if (t >= start) omega = rpm;
  return units::rpmToRadPerSec(omega);
}

}  // namespace

SteadyStateTable generateTable(const Model& truth, const TablePlan& plan, std::uint64_t seed,
                               const EvaluatorOptions& options) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  SteadyStateTable table;
  table.source = "<generated>";
  table.settle_time = plan.settle_time;
  table.window = plan.window;
  table.noise["v"] = plan.v_noise;
  if (plan.measure_rotation) {
    table.noise["omega_h"] = plan.omega_noise;
    table.noise["omega_t"] = plan.omega_noise;
  }
  if (plan.tilt_noise > 0.0) table.noise["tilt"] = plan.tilt_noise;
  // no tail counts: the baseline's robot, no override
  const std::vector<int> tail_counts = plan.n_tails.empty() ? std::vector<int>{0} : plan.n_tails;
  for (int n : tail_counts)
    for (double rpm : plan.omega_rpm) {
      SteadyStateRow row;
      row.omega_T = units::rpmToRadPerSec(rpm);
      row.id = std::to_string(static_cast<int>(rpm)) + "rpm";
      if (n > 0) {
        row.overrides = {{"robot.n_tails", std::to_string(n)}};
        row.id = "n" + std::to_string(n) + "_" + row.id;
      }
      for (const auto& [name, sigma] : table.noise) row.measured[name] = 0.0;
      table.rows.push_back(row);
    }
  // The experiments were run in a random order, evenly over the session.
  std::vector<int> order(table.rows.size());
  std::iota(order.begin(), order.end(), 0);
  std::shuffle(order.begin(), order.end(), rng);
  const double spacing =
      plan.session_hours * units::kSecondsPerHour / std::max<size_t>(1, table.rows.size());
  for (size_t k = 0; k < order.size(); ++k) table.rows[order[k]].time = k * spacing;

  // Exact model outputs through the same evaluator the identification uses (one table with
  // unit noise gives z = model - data with data = 0, i.e. the model value itself).
  MeasuredData exact;
  SteadyStateTable unit_noise = table;
  for (auto& [name, sigma] : unit_noise.noise) sigma = 1.0;
  exact.tables.push_back(unit_noise);
  Split all;
  all.table_row_held_out.push_back(std::vector<bool>(table.rows.size(), false));
  const Evaluator evaluator(exact, all, options);
  const Evaluation e = evaluator.evaluate(truth, truth.values(), Part::kTrain);
  if (!e.ok) throw std::runtime_error("the truth model failed: " + e.failure);
  for (const ResidualPoint& p : e.points)
    table.rows[p.row].measured[p.output] = p.model + table.noise.at(p.output) * unit(rng);
  return table;
}

TimeSeries generateSeries(const Model& truth, const SeriesPlan& plan, std::uint64_t seed,
                          const EvaluatorOptions& options) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> unit(0.0, 1.0);
  // The truth is simulated with the real motor speed (with ripple, if any), held over a fine
  // sampling of the command; the data record the nominal command at the video samples.
  TimeSeries fine;
  const double fine_dt = std::min(plan.sample_interval, 0.1);
  for (const double t : gridTimes(fine_dt, plan.duration)) {
    fine.t.push_back(t);
    const double ripple =
        1.0 + plan.ripple_fraction * std::sin(2.0 * M_PI * t / plan.ripple_period);
    fine.omega_cmd.push_back(commandAt(plan, t) * ripple);
    fine.position.push_back(Vec3::Zero());
  }
  fine.session_time = plan.session_time;
  MeasuredData holder;
  holder.series.push_back(fine);
  Split split;
  split.series_split_time.push_back(plan.duration);
  const Evaluator evaluator(holder, split, options);
  const Evaluator::SeriesTrace trace = evaluator.traceSeries(truth, truth.values(), 0);

  TimeSeries s;
  s.source = "<generated>";
  s.session_time = plan.session_time;
  s.has_z = plan.has_z;
  s.position_noise = plan.position_noise;
  s.orientation_noise = plan.orientation ? plan.orientation_noise : 0.0;
  s.turns_noise = plan.turns ? plan.turns_noise : 0.0;
  auto traceIndex = [&](double t) {
    const auto it = std::lower_bound(trace.t.begin(), trace.t.end(), t - 1e-9);
    return std::min<size_t>(it - trace.t.begin(), trace.t.size() - 1);
  };
  for (const double t : gridTimes(plan.sample_interval, plan.duration)) {
    const size_t k = traceIndex(t);
    s.t.push_back(t);
    s.omega_cmd.push_back(commandAt(plan, t));
    Vec3 p = trace.position[k];
    for (int a = 0; a < 3; ++a) p(a) += plan.position_noise * unit(rng);
    if (!plan.has_z) p.z() = 0.0;
    s.position.push_back(p);
    if (plan.orientation) {
      // IMU: the head axis with small random tilts; the frame's roll about the axis is free.
      Vec3 axis = trace.axis[k];
      for (int a = 0; a < 3; ++a) axis(a) += plan.orientation_noise * unit(rng);
      s.orientation.push_back(Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), axis.normalized()));
    }
    if (plan.turns) {
      const bool first = s.t.size() == 1;  // counting starts at zero
      s.head_turns.push_back(trace.head_turns[k] + (first ? 0.0 : plan.turns_noise * unit(rng)));
      s.tail_turns.push_back(trace.tail_turns[k] + (first ? 0.0 : plan.turns_noise * unit(rng)));
    }
  }
  return s;
}

}  // namespace identify
}  // namespace flagella
