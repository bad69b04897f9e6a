#include "flagella_control/tracking_bound.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <stdexcept>
#include <unordered_map>

#include "flagella_control/switching_model.h"
#include "flagella_control/validation.h"

namespace flagella::control {
namespace {

constexpr double kSearchBack = 0.02;   // [m] progress window behind the last progress point
constexpr double kSearchAhead = 0.15;  // [m] and ahead of it (more than a period's motion)

enum class Objective { MaxError, RmsError };

struct SearchState {
  Vec2 position = Vec2::Zero();
  double heading = 0.0;
  double progress = 0.0;  // lap-cumulative arclength of the nearest point, never decreasing
  double cross_track = 0.0;
  double max_error = 0.0, sum_sq = 0.0;
  long samples = 0;
  int last_sign = 0;  // sign applied at the end of the period (0: the motor not started)
  double dead_remaining = 0.0;
  int parent = -1;  // index in the previous layer
  double plus = 0.0;
};

struct Finished {
  SearchState state;
  int layer = 0;
  std::vector<Vec2> tail;  // samples of the last, partial period
};

const char* const kOptions = "tracking bound";

bool better(Objective objective, const SearchState& a, const SearchState& b) {
  if (objective == Objective::MaxError)
    return a.max_error < b.max_error || (a.max_error == b.max_error && a.sum_sq < b.sum_sq);
  return a.sum_sq < b.sum_sq || (a.sum_sq == b.sum_sq && a.max_error < b.max_error);
}

double finalCost(Objective objective, const SearchState& s) {
  return objective == Objective::MaxError ? s.max_error
                                          : std::sqrt(s.sum_sq / std::max(1L, s.samples));
}

class BoundSearch {
 public:
  BoundSearch(const Path& path, int laps, const BinaryCalibration& c, const TrackingBoundOptions& o)
      : path_(path), model_(c), options_(o), advance_angle_(c.advance_angle) {
    total_ = path.length() * (path.closed() ? laps : 1);
    period_ = c.switch_period;
    samples_per_period_ = std::max(1, static_cast<int>(std::lround(period_ / o.sample_interval)));
  }

  /// The best schedule under `objective` among those whose error never exceeds `error_cap` and
  /// that complete within `time_cap` [s].
  BoundSchedule run(Objective objective, double error_cap, double time_cap, long& expanded) {
    std::vector<std::vector<SearchState>> layers(1);
    SearchState start;
    const PathPoint p0 = path_.at(0.0);
    start.position = p0.position;
    start.heading = p0.tangent - advance_angle_;
    start.samples = 1;  // the start itself, on the path
    layers[0].push_back(start);
    std::vector<Finished> finished;
    const int max_layers = static_cast<int>(std::ceil(time_cap / period_));
    std::vector<Vec2> tail;
    for (int layer = 0; layer < max_layers && !layers.back().empty(); ++layer) {
      std::unordered_map<std::uint64_t, int> cells;
      std::vector<SearchState> next;
      const std::vector<SearchState>& current = layers.back();
      for (int i = 0; i < static_cast<int>(current.size()); ++i) {
        for (int k = 0; k <= options_.duty_steps; ++k) {
          ++expanded;
          SearchState s = current[i];
          s.parent = i;
          s.plus = period_ * k / options_.duty_steps;
          tail.clear();
          const double cap = objective == Objective::MaxError
                                 ? std::min(error_cap, bestFinishedMax(finished))
                                 : error_cap;
          const int done_at = fly(s, current[i], cap, tail);
          if (done_at == kOverCap) continue;
          if (done_at > 0) {
            finished.push_back({s, layer, tail});
            continue;
          }
          merge(objective, s, cells, next);
        }
      }
      layers.push_back(prune(objective, next));
    }
    return best(objective, finished, layers);
  }

 private:
  static constexpr int kOverCap = -2;

