// Robot-level balances of the beam model (docs/model.md 6): closed-form LB and the numerical solve
// (nested bracketed root finds for omega_t and v_h around the tail BVP of flagellum_bvp.cpp).
#include "flagella_sim/beam/euler_bernoulli_beam.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace flagella::beam {
namespace {

constexpr int kMinSteps = 4;
constexpr int kMaxBracketExpansions = 60;

std::string describe(double value) {
  std::ostringstream out;
  out.precision(6);
  out << value;
  return out.str();
}

void requirePositive(double value, const std::string& field, const std::string& unit) {
  if (!(value > 0.0) || !std::isfinite(value))
    throw std::invalid_argument(field + " must be finite and > 0" + unit + " (got " +
                                describe(value) + ")");
}

void requireNonNegative(double value, const std::string& field, const std::string& unit) {
  if (!(value >= 0.0) || !std::isfinite(value))
    throw std::invalid_argument(field + " must be finite and >= 0" + unit + " (got " +
                                describe(value) + ")");
}

// Stokes-law head drag coefficients (docs/model.md 3.1).
struct HeadDrag {
  double translational = 0.0;  // C_t 6 pi mu a
  double rotational = 0.0;     // C_r 8 pi mu a^3
};

HeadDrag headDrag(const BeamDesign& d) {
  const double a = d.head_radius;
  return {d.C_t * 6.0 * M_PI * d.viscosity * a, d.C_r * 8.0 * M_PI * d.viscosity * a * a * a};
}

struct RootResult {
  double x = 0.0;
  int iterations = 0;
  bool converged = false;
};

// Brent's method on a bracket [a, b] with f(a), f(b) of opposite sign (or one of them zero).
template <class Function>
RootResult brentRoot(Function&& f, double a, double b, double fa, double fb, double xtol,
                     int max_iterations) {
  constexpr double kEps = std::numeric_limits<double>::epsilon();
  double c = b, fc = fb, d = b - a, e = d;
  RootResult result;
  for (result.iterations = 0; result.iterations < max_iterations; ++result.iterations) {
    if ((fb > 0.0 && fc > 0.0) || (fb < 0.0 && fc < 0.0)) {
      c = a;
      fc = fa;
      d = e = b - a;
    }
    if (std::abs(fc) < std::abs(fb)) {
      a = b, b = c, c = a;
      fa = fb, fb = fc, fc = fa;
    }
    const double tol = 2.0 * kEps * std::abs(b) + 0.5 * xtol;
    const double half = 0.5 * (c - b);
    if (std::abs(half) <= tol || fb == 0.0) {
      result.x = b;
      result.converged = true;
      return result;
    }
    if (std::abs(e) >= tol && std::abs(fa) > std::abs(fb)) {
      // Inverse quadratic interpolation, or secant when only two points are distinct.
      const double s = fb / fa;
      double p, q;
      if (a == c) {
        p = 2.0 * half * s;
        q = 1.0 - s;
      } else {
        const double qa = fa / fc, r = fb / fc;
        p = s * (2.0 * half * qa * (qa - r) - (b - a) * (r - 1.0));
        q = (qa - 1.0) * (r - 1.0) * (s - 1.0);
      }
      if (p > 0.0) q = -q;
      p = std::abs(p);
      if (2.0 * p < std::min(3.0 * half * q - std::abs(tol * q), std::abs(e * q))) {
        e = d;
        d = p / q;
      } else {
        d = half;
        e = d;
      }
    } else {
      d = half;
      e = d;
    }
    a = b;
    fa = fb;
    b += std::abs(d) > tol ? d : std::copysign(tol, half);
    fb = f(b);
  }
  result.x = b;
  return result;
}

bool oppositeSigns(double fa, double fb) { return fa == 0.0 || fb == 0.0 || (fa < 0) != (fb < 0); }

struct SpeedResult {
  double v_h = 0.0;
  FlagellumLoads loads;
  bool converged = false;
  std::string message;
};

// Force balance n_t F_p(omega_t, v_h) = C_t 6 pi mu a v_h for v_h at fixed omega_t (docs/model.md
// 6).
SpeedResult solveSpeed(const BeamDesign& design, double omega_t, BeamRegime regime,
                       const BeamSolverOptions& options, const HeadDrag& head) {
  std::string failure;
  auto residual = [&](double v_h) {
    const FlagellumLoads loads = solveFlagellum(design, omega_t, v_h, regime, options);
    if (!loads.converged && failure.empty()) failure = loads.message;
    return design.n_tails * loads.propulsive_force - head.translational * v_h;
  };
  SpeedResult out;
  const double g0 = residual(0.0);
  // F_p does not grow with v_h, so the root lies within [0, g(0)/(C_t 6 pi mu a)] in practice.
  double v_far = g0 / head.translational;
  double g_far = g0;
  for (int k = 0; g0 != 0.0 && k < kMaxBracketExpansions; ++k, v_far *= 2.0) {
    g_far = residual(v_far);
    if (oppositeSigns(g0, g_far)) break;
  }
  if (!oppositeSigns(g0, g_far)) {
    out.message = "force balance: no sign change of n F_p - C_t 6 pi mu a v_h found";
    return out;
  }
  const RootResult root =
      brentRoot(residual, 0.0, v_far, g0, g_far, options.balance_tolerance * std::abs(v_far),
                options.max_balance_iterations);
  out.v_h = root.x;
  out.loads = solveFlagellum(design, omega_t, out.v_h, regime, options);
  if (!out.loads.converged && failure.empty()) failure = out.loads.message;
  if (!root.converged && failure.empty())
    failure = "force balance: root find did not converge in " +
              std::to_string(options.max_balance_iterations) + " iterations";
  out.message = failure;
  out.converged = failure.empty();
  return out;
}

void fillFromLoads(const BeamDesign& design, double omega_t, const SpeedResult& speed,
                   BeamSolution& sol) {
  sol.omega_t = omega_t;
  sol.omega_h = sol.omega_T - omega_t;  // docs/model.md 6: omega_T = omega_h + omega_t
  sol.speed = speed.v_h;
  sol.tip_deflection = speed.loads.tip_deflection;
  sol.relative_tip_deflection = sol.tip_deflection / design.tail_length;
  sol.propulsive_force = speed.loads.propulsive_force;
  sol.lateral_force = speed.loads.lateral_force;
}

}  // namespace

