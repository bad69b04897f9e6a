// One clamped tail of the beam model (docs/model.md 6): EI w'''' = p(w'), w(0) = w'(0) = 0,
// w''(L) = w'''(L) = 0, solved by RK4 shooting on (w''(0), w'''(0)) with Newton. The Jacobian comes
// from the variational equations, integrated with the same RK4 steps, so it is the exact
// derivative of the discrete shooting map and Newton converges quadratically.
#include <Eigen/Dense>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "flagella_sim/beam/euler_bernoulli_beam.h"

namespace flagella::beam {
namespace {

// State layout: the deflection and its first three derivatives, the running load integrals, and
// the sensitivities of (w, w', w'', w''') to the shooting unknowns A = w''(0) and B = w'''(0).
constexpr int kW = 0, kSlope = 1, kCurvature = 2, kShear = 3, kLateral = 4, kThrust = 5;
constexpr int kSensA = 6, kSensB = 10, kStateSize = 14;
using State = Eigen::Matrix<double, kStateSize, 1>;

constexpr int kMaxLineSearchHalvings = 30;

// Per-length RFT loads on the tail as functions of the slope s = w' (docs/model.md 6).
struct TailLoads {
  bool linear = false;
  double eta_t = 0.0, eta_p = 0.0;
  double V = 0.0;          // omega_t R_d
  double v_lateral = 0.0;  // head speed seen by p
  double v_axial = 0.0;    // head speed seen by q

  // docs/model.md 6: p = eta_p V + (eta_t - eta_p)(V s^2 + v_h s)/(1 + s^2); LB: p = eta_p V.
  double p(double s) const {
    if (linear) return eta_p * V;
    return eta_p * V + (eta_t - eta_p) * (V * s * s + v_lateral * s) / (1.0 + s * s);
  }
  double dpds(double s) const {
    if (linear) return 0.0;
    const double denom = 1.0 + s * s;
    return (eta_t - eta_p) * (2.0 * V * s + v_lateral * (1.0 - s * s)) / (denom * denom);
  }
  // docs/model.md 6: q = (eta_p - eta_t)(V s + v_h)/(1 + s^2) - eta_p v_h; LB drops the s^2.
  double q(double s) const {
    const double denom = linear ? 1.0 : 1.0 + s * s;
    return (eta_p - eta_t) * (V * s + v_axial) / denom - eta_p * v_axial;
  }
  // Upper bound of |p|, used to scale the shooting residual.
  double scale() const {
    return eta_p * std::abs(V) + (linear ? 0.0 : std::abs(eta_p - eta_t) * std::abs(v_lateral));
  }
};

TailLoads makeTailLoads(const BeamDesign& design, double omega_t, double v_h, BeamRegime regime) {
  const RftCoefficients eta =
      rftCoefficients(design.viscosity, design.tail_length, design.tail_radius, design.log_form);
  TailLoads loads;
  loads.eta_t = eta.eta_t;
  loads.eta_p = eta.eta_p;
  loads.V = omega_t * design.disc_radius;  // docs/model.md 6: V = omega_t R_d
  loads.linear = regime == BeamRegime::kLinear;
  const bool head_moves = regime != BeamRegime::kNonlinearWithoutHead;
  loads.v_lateral = head_moves ? v_h : 0.0;
  loads.v_axial = head_moves && design.include_tail_axial_drag ? v_h : 0.0;
  return loads;
}

class ShootingProblem {
 public:
  ShootingProblem(const TailLoads& loads, double EI, double length, int steps)
      : loads_(loads), EI_(EI), length_(length), steps_(steps) {}

  double length() const { return length_; }

  // Integrates from y = 0 with w''(0) = A, w'''(0) = B; optionally records w at the nodes.
  State integrate(const Eigen::Vector2d& shoot, std::vector<double>* w = nullptr) const {
    State s = State::Zero();
    s[kCurvature] = shoot[0];
    s[kShear] = shoot[1];
    s[kSensA + kCurvature] = 1.0;
    s[kSensB + kShear] = 1.0;
    const double h = length_ / steps_;
    if (w) w->assign(1, 0.0);
    for (int i = 0; i < steps_; ++i) {
      const State k1 = derivative(s);
      const State k2 = derivative(s + 0.5 * h * k1);
      const State k3 = derivative(s + 0.5 * h * k2);
      const State k4 = derivative(s + h * k3);
      s += (h / 6.0) * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
      if (w) w->push_back(s[kW]);
    }
    return s;
  }

  // Dimensionless free-end residual (L w''(L), L^2 w'''(L)); zero at the solution.
  Eigen::Vector2d residual(const State& end) const {
    return {length_ * end[kCurvature], length_ * length_ * end[kShear]};
  }

  Eigen::Matrix2d jacobian(const State& end) const {
    Eigen::Matrix2d J;
    J << end[kSensA + kCurvature], end[kSensB + kCurvature], end[kSensA + kShear],
        end[kSensB + kShear];
    J.row(0) *= length_;
    J.row(1) *= length_ * length_;
    return J;
  }

