// Euler–Bernoulli beam model of a multi-tail robot in a resistive medium (docs/model.md 6, Ch.3).
//
// Each tail is a cantilever clamped on the spinning plate at radius R_d. It is loaded by RFT drag
// (docs/model.md 2) and satisfies EI w'''' = p(w') with w(0) = w'(0) = 0 and w''(L) = w'''(L) = 0.
// The nonlinearity of the "small-slope elastica" lives only in the loads p, q through w'. The tail
// forces are balanced against the Stokes-law head drag (docs/model.md 3.1, 6), with the motor
// constraint omega_T = omega_h + omega_t. All rates and speeds are magnitudes [CORR-15].
#pragma once

#include <string>
#include <vector>

#include "flagella_sim/effects/rft_coefficients.h"

namespace flagella::beam {

/// Robot and medium parameters of the beam model (docs/model.md 6, 8.1, 8.2). SI units.
struct BeamDesign {
  int n_tails = 0;              ///< n_t, number of tails (>= 1)
  double tail_length = 0.0;     ///< L [m]
  double tail_radius = 0.0;     ///< r0 [m]
  double youngs_modulus = 0.0;  ///< E [Pa]; EI = E pi r0^4 / 4
  double disc_radius = 0.0;     ///< R_d [m], tail attachment radius
  double head_radius = 0.0;     ///< a [m]
  double C_t = 0.0;             ///< head translational drag prefactor
  double C_r = 0.0;             ///< head rotational drag prefactor
  double viscosity = 0.0;       ///< mu [Pa s]
  RftLogForm log_form = RftLogForm::kTwoLengthOverRadius;
  /// Keep the tail's drag due to the head speed in the thrust load q (the eta_t v_h L term of the
  /// linear force balance, docs/model.md 6 / [CORR-14]). false = the dissertation's simplification,
  /// which sets v_h = 0 inside q (v_h still enters the lateral load p in the kNonlinear regime).
  bool include_tail_axial_drag = true;
};

/// LB, NLB and NLB w/o head of docs/model.md 6.
enum class BeamRegime {
  kLinear,                ///< drop the w'^2 terms: p = eta_p V
  kNonlinear,             ///< full loads p(w'), q(w')
  kNonlinearWithoutHead,  ///< full loads with v_h = 0 inside p and q
};

std::string toString(BeamRegime regime);

/// Numerical settings of the shooting BVP solver and of the balance root finds.
struct BeamSolverOptions {
  int num_steps = 400;  ///< RK4 steps along the tail (the w(y) output has num_steps+1 nodes)
  double bvp_tolerance = 1e-10;      ///< shooting residual relative to the slope scale p L^3 / EI
  int max_bvp_iterations = 50;       ///< Newton iterations on (w''(0), w'''(0))
  double balance_tolerance = 1e-13;  ///< relative tolerance on omega_t and v_h
  int max_balance_iterations = 200;  ///< iterations of each bracketed 1-D root find
};

/// Loads on one clamped tail at a given tail spin and head speed.
struct FlagellumLoads {
  double lateral_force = 0.0;     ///< F_x = int_0^L p dy per tail [N]
  double propulsive_force = 0.0;  ///< F_p = int_0^L q dy per tail, along -y, positive = thrust [N]
  double tip_deflection = 0.0;    ///< w(L) [m]
  std::vector<double> y, w;       ///< deflection profile on the RK4 nodes
  bool converged = false;
  int iterations = 0;   ///< Newton iterations of the shooting method
  std::string message;  ///< reason for non-convergence (empty when converged)
};

/// Solves the tail BVP EI w'''' = p(w') (docs/model.md 6) by RK4 shooting with Newton on w''(0),
/// w'''(0). omega_t >= 0 [rad/s]; v_h [m/s] is the head speed toward -y.
FlagellumLoads solveFlagellum(const BeamDesign& design, double omega_t, double v_h,
                              BeamRegime regime, const BeamSolverOptions& options = {});

/// Steady state of the whole robot at motor speed omega_T.
struct BeamSolution {
  double omega_T = 0.0;                  ///< motor speed [rad/s] (input)
  double omega_t = 0.0;                  ///< tail (plate) spin [rad/s]
  double omega_h = 0.0;                  ///< head spin [rad/s]
  double speed = 0.0;                    ///< head speed v_h toward -y [m/s]
  double tip_deflection = 0.0;           ///< w(L) [m]
  double relative_tip_deflection = 0.0;  ///< w(L) / L
  double propulsive_force = 0.0;         ///< F_p per tail [N]
  double lateral_force = 0.0;            ///< F_x per tail [N]
  int iterations = 0;                    ///< iterations of the outer (torque) root find
  bool converged = false;
  std::string message;
};

/// Solves the torque, force and motor balances of docs/model.md 6 numerically (nested bracketed
/// root finds for omega_t and v_h around the shooting BVP). Every regime, kLinear included, uses
/// the BVP. omega_T >= 0 [rad/s].
BeamSolution solveBeamModel(const BeamDesign& design, double omega_T, BeamRegime regime,
                            const BeamSolverOptions& options = {});

/// Closed-form LB solution of docs/model.md 6 (honours include_tail_axial_drag).
BeamSolution linearBeamClosedForm(const BeamDesign& design, double omega_T);

/// EI = E pi r0^4 / 4 [N m^2] (docs/model.md 6).
double bendingStiffness(const BeamDesign& design);

/// Throws std::invalid_argument naming the offending field and its allowed range.
void validateBeamDesign(const BeamDesign& design);
void validateBeamSolverOptions(const BeamSolverOptions& options);

}  // namespace flagella::beam