std::string toString(BeamRegime regime) {
  switch (regime) {
    case BeamRegime::kLinear:
      return "LB";
    case BeamRegime::kNonlinear:
      return "NLB";
    case BeamRegime::kNonlinearWithoutHead:
      return "NLB w/o head";
  }
  throw std::invalid_argument("regime must be one of kLinear, kNonlinear, kNonlinearWithoutHead");
}

double bendingStiffness(const BeamDesign& design) {
  const double r0 = design.tail_radius;
  return design.youngs_modulus * M_PI * r0 * r0 * r0 * r0 /
         4.0;  // docs/model.md 6: EI = E pi r0^4/4
}

void validateBeamDesign(const BeamDesign& design) {
  if (design.n_tails < 1)
    throw std::invalid_argument("n_tails must be >= 1 (got " + std::to_string(design.n_tails) +
                                ")");
  requirePositive(design.tail_length, "tail_length", " m");
  requirePositive(design.tail_radius, "tail_radius", " m");
  requirePositive(design.youngs_modulus, "youngs_modulus", " Pa");
  requirePositive(design.disc_radius, "disc_radius", " m");
  requirePositive(design.head_radius, "head_radius", " m");
  requirePositive(design.C_t, "C_t", "");
  requirePositive(design.C_r, "C_r", "");
  requirePositive(design.viscosity, "viscosity", " Pa s");
  try {
    rftCoefficients(design.viscosity, design.tail_length, design.tail_radius, design.log_form);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("tail_length / tail_radius: " + std::string(e.what()));
  }
}

void validateBeamSolverOptions(const BeamSolverOptions& options) {
  if (options.num_steps < kMinSteps)
    throw std::invalid_argument("num_steps must be >= " + std::to_string(kMinSteps) + " (got " +
                                std::to_string(options.num_steps) + ")");
  requirePositive(options.bvp_tolerance, "bvp_tolerance", "");
  requirePositive(options.balance_tolerance, "balance_tolerance", "");
  if (options.max_bvp_iterations < 1)
    throw std::invalid_argument("max_bvp_iterations must be >= 1");
  if (options.max_balance_iterations < 1)
    throw std::invalid_argument("max_balance_iterations must be >= 1");
}