  // Flies one period from `from` with s.plus; updates s. Returns the sample index (1-based) at
  // which the path was completed, -1 if it was not, kOverCap once the error exceeds `cap`.
  // The period's samples go to `tail`.
  int fly(SearchState& s, const SearchState& from, double cap, std::vector<Vec2>& tail) const {
    ModelMotion motion;
    for (int m = 1; m <= samples_per_period_; ++m) {
      const double t = period_ * m / samples_per_period_;
      motion = model_.until(from.heading, from.last_sign, from.dead_remaining, s.plus, t);
      const Vec2 position = from.position + motion.displacement;
      tail.push_back(position);
      const double error = path_.project(position).distance;
      if (error > cap) return kOverCap;
      s.max_error = std::max(s.max_error, error);
      s.sum_sq += error * error;
      ++s.samples;
      const PathProjection window = path_.project(position, s.progress - kSearchBack,
                                                  std::min(s.progress + kSearchAhead, total_));
      // Progress is made only near the stretch of the path being flown: far from it (another
      // side of a closed path, flown backwards) the window's nearest point is its end, and the
      // progress would leap along the path without the robot.
      if (window.distance > cap) return kOverCap;
      s.progress = std::max(s.progress, window.s);
      s.cross_track = window.cross_track;
      s.position = position;
      s.heading = from.heading + motion.turn;
      if (s.progress >= total_ - options_.finish_tolerance) return m;
    }
    s.last_sign = s.plus < period_ ? -1 : 1;
    s.dead_remaining = motion.dead_remaining;
    return -1;
  }

  void merge(Objective objective, const SearchState& s,
             std::unordered_map<std::uint64_t, int>& cells, std::vector<SearchState>& next) const {
    const double tangent = path_.at(s.progress).tangent;
    const double relative = wrapAngle(s.heading + advance_angle_ - tangent);
    const auto cell = [](double value, double size) {
      return static_cast<std::uint64_t>(static_cast<std::int64_t>(std::floor(value / size)) &
                                        0x1fffff);
    };
    const std::uint64_t key = cell(s.progress, options_.progress_cell) << 43 |
                              cell(s.cross_track, options_.cross_track_cell) << 22 |
                              cell(relative, options_.heading_cell) << 1 | (s.last_sign > 0);
    const auto [it, inserted] = cells.emplace(key, static_cast<int>(next.size()));
    if (inserted)
      next.push_back(s);
    else if (better(objective, s, next[it->second]))
      next[it->second] = s;
  }

  // Keeps the best states_per_progress of each progress cell.
  std::vector<SearchState> prune(Objective objective, std::vector<SearchState>& states) const {
    std::sort(states.begin(), states.end(), [&](const SearchState& a, const SearchState& b) {
      const long ca = std::lround(std::floor(a.progress / options_.progress_cell));
      const long cb = std::lround(std::floor(b.progress / options_.progress_cell));
      return ca != cb ? ca < cb : better(objective, a, b);
    });
    std::vector<SearchState> kept;
    long current_cell = -1;
    int in_cell = 0;
    for (const SearchState& s : states) {
      const long c = std::lround(std::floor(s.progress / options_.progress_cell));
      if (c != current_cell) {
        current_cell = c;
        in_cell = 0;
      }
      if (in_cell++ < options_.states_per_progress) kept.push_back(s);
    }
    return kept;
  }

  static double bestFinishedMax(const std::vector<Finished>& finished) {
    double best = INFINITY;
    for (const Finished& f : finished) best = std::min(best, f.state.max_error);
    return best;
  }

  BoundSchedule best(Objective objective, const std::vector<Finished>& finished,
                     const std::vector<std::vector<SearchState>>& layers) const {
    BoundSchedule out;
    const Finished* winner = nullptr;
    for (const Finished& f : finished)
      if (!winner || finalCost(objective, f.state) < finalCost(objective, winner->state))
        winner = &f;
    if (!winner) return out;  // not complete within max_duration
    out.complete = true;
    out.max_error = winner->state.max_error;
    out.rms_error = std::sqrt(winner->state.sum_sq / winner->state.samples);
    out.duration = winner->layer * period_ +
                   period_ * static_cast<double>(winner->tail.size()) / samples_per_period_;
    // Walk back through the layers for the schedule and the sampled path.
    std::vector<double> plus{winner->state.plus};
    std::vector<std::vector<Vec2>> pieces{winner->tail};
    int index = winner->state.parent;
    for (int layer = winner->layer; layer > 0; --layer) {
      const SearchState& s = layers[layer][index];
      plus.push_back(s.plus);
      const SearchState& from = layers[layer - 1][s.parent];
      std::vector<Vec2> piece;
      for (int m = 1; m <= samples_per_period_; ++m)
        piece.push_back(from.position + model_
                                            .until(from.heading, from.last_sign,
                                                   from.dead_remaining, s.plus,
                                                   period_ * m / samples_per_period_)
                                            .displacement);
      pieces.push_back(piece);
      index = s.parent;
    }
    out.plus_durations.assign(plus.rbegin(), plus.rend());
    out.samples.push_back(layers[0][0].position);
    for (auto it = pieces.rbegin(); it != pieces.rend(); ++it)
      out.samples.insert(out.samples.end(), it->begin(), it->end());
    return out;
  }

