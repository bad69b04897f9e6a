#include "flagella_sim/simulation/simulation.h"

#include <cmath>

#include "flagella_sim/core/geometry.h"
#include "flagella_sim/core/units.h"
#include "flagella_sim/effects/com_offset.h"
#include "flagella_sim/effects/effect_registry.h"
#include "flagella_sim/effects/stokes_head_drag.h"
#include "flagella_sim/outputs/fits.h"
#include "flagella_sim/robots/flagellum_tilt.h"
#include "flagella_sim/rod/rod_kinematics.h"

namespace flagella {

namespace {

std::vector<EffectPtr> makeEffects(const SimulationConfig& c) {
  std::vector<EffectPtr> effects;
  const RobotDimensions robot = c.robotDimensions();
  for (const EffectSpec& spec : c.effects) effects.push_back(makeEffect(spec, c.medium, robot));
  return effects;
}

// Sample times are compared with this slack so round-off never skips a sample.
constexpr double kSampleTimeSlack = 1e-9;

}  // namespace

RodNetwork buildRobot(const SimulationConfig& config) { return config.robot->build(); }

std::shared_ptr<const MotorCommand> makeMotor(const MotorSpec& spec) {
  std::shared_ptr<const MotorCommand> motor;
  if (spec.mode == "binary")
    motor =
        std::make_shared<BinaryMotor>(spec.omega, spec.positive_duration, spec.negative_duration);
  else
    motor = std::make_shared<ConstantMotor>(spec.omega);
  if (spec.ramp_time > 0.0) motor = std::make_shared<RampedMotor>(motor, spec.ramp_time);
  return motor;
}

Simulation::Simulation(const SimulationConfig& config)
    : config_(config),
      stepper_(buildRobot(config), makeEffects(config), config.medium, config.solver),
      motor_(makeMotor(config.motor)),
      state_(stepper_.initialState()) {
  motor_.setSpeedLaws(stepper_.motorSpeedLaws());
  if (config.slider.enabled) {
    slider_couple_ = stepper_.findEffect<ComOffset>();
    if (!slider_couple_)
      throw ConfigError("slider: needs effects.com_offset (the couple it shifts)");
    neutral_offset_ = slider_couple_->parameters().get("offset");
    slider_.emplace(config.slider);
    applySliderOffset();
  }
  recordSample();
}

void Simulation::applySliderOffset() {
  ParameterSet& couple = slider_couple_->parameters();
  const double l = slider_->comOffset(neutral_offset_, couple.get("head_mass"));
  couple.set("offset", l, "effects.com_offset");  // docs/model.md 5
}

StepReport Simulation::step() {
  motor_.beginStep(state_.time, config_.dt);
  std::optional<SliderState> slider_before;  // l(t_{k+1}) for the step; put back if it fails
  if (slider_) {
    slider_before = slider_->state();
    slider_->advance(config_.dt);
    applySliderOffset();
  }
  StepReport r;
  try {
    r = stepper_.step(state_, config_.dt, motor_);
  } catch (...) {
    if (slider_) {
      slider_->restore(*slider_before);
      applySliderOffset();
    }
    throw;
  }
  newton_iterations_ += r.newton_iterations;
  subdivided_steps_ += r.substeps > 1;
  damped_steps_ += r.damped_retries;
  return r;
}

void Simulation::run(double duration, const std::function<void(double)>& progress) {
  const double t_start = state_.time;
  const long steps = std::lround(duration / config_.dt);
  try {
    for (long k = 0; k < steps; ++k) {
      step();
      if (state_.time + kSampleTimeSlack >= next_sample_time_) {
        recordSample();
        if (progress) progress((state_.time - t_start) / duration);
      }
    }
  } catch (const std::runtime_error&) {  // SolverFailure, or an effect out of its domain
    recordFinalSample();
    throw;
  }
  recordFinalSample();
  if (progress) progress(1.0);
}

TrajectorySample Simulation::sample() const {
  const RodNetwork& net = network();
  const RobotParts& parts = net.parts;
  TrajectorySample s;
  s.time = state_.time;
  s.head_position = nodePosition(state_.q, parts.head_center_node);
  s.head_velocity = state_.qdot.segment<3>(3 * parts.head_center_node);
  const Vec3 axis = state_.frames.tangent[parts.head_edge];
  s.head_axis = axis;
  const Vec3 m1 = materialDirector1(state_.frames, state_.q, net, parts.head_edge);
  s.head_orientation = quaternionFromFrame(m1, axis.cross(m1), axis);
  s.head_angle = state_.q(net.thetaIndex(parts.head_edge));
  s.tail_angle = state_.q(net.thetaIndex(parts.shaft_edge));
  s.omega_h = state_.qdot(net.thetaIndex(parts.head_edge));
  s.omega_t = state_.qdot(net.thetaIndex(parts.shaft_edge));
  s.omega_T = motor_.lastCommand();
  s.omega_motor = motor_.lastSpeed();
  // Yaw of the forward direction -t^0 about the vertical, and its exact rate from the
  // velocities of x_0, x_1: d(t)/dt = (I - t t^T)(v_1 - v_0)/|e^0|.
  const Vec3& up = stepper_.medium().up;
  const Vec3 e1 = anyPerpendicular(up);
  const Vec3 e2 = up.cross(e1);
  const Vec3 edge = nodePosition(state_.q, parts.head_center_node) -
                    nodePosition(state_.q, parts.head_front_node);
  const Vec3 edge_rate = state_.qdot.segment<3>(3 * parts.head_center_node) -
                         state_.qdot.segment<3>(3 * parts.head_front_node);
  const Vec3 axis_rate = (edge_rate - axis.dot(edge_rate) * axis) / edge.norm();
  const Vec3 forward_h = -(axis - axis.dot(up) * up);
  const Vec3 forward_rate_h = -(axis_rate - axis_rate.dot(up) * up);
  if (forward_h.squaredNorm() > 0.0) {
    s.yaw = std::atan2(forward_h.dot(e2), forward_h.dot(e1));
    s.yaw_rate = up.dot(forward_h.cross(forward_rate_h)) / forward_h.squaredNorm();
  }
  if (const std::optional<double> tilt = config_.robot->flagellumTilt(state_.q, parts, axis))
    s.flagellum_tilt = *tilt;  // docs/model.md 8.4.4
  s.newton_iterations = newton_iterations_;
  s.subdivided_steps = subdivided_steps_;
  s.damped_steps = damped_steps_;
  if (record_nodes_)
    for (int i = 0; i < net.numNodes(); ++i) s.nodes.push_back(nodePosition(state_.q, i));
  return s;
}

void Simulation::recordFinalSample() {
  if (trajectory_.empty() || trajectory_.back().time + kSampleTimeSlack < state_.time)
    recordSample();
}

void Simulation::recordSample() {
  trajectory_.push_back(sample());
  next_sample_time_ = state_.time + config_.output_interval;
}

SummaryMetrics Simulation::summary() const {
  SummaryInputs in;
  in.up = config_.medium.up;
  in.initial_axis = trajectory_.front().head_axis;
  in.steady_fraction = config_.steady_fraction;
  in.buckling_tilt = units::degToRad(config_.buckling_tilt_deg);
  if (const Effect* e = stepper_.findEffect<StokesHeadDrag>()) {
    in.C_t = e->parameters().get("C_t");
    in.C_r = e->parameters().get("C_r");
    in.head_radius = e->parameters().get("head_radius");
  }
  return summarize(trajectory_, in);
}

ParameterSet& Simulation::parameterOwner(const std::string& name, std::string& local) const {
  auto& stepper = const_cast<ImplicitStepper&>(stepper_);
  const std::string medium_prefix = "medium.";
  const std::string effects_prefix = "effects.";
  if (name.rfind(medium_prefix, 0) == 0) {
    local = name.substr(medium_prefix.size());
    return stepper.mediumParameters();
  }
  if (name.rfind(effects_prefix, 0) == 0) {
    const std::string rest = name.substr(effects_prefix.size());
    const size_t dot = rest.find('.');
    if (dot != std::string::npos) {
      if (Effect* e = stepper.findEffect(rest.substr(0, dot))) {
        local = rest.substr(dot + 1);
        return e->parameters();
      }
      throw ConfigError("parameter '" + name + "': effect '" + rest.substr(0, dot) +
                        "' is not switched on");
    }
  }
  throw ConfigError("parameter '" + name +
                    "' must look like medium.<name> or effects.<effect>.<name>");
}

double Simulation::parameter(const std::string& name) const {
  std::string local;
  return parameterOwner(name, local).get(local);
}

const ParameterSpec& Simulation::parameterSpec(const std::string& name) const {
  std::string local;
  const ParameterSet& owner = parameterOwner(name, local);
  owner.get(local);  // throws a ConfigError naming the parameter if unknown
  for (const ParameterSpec& p : owner.specs())
    if (p.name == local) return p;
  throw ConfigError("unknown parameter '" + name + "'");
}

void Simulation::setParameter(const std::string& name, double value) {
  if (slider_ && name == "effects.com_offset.offset")
    throw ConfigError(
        "effects.com_offset.offset follows the slider (l = l_0 + (m_s/m_h) x_s, l_0 the "
        "configured offset): command the slider instead");
  std::string local;
  ParameterSet& owner = parameterOwner(name, local);
  owner.set(local, value, name.substr(0, name.size() - local.size() - 1));
}

std::vector<std::string> Simulation::parameterNames() const {
  std::vector<std::string> names;
  for (const ParameterSpec& p : stepper_.medium().parameters().specs())
    names.push_back("medium." + p.name);
  for (const EffectPtr& e : stepper_.effects())
    for (const ParameterSpec& p : e->parameters().specs())
      names.push_back("effects." + e->name() + "." + p.name);
  return names;
}

}  // namespace flagella