  // Shooting values of the linear (constant-load) solution, docs/model.md 6: w''(0) = p L^2/(2EI),
  // w'''(0) = -p L/EI.
  Eigen::Vector2d linearGuess() const {
    const double p0 = loads_.p(0.0);
    return {p0 * length_ * length_ / (2.0 * EI_), -p0 * length_ / EI_};
  }

  // Slope scale p L^3 / EI of the deflection.
  double slopeScale() const { return loads_.scale() * length_ * length_ * length_ / EI_; }

 private:
  State derivative(const State& s) const {
    State d = State::Zero();
    const double slope = s[kSlope];
    const double p = loads_.p(slope);
    d[kW] = s[kSlope];
    d[kSlope] = s[kCurvature];
    d[kCurvature] = s[kShear];
    d[kShear] = p / EI_;           // docs/model.md 6: EI w'''' = p
    d[kLateral] = p;               // F_x = int p dy
    d[kThrust] = loads_.q(slope);  // F_p = int q dy
    const double dp = loads_.dpds(slope) / EI_;
    for (const int offset : {kSensA, kSensB}) {
      d[offset + kW] = s[offset + kSlope];
      d[offset + kSlope] = s[offset + kCurvature];
      d[offset + kCurvature] = s[offset + kShear];
      d[offset + kShear] = dp * s[offset + kSlope];
    }
    return d;
  }

  TailLoads loads_;
  double EI_, length_;
  int steps_;
};

struct NewtonStep {
  bool accepted = false;
  Eigen::Vector2d shoot;
  State end;
  double residual_norm = 0.0;
};

// Backtracking line search along the Newton direction: accept the first step that lowers the
// residual norm.
NewtonStep lineSearch(const ShootingProblem& problem, const Eigen::Vector2d& shoot,
                      const Eigen::Vector2d& direction, double current_norm) {
  double lambda = 1.0;
  for (int k = 0; k <= kMaxLineSearchHalvings; ++k, lambda *= 0.5) {
    NewtonStep trial;
    trial.shoot = shoot + lambda * direction;
    trial.end = problem.integrate(trial.shoot);
    if (!trial.end.allFinite()) continue;
    trial.residual_norm = problem.residual(trial.end).norm();
    if (trial.residual_norm < current_norm) {
      trial.accepted = true;
      return trial;
    }
  }
  return {};
}

std::string describe(double value) {
  std::ostringstream out;
  out.precision(6);
  out << value;
  return out.str();
}

}  // namespace

FlagellumLoads solveFlagellum(const BeamDesign& design, double omega_t, double v_h,
                              BeamRegime regime, const BeamSolverOptions& options) {
  validateBeamDesign(design);
  validateBeamSolverOptions(options);
  if (!std::isfinite(omega_t) || omega_t < 0.0)
    throw std::invalid_argument("omega_t must be finite and >= 0 rad/s (got " + describe(omega_t) +
                                ")");
  if (!std::isfinite(v_h))
    throw std::invalid_argument("v_h must be finite (got " + describe(v_h) + ")");
  toString(regime);  // throws on an invalid enumerator

  const ShootingProblem problem(makeTailLoads(design, omega_t, v_h, regime),
                                bendingStiffness(design), design.tail_length, options.num_steps);
  const double tolerance = options.bvp_tolerance * problem.slopeScale();

  FlagellumLoads out;
  Eigen::Vector2d shoot = problem.linearGuess();
  State end = problem.integrate(shoot);
  double norm = problem.residual(end).norm();
  while (!(norm <= tolerance)) {
    if (out.iterations >= options.max_bvp_iterations) {
      out.message = "tail BVP: Newton did not converge in " +
                    std::to_string(options.max_bvp_iterations) + " iterations (scaled residual " +
                    describe(norm) + ")";
      break;
    }
    const Eigen::Vector2d direction =
        problem.jacobian(end).fullPivLu().solve(-problem.residual(end));
    const NewtonStep step =
        direction.allFinite() ? lineSearch(problem, shoot, direction, norm) : NewtonStep{};
    ++out.iterations;
    if (!step.accepted) {
      out.message = "tail BVP: line search failed to reduce the residual (scaled residual " +
                    describe(norm) + ")";
      break;
    }
    shoot = step.shoot;
    end = step.end;
    norm = step.residual_norm;
  }
  out.converged = out.message.empty();
  problem.integrate(shoot, &out.w);
  out.y.resize(out.w.size());
  for (size_t i = 0; i < out.y.size(); ++i)
    out.y[i] = problem.length() * static_cast<double>(i) / options.num_steps;
  out.tip_deflection = end[kW];
  out.lateral_force = end[kLateral];
  out.propulsive_force = end[kThrust];
  return out;
}

}  // namespace flagella::beam