  const Path& path_;
  DeadTimeModel model_;
  TrackingBoundOptions options_;
  double advance_angle_ = 0.0;
  double total_ = 0.0, period_ = 0.0;
  int samples_per_period_ = 1;
};

}  // namespace

void TrackingBoundOptions::validate() const {
  requireInRange(kOptions, "duty_steps", duty_steps, 1, 1000);
  requireInRange(kOptions, "sample_interval", sample_interval, 1e-3, 1e3);
  requireInRange(kOptions, "progress_cell", progress_cell, 1e-5, 1.0);
  requireInRange(kOptions, "cross_track_cell", cross_track_cell, 1e-5, 1.0);
  requireInRange(kOptions, "heading_cell", heading_cell, 1e-4, 1.0);
  requireInRange(kOptions, "states_per_progress", states_per_progress, 1, 10000);
  requireInRange(kOptions, "first_cap", first_cap, 1e-5, 10.0);
  requireInRange(kOptions, "largest_cap", largest_cap, first_cap, 100.0);
  requireInRange(kOptions, "cap_tolerance", cap_tolerance, 1e-6, 1.0);
  requireInRange(kOptions, "rms_error_cap_factor", rms_error_cap_factor, 1.0, 100.0);
  requireInRange(kOptions, "plan_error_cap_factor", plan_error_cap_factor, 1.0, 100.0);
  requireInRange(kOptions, "finish_tolerance", finish_tolerance, 0.0, 1.0);
  requireInRange(kOptions, "rms_time_factor", rms_time_factor, 1.0, 10.0);
  requireInRange(kOptions, "max_duration", max_duration, 1e-3, 1e6);
}

TrackingBound computeTrackingBound(const Path& path, int laps, const BinaryCalibration& c,
                                   const TrackingBoundOptions& options) {
  c.validate();
  options.validate();
  if (path.empty()) throw std::invalid_argument("tracking bound: the path is empty");
  if (laps < 1) throw std::invalid_argument("tracking bound: laps must be >= 1");
  BoundSearch search(path, laps, c, options);
  TrackingBound bound;
  const DeadTimeModel model(c);
  bound.dead_time = model.deadTime();
  bound.direction_mismatch = model.directionMismatch();
  // The max error: the search confined to a tube of the path (error cap), the cap doubled from
  // a first guess until a schedule completes, then bisected between the largest cap that found
  // none and the best max found (docs/model.md 7.5).
  double infeasible = 0.0, cap = options.first_cap;
  while (cap <= options.largest_cap) {
    BoundSchedule s =
        search.run(Objective::MaxError, cap, options.max_duration, bound.states_expanded);
    if (s.complete) {
      bound.best_max = std::move(s);
      break;
    }
    infeasible = cap;
    cap *= 2.0;
  }
  if (!bound.best_max.complete) return bound;
  while (bound.best_max.max_error - infeasible > options.cap_tolerance) {
    cap = 0.5 * (infeasible + bound.best_max.max_error);
    BoundSchedule s =
        search.run(Objective::MaxError, cap, options.max_duration, bound.states_expanded);
    if (s.complete && s.max_error < bound.best_max.max_error)
      bound.best_max = std::move(s);
    else
      infeasible = cap;
  }
  // The RMS: schedules that stay within rms_error_cap_factor of the max bound and complete
  // within rms_time_factor of its schedule's duration (lingering would dilute it without end).
  bound.best_rms =
      search.run(Objective::RmsError, options.rms_error_cap_factor * bound.best_max.max_error,
                 std::min(options.max_duration, options.rms_time_factor * bound.best_max.duration),
                 bound.states_expanded);
  // The plan: the RMS search again, in the tighter tube.
  bound.plan =
      search.run(Objective::RmsError, options.plan_error_cap_factor * bound.best_max.max_error,
                 std::min(options.max_duration, options.rms_time_factor * bound.best_max.duration),
                 bound.states_expanded);
  // Each schedule found is a candidate for the others' objectives (a pruned search is not
  // monotone in its tube: the tighter one has found a smaller RMS).
  if (!bound.plan.complete || bound.best_max.rms_error < bound.plan.rms_error)
    bound.plan = bound.best_max;
  if (!bound.best_rms.complete || bound.plan.rms_error < bound.best_rms.rms_error)
    bound.best_rms = bound.plan;
  return bound;
}

}  // namespace flagella::control
