// Settings of the implicit Euler / Newton-Raphson step (docs/model.md 1.10).
#pragma once

namespace flagella {

struct NewtonOptions {
  /// Converged when max_i |f_i| / scale_i < residual_tolerance, with scale_i = force_scale for
  /// position rows and moment_scale for twist rows (a scale-aware test, docs/model.md 1.10).
  /// Default 1e-4: on the shipped robots the summary metrics then differ from a 1e-9 solve by
  /// about 1e-5 relative, while Newton needs about half the iterations of 1e-6.
  double residual_tolerance = 1e-4;
  /// Also converged when the Newton update is this small relative to the length scale (rows
  /// already at round-off level) and the residual is within 1e3 x tolerance; in the damped
  /// retry too, where such an update is taken whole (no line search below the round-off floor).
  double step_tolerance = 1e-12;
  int max_iterations = 25;
  /// A step whose plain Newton iteration fails is first retried at the same dt with a
  /// backtracking line search on the scaled residual (it breaks the two-cycles Newton falls into
  /// on a regularised sign function, e.g. granular jamming at a stop). Steps that converge
  /// without it are not affected.
  bool damped_retry = true;
  /// Plain Newton is handed to the damped retry as stagnating when, from its fourth update on,
  /// the scaled residual has not fallen by half per two updates over the last this many updates
  /// (residual > 0.5^(n/2) x the residual n updates earlier) while still far from the tolerance.
  /// 2 (default): not halved in two updates. A longer window lets a Newton iteration that
  /// alternates between a large and a falling residual, as on a robot turning tens of degrees per
  /// step, converge on its own; a two-cycle is still caught, n/2 updates later at most
  /// (docs/model.md 1.10).
  int stagnation_updates = 2;
  static constexpr int kMinStagnationUpdates = 2, kMaxStagnationUpdates = 12;
  /// On failure the step is split in two halves, recursively, up to this depth (2^depth pieces).
  int max_subdivision_depth = 6;
  double force_scale = 1.0;   ///< [N], e.g. EI/L^2 of a flexible tail
  double moment_scale = 1.0;  ///< [N m], e.g. EI/L
  double length_scale = 1.0;  ///< [m], e.g. tail length
  /// Modified Newton (docs/model.md 1.10): the factored Jacobian serves the next update (a chord
  /// step) when the last update reduced the scaled residual by at least this factor; otherwise,
  /// and always in the damped retry, it is rebuilt and refactored at the current iterate (a chord
  /// update that raised the residual is undone first). 0: a fresh Jacobian for every update. The
  /// convergence test is the same either way, so only the iteration path changes.
  double jacobian_reuse = 0.1;
  /// Newton-Krylov updates for a dense Newton system (docs/model.md 4.4): each update of a plain
  /// attempt solves the Jacobian at the current iterate by GMRES preconditioned with the last
  /// factored one (kept across steps of the same dt and viscosity), to 0.1 x residual_tolerance
  /// in the scaled norm, in at most this many products; the Jacobian is refactored when GMRES
  /// does not get there, or for the next update when it needed more than half of them. 0: every
  /// update factors the Jacobian at its iterate (and chord steps as jacobian_reuse says). The
  /// convergence test is the same either way.
  int krylov_iterations = 12;
  /// Initial guess q(t_k) + dt qdot(t_k) (public group code) instead of q(t_k); when the step
  /// continues the last accepted one with the same dt, the rate is extrapolated linearly from the
  /// last two steps, q(t_k) + dt (2 qdot(t_k) - qdot(t_{k-1})) (docs/model.md 1.10).
  bool extrapolate_initial_guess = true;
  /// With that history, each node's position is extrapolated as a turn at the rate of its last
  /// two chords instead (rotatingChordPrediction, docs/model.md 1.10): exact for nodes on steady
  /// circles, as on a rotating flagellum. Twists stay linear. The convergence test is the same.
  bool rotating_predictor = false;
  /// Sparse linear solve by the 4x4-block LU (a node's coordinates with an edge's twist per
  /// block, no pivoting across blocks, KLU when it refuses its pivots); false: KLU always. Both
  /// solve the same system, to round-off (docs/model.md 1.10).
  bool block_lu = true;
  /// Dense Newton systems (docs/model.md 4.4): the sparse DOFs (twists, head) are condensed out
  /// and only the Schur complement on the flagellum positions is factored densely, falling back
  /// to the whole matrix when a block is near singular; false: always the whole matrix. Both
  /// solve the same system, to round-off.
  bool condensed_dense_lu = true;
  /// Print every Newton iterate's scaled residual to stderr.
  bool trace = false;
};

}  // namespace flagella
