#include "flagella_sim/analysis/buckling_probe.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include "flagella_sim/core/units.h"
#include "flagella_sim/robots/flagellum_tilt.h"
#include "flagella_sim/simulation/simulation.h"
#include "flagella_sim/solver/solver_failure.h"

namespace flagella {

namespace {

SimulationConfig atConstantRate(const SimulationConfig& config, double rpm) {
  SimulationConfig c = config;
  c.motor.mode = "constant";
  c.motor.omega = (config.motor.omega < 0.0 ? -1.0 : 1.0) * rpm * units::kRadPerSecPerRpm;
  return c;
}

// A run gives up when the flagellum turns slower than the motor by more than this factor.
constexpr double kMaxTurnsPerMotorTurn = 20.0;

double secondsSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Tilt vectors sampled every `interval` until the flagellum has turned `turns` times (its twist
// angle theta^1 from the start), and when it had turned `settle_turns` times.
struct TiltRecord {
  std::vector<double> time;
  std::vector<Vec3> tilt;
  double max_tilt = 0.0;     // [rad]
  double settle_time = 0.0;  // [s]
  double turn_period = 0.0;  // mean flagellum turn after settle_time [s]
  std::string failure;       // the Newton failure that ended the record early, if any
};

TiltRecord recordTilt(Simulation& sim, double turns, double settle_turns, double interval,
                      double max_duration) {
  TiltRecord r;
  const SimulationConfig& c = sim.config();
  const std::vector<int> helix = helixNodes(sim.network().parts);
  const double per_turn = c.robotGeometry<HelicalGeometry>().edgesPerTurn();
  const int head_edge = sim.network().parts.head_edge;
  const int shaft_theta = sim.network().thetaIndex(sim.network().parts.shaft_edge);
  const double angle0 = sim.state().q(shaft_theta);
  const long every = std::max(1L, std::lround(interval / c.dt));
  double settle_angle = 0.0;
  bool settled = false;
  for (long k = 0;; ++k) {
    if (k > 0) {
      try {
        sim.step();
      } catch (const SolverFailure& e) {  // the caller decides what the record still shows
        r.failure = e.what();
        return r;
      }
    }
    const RodState& s = sim.state();
    const double turned = std::abs(s.q(shaft_theta) - angle0);
    if (!settled && turned >= 2.0 * M_PI * settle_turns)
      settled = true, r.settle_time = s.time, settle_angle = turned;
    const bool done = turned >= 2.0 * M_PI * turns;
    if (k % every == 0 || done) {
      const Vec3 v = flagellumTiltVector(s.q, helix, per_turn, s.frames.tangent[head_edge]);
      r.time.push_back(s.time);
      r.tilt.push_back(v);
      r.max_tilt = std::max(r.max_tilt, std::asin(std::min(1.0, v.norm())));
    }
    if (done) {
      r.turn_period = 2.0 * M_PI * (s.time - r.settle_time) / (turned - settle_angle);
      return r;
    }
    if (s.time > max_duration)
      throw std::runtime_error("growth rate: the flagellum turned less than " +
                               std::to_string(turns) + " times in " + std::to_string(max_duration) +
                               " s");
  }
}

}  // namespace

ThresholdProbe runBucklingProbe(const SimulationConfig& config, double rpm) {
  ThresholdProbe p;
  p.rate = rpm;
  const SimulationConfig c = atConstantRate(config, rpm);
  const auto t0 = std::chrono::steady_clock::now();
  try {
    Simulation sim(c);
    sim.run(c.duration);
    const SummaryMetrics m = sim.summary();
    p.above = m.buckled;
    p.indicator = units::radToDeg(m.flagellum_tilt_max);
  } catch (const std::exception& e) {  // SolverFailure, or an effect out of its domain
    p.failed = true;
    p.error = e.what();
  }
  p.wall_seconds = secondsSince(t0);
  return p;
}

void validate(const GrowthProbeOptions& o) {
  if (!(o.settle_turns >= 0.0 && o.settle_turns <= 1e4))
    throw std::invalid_argument("--settle-turns must be in [0, 1e4]");
  if (!(o.observe_turns >= o.settle_turns + 2.0 && o.observe_turns <= 1e5))
    throw std::invalid_argument("--observe-turns must be in [--settle-turns + 2, 1e5]");
  if (!(o.small_tilt_deg > 0.0 && o.small_tilt_deg < 45.0))
    throw std::invalid_argument("--small-tilt must be in (0, 45) deg");
  if (!(o.decay_limit > 0.0 && o.decay_limit < 1.0))
    throw std::invalid_argument("decay_limit must be in (0, 1)");
  if (!(o.decayed_before > 0.0 && o.decayed_before < 1.0))
    throw std::invalid_argument("decayed_before must be in (0, 1)");
  if (o.samples_per_period < 8 || o.samples_per_period > 1000)
    throw std::invalid_argument("samples_per_period must be in [8, 1000]");
}

GrowthProbe runGrowthProbe(const SimulationConfig& config, double rpm,
                           const GrowthProbeOptions& o) {
  validate(o);
  GrowthProbe p;
  p.rate = rpm;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    const SimulationConfig c = atConstantRate(config, rpm);
    if (!c.findRobotGeometry<HelicalGeometry>())
      throw std::invalid_argument("growth rate: needs a helical robot");
    Simulation sim(c);
    const double motor_turn = 60.0 / rpm;  // [s]
    const TiltRecord r =
        recordTilt(sim, o.observe_turns, o.settle_turns, motor_turn / o.samples_per_period,
                   kMaxTurnsPerMotorTurn * o.observe_turns * motor_turn);
    p.max_tilt_deg = units::radToDeg(r.max_tilt);
    if (!r.failure.empty()) {
      // Newton failed: in a flagellum already leaning past the small-tilt limit this is violent
      // buckling, growing for sure (a bound from the rise to the largest tilt); else a failure
      if (p.max_tilt_deg <= o.small_tilt_deg) throw std::runtime_error(r.failure);
      p.saturated = true;
      p.window_from = r.time.front();
      p.window_to = r.time.back();
      const double first = std::max(r.tilt[std::min<size_t>(1, r.tilt.size() - 1)].norm(), 1e-6);
      p.sigma = std::max(
          std::log(std::sin(r.max_tilt) / first) / std::max(p.window_to - p.window_from, c.dt),
          1e-12);
      p.error = "Newton failed after the tilt passed " + std::to_string(o.small_tilt_deg) +
                " deg: counted as growing (" + r.failure + ")";
      p.wall_seconds = secondsSince(t0);
      return p;
    }
    p.period = r.turn_period;
    const AmplitudeSeries slow = slowTiltAmplitude(r.time, r.tilt, p.period);
    const GrowthReading g =
        readGrowth(slow, r.settle_time, p.period, std::sin(units::degToRad(o.small_tilt_deg)),
                   o.decay_limit, o.decayed_before);
    if (!g.message.empty()) throw std::runtime_error("growth rate: " + g.message);
    p.sigma = g.sigma;
    p.sigma_error = g.error;
    p.window_from = g.from;
    p.window_to = g.to;
    p.saturated = g.grew_early;
    p.decayed = g.decayed_early;
  } catch (const std::exception& e) {  // SolverFailure, or an effect out of its domain
    p.failed = true;
    p.error = e.what();
  }
  p.wall_seconds = secondsSince(t0);
  return p;
}

}  // namespace flagella