BeamSolution linearBeamClosedForm(const BeamDesign& design, double omega_T) {
  validateBeamDesign(design);
  requireNonNegative(omega_T, "omega_T", " rad/s");
  const RftCoefficients eta =
      rftCoefficients(design.viscosity, design.tail_length, design.tail_radius, design.log_form);
  const double n = design.n_tails, L = design.tail_length, Rd = design.disc_radius;
  const double EI = bendingStiffness(design);
  const HeadDrag head = headDrag(design);
  const double L4 = L * L * L * L;

  BeamSolution sol;
  sol.omega_T = omega_T;
  // docs/model.md 6 (LB): omega_h = n eta_p R_d^2 L omega_t / (8 pi C_r mu a^3)
  const double spin_ratio = n * eta.eta_p * Rd * Rd * L / head.rotational;
  sol.omega_t = omega_T / (1.0 + spin_ratio);
  sol.omega_h = spin_ratio * sol.omega_t;
  const double V = sol.omega_t * Rd;
  const double p = eta.eta_p * V;
  sol.lateral_force = p * L;                 // docs/model.md 6: F_x = eta_p omega_t R_d L
  sol.tip_deflection = p * L4 / (8.0 * EI);  // docs/model.md 6: w(L) = p L^4 / (8 EI)
  sol.relative_tip_deflection = sol.tip_deflection / L;
  // docs/model.md 6 / [CORR-14]: v_h = n (eta_p - eta_t) eta_p R_d^2 L^4 omega_t^2 / (8 EI (6 pi
  // C_t mu a
  // + n eta_t L)); the n eta_t L term is dropped in the dissertation's simplification.
  const double axial = design.include_tail_axial_drag ? n * eta.eta_t * L : 0.0;
  sol.speed = n * (eta.eta_p - eta.eta_t) * eta.eta_p * Rd * Rd * L4 * sol.omega_t * sol.omega_t /
              (8.0 * EI * (head.translational + axial));
  // docs/model.md 6: F_p = (eta_p - eta_t) omega_t R_d w(L) - eta_t v_h L
  sol.propulsive_force = (eta.eta_p - eta.eta_t) * V * sol.tip_deflection -
                         (design.include_tail_axial_drag ? eta.eta_t * sol.speed * L : 0.0);
  sol.converged = true;
  return sol;
}

BeamSolution solveBeamModel(const BeamDesign& design, double omega_T, BeamRegime regime,
                            const BeamSolverOptions& options) {
  validateBeamDesign(design);
  validateBeamSolverOptions(options);
  requireNonNegative(omega_T, "omega_T", " rad/s");
  toString(regime);  // throws on an invalid enumerator

  BeamSolution sol;
  sol.omega_T = omega_T;
  if (omega_T == 0.0) {
    sol.converged = true;
    return sol;
  }
  const HeadDrag head = headDrag(design);
  std::string failure;
  // docs/model.md 6 torque balance: n_t R_d F_x(omega_t, v_h) = C_r 8 pi mu a^3 (omega_T - omega_t)
  auto torque_residual = [&](double omega_t) {
    const SpeedResult speed = solveSpeed(design, omega_t, regime, options, head);
    if (!speed.converged && failure.empty())
      failure = speed.message + " (at omega_t = " + describe(omega_t) + " rad/s)";
    return design.n_tails * design.disc_radius * speed.loads.lateral_force -
           head.rotational * (omega_T - omega_t);
  };
  const double f_low = torque_residual(0.0);
  const double f_high = torque_residual(omega_T);
  if (!oppositeSigns(f_low, f_high)) {
    sol.message = "torque balance: no sign change on omega_t in [0, omega_T]";
    return sol;
  }
  const RootResult root =
      brentRoot(torque_residual, 0.0, omega_T, f_low, f_high, options.balance_tolerance * omega_T,
                options.max_balance_iterations);
  const SpeedResult speed = solveSpeed(design, root.x, regime, options, head);
  if (!speed.converged && failure.empty()) failure = speed.message;
  if (!root.converged && failure.empty())
    failure = "torque balance: root find did not converge in " +
              std::to_string(options.max_balance_iterations) + " iterations";
  fillFromLoads(design, root.x, speed, sol);
  sol.iterations = root.iterations;
  sol.message = failure;
  sol.converged = failure.empty();
  return sol;
}

}  // namespace flagella::beam
