#include "flagella_sim/effects/rss_hydrodynamics.h"

#include <cmath>
#include <stdexcept>

namespace flagella {

RssHydrodynamics::RssHydrodynamics(double filament_radius, bool implicit)
    : Effect(kName, rssHydrodynamicsEffect().parameters),
      implicit_(implicit),
      filament_radius_(filament_radius) {
  eps_ratio_ = parameterIndex("eps_ratio");
  eps_ = parameterIndex("eps", params_[eps_ratio_] * filament_radius);
  reuse_tolerance_ = parameterIndex("reuse_tolerance");
  last_eps_ = params_[eps_];
  last_ratio_ = params_[eps_ratio_];
}

double RssHydrodynamics::currentEps() {
  // The parameter set last wins: a config (or a running session) gives eps or eps_ratio. Until
  // either changes, eps = eps_ratio r0 both ways.
  if (params_[eps_] != last_eps_)
    relative_ = false;
  else if (params_[eps_ratio_] != last_ratio_)
    relative_ = true;
  if (relative_) params_.set("eps", params_[eps_ratio_] * filament_radius_, "effects.rss");
  last_eps_ = params_[eps_];
  last_ratio_ = params_[eps_ratio_];
  return params_[eps_];
}

namespace {
// eps_ratio = sqrt(e): a line of regularized Stokeslets with eps = sqrt(e) r0 has the resistance of
// a slender filament of radius r0 (docs/model.md 4.5).
const double kDefaultEpsRatio = std::sqrt(std::exp(1.0));
// Rigid reuse of the RSS factorisation (docs/model.md 4.4): see README, step cost.
constexpr double kDefaultReuseTolerance = 1e-3;

std::unique_ptr<RssHydrodynamics> makeRss(const EffectBuildContext& c) {
  if (!(c.medium.viscosity() > 0.0))
    throw ConfigError("effects.rss needs medium.viscosity > 0 (Stokes flow), got " +
                      formatNumber(c.medium.viscosity()));
  return std::make_unique<RssHydrodynamics>(c.robot.filament_radius,
                                            c.spec.option("coupling") == "implicit");
}
}  // namespace

const EffectDescriptor& rssHydrodynamicsEffect() {
  static const EffectDescriptor d = [] {
    EffectDescriptor e;
    e.name = RssHydrodynamics::kName;
    e.description = "regularized Stokeslet segments on the tails (nonlocal viscous drag)";
    e.options = {{"coupling",
                  "implicit",
                  {"implicit", "explicit"},
                  "implicit: dense Jacobian block, frozen geometry (docs/model.md 4.4 B); "
                  "explicit: force from the previous step's velocities (4.4 A, needs small dt)"}};
    e.parameters = {
        {"eps", 2.6e-3, 1e-7, 0.1, "m",
         "regularisation eps (default eps_ratio r0, docs/model.md 4.5)"},
        {"eps_ratio", kDefaultEpsRatio, 0.05, 20.0, "",
         "eps / robot.filament_radius, used unless eps is given (default sqrt(e), docs/model.md "
         "4.5; the value a gimbal threshold table calibrates)"},
        {"reuse_tolerance", kDefaultReuseTolerance, 0.0, 0.1, "",
         "a step reuses the factored RSS matrix, rotated, while the nodes are a rigid motion of "
         "those it was built at to within this fraction of eps (docs/model.md 4.4); 0: rebuilt "
         "every step"}};
    e.default_rules = {{"eps", "eps_ratio robot.filament_radius"}};
    e.exclusive_parameters = {{"eps", "eps_ratio"}};
    e.make = [](const EffectBuildContext& c) -> EffectPtr { return makeRss(c); };
    return e;
  }();
  return d;
}

void RssHydrodynamics::attach(const RodNetwork& net) {
  nodes_.clear();
  segments_.clear();
  for (const std::vector<int>& chain : net.parts.tail_nodes) {
    const int first = static_cast<int>(nodes_.size());
    for (size_t k = 0; k < chain.size(); ++k) {
      nodes_.push_back(chain[k]);
      if (k > 0)
        segments_.push_back({first + static_cast<int>(k) - 1, first + static_cast<int>(k)});
    }
  }
  if (segments_.empty())
    throw ConfigError("effects.rss: the robot has no tail or flagellum nodes to act on");
  dofs_.clear();
  for (int node : nodes_)
    for (int a = 0; a < 3; ++a) dofs_.push_back(RodNetwork::positionIndex(node) + a);
  any_fixed_ = false;
  for (int dof : dofs_) any_fixed_ = any_fixed_ || net.fixed_dof[dof];
}

VecX RssHydrodynamics::gather(const VecX& q) const {
  VecX x(dofs_.size());
  for (size_t i = 0; i < dofs_.size(); ++i) x(i) = q(dofs_[i]);
  return x;
}

void RssHydrodynamics::beginStep(const StepStart& start) {
  rss::Polyline polyline;
  for (int node : nodes_) polyline.push_back(nodePosition(start.state.q, node));
  try {
    if (solver_) {  // storage reused
      reused_ += solver_->updateOrReuse(polyline, segments_, currentEps(), start.viscosity,
                                        params_[reuse_tolerance_]);
      ++steps_;
    } else {
      solver_.emplace(polyline, segments_, currentEps(), start.viscosity);
      solver_->setLazyFactorization(implicit_);  // from the second step on (docs/model.md 4.4)
    }
    following_ = false;  // a new Ablk
    step_dt_ = start.dt;
    if (!implicit_)
      explicit_force_ = solver_->nodalForces(gather(start.state.qdot));  // docs/model.md 4.4 A
  } catch (const std::invalid_argument& e) {
    solver_.reset();
    throw std::runtime_error(std::string("effects.rss at t = ") + std::to_string(start.state.time) +
                             " s: " + e.what());
  }
}

void RssHydrodynamics::addForce(const EffectContext& ctx, VecX& force,
                                JacobianSink* /*jacobian*/) const {
  if (implicit_ && !solver_) throw std::logic_error("effects.rss: force asked before beginStep");
  if (!implicit_) {  // docs/model.md 4.4 option A: F^hyd fixed over the step
    for (size_t i = 0; i < dofs_.size(); ++i) force(dofs_[i]) += explicit_force_(i);
    return;
  }
  // docs/model.md 4.4 option B: F^hyd = -K (x - x(t_k))/dt = -diag(8 pi mu l_p) g / dt
  const VecX& g = preimageAt(gather(ctx.q), ctx.q_start);
  const VecX w = solver_->dragRowWeights();
  for (size_t i = 0; i < dofs_.size(); ++i) force(dofs_[i]) -= w(i) * g(i) / ctx.dt;
}

const VecX& RssHydrodynamics::preimageAt(const VecX& x, const VecX& q_start) const {
  if (following_ && x == followed_x_) return followed_g_;
  followed_g_ = solver_->solveWith(x - gather(q_start));
  followed_x_ = x;
  following_ = true;
  ++force_solves_;
  return followed_g_;
}

void RssHydrodynamics::predictIterate(const RodState& start, double dt, VecX& q) {
  // docs/model.md 4.4: the first iterate from g extrapolated over the last two steps,
  // x = x_k + Ablk g (the stepper's predictor extrapolates x instead)
  const bool chained = solver_ && implicit_ && !any_fixed_ && last_.valid &&
                       last_.end == start.time && last_.dt == dt;
  if (!chained) return;
  VecX g = last_.g;
  if (before_last_.valid && before_last_.end == last_.start && before_last_.dt == dt)
    g = 2.0 * last_.g - before_last_.g;
  const VecX x = gather(start.q) + solver_->multiply(g);
  for (size_t i = 0; i < dofs_.size(); ++i) q(dofs_[i]) = x(i);
  followed_x_ = x;
  followed_g_ = std::move(g);
  following_ = true;
}

void RssHydrodynamics::noteMappedUpdate(const VecX& previous, const VecX& q, const VecX& preimage,
                                        const FactoredMatrix* mapped, double scale) {
  // q -= C z moved the RSS positions by Ablk z / alpha: g -= z / alpha (docs/model.md 4.4),
  // from the followed iterate only
  if (!following_ || !solver_ || mapped != &*solver_ || gather(previous) != followed_x_) {
    following_ = false;
    return;
  }
  for (size_t i = 0; i < dofs_.size(); ++i) followed_g_(i) -= preimage(dofs_[i]) / scale;
  followed_x_ = gather(q);
}

void RssHydrodynamics::acceptStep(const RodNetwork& /*net*/, const RodState& start,
                                  const RodState& end) {
  if (!implicit_ || !solver_) return;
  before_last_ = std::move(last_);
  last_.g = preimageAt(gather(end.q), start.q);
  last_.start = start.time;
  last_.end = end.time;
  last_.dt = step_dt_;
  last_.valid = true;
}

void RssHydrodynamics::addDenseJacobian(const EffectContext& ctx, DenseJacobianSink& sink) const {
  if (!solver_) throw std::logic_error("effects.rss: Jacobian asked before beginStep");
  // dF/dx = -K/dt = -(1/dt) diag(8 pi mu l_p) Ablk^{-1} (docs/model.md 4.4 B)
  sink.addScaledInverse(dofs_, *solver_, solver_->dragRowWeights(), -1.0 / ctx.dt);
}

}  // namespace flagella
