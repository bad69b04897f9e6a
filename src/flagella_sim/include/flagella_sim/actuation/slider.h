// The mass-transformer's slider (docs/model.md 5): a lead screw driven by a small motor moves an
// internal mass m_s along the head axis. One component of the simulation state: a target
// position goes in, the slider position x_s(t) comes out, and with it the COM - COV offset
// l(t) = l_0 + (m_s / m_h) x_s(t) of the com_offset couple. The screw motor turns at most at
// max_screw_rate and changes its rate by at most max_screw_accel (a trapezoidal move, braking on
// the curve v = sqrt(2 a e) to stop on the target); the travel ends in hard stops that are
// reported and never passed.
#pragma once

#include <string>

#include "flagella_sim/core/units.h"

namespace flagella {

/// Allowed values of a SliderSpec (SliderSpec::validate and the config parser).
namespace slider_limits {
inline constexpr double kMinMass = 1e-6, kMaxMass = 10.0;  // [kg]
inline constexpr double kMinLead = 1e-6, kMaxLead = 0.1;   // [m]
inline constexpr double kMinScrewRate = units::rpmToRadPerSec(1e-2),
                        kMaxScrewRate = 1e4;                          // [rad/s]
inline constexpr double kMinScrewAccel = 1e-3, kMaxScrewAccel = 1e6;  // [rad/s^2]
inline constexpr double kMaxTravel = 1.0;  // [m] either side of the neutral position
}  // namespace slider_limits

/// Config section `slider:` (docs/model.md 5; every value [ASSUMED]: the source gives none).
struct SliderSpec {
  bool enabled = false;  ///< the section is present
  double mass = 0.015;   ///< m_s [kg]: tungsten, batteries, electronics
  double lead = 0.5e-3;  ///< p_lead: travel per screw turn [m] (an M3 lead screw)
  double max_screw_rate = units::rpmToRadPerSec(300.0);  ///< omega_s max [rad/s]: 2.5 mm/s
  double max_screw_accel = 300.0;                        ///< [rad/s^2] (full rate in about 0.1 s)
  double travel_min = -8e-3;      ///< hard stop behind the neutral position [m]
  double travel_max = 8e-3;       ///< hard stop ahead of it, along +t^0 [m]
  double initial_position = 0.0;  ///< x_s(0) [m], inside the travel

  double maxSpeed() const;         ///< p_lead omega_max / (2 pi) [m/s]
  double maxAcceleration() const;  ///< p_lead alpha_max / (2 pi) [m/s^2]
  /// Throws ConfigError naming the field and its allowed range.
  void validate() const;
};

/// Where the slider is and what it is doing.
struct SliderState {
  double position = 0.0;  ///< x_s [m] from the neutral position, along +t^0
  double velocity = 0.0;  ///< [m/s]
  double target = 0.0;    ///< [m]
  bool at_stop = false;   ///< resting against a hard stop
  long stop_hits = 0;     ///< times it ran into a stop
};

class Slider {
 public:
  explicit Slider(const SliderSpec& spec);

  /// Sets the position to drive to [m]. Must be finite (std::invalid_argument otherwise); a
  /// target beyond the travel drives the slider into the hard stop, where it stays (reported).
  void setTarget(double target);
  /// Moves the slider over `dt` seconds toward the target (internal sub-steps of at most 1 ms).
  void advance(double dt);
  /// l(t) = l_0 + (m_s / m_h) x_s (docs/model.md 5).
  double comOffset(double neutral_offset, double head_mass) const;
  /// Screw rate omega_s = 2 pi v / p_lead [rad/s].
  double screwRate() const;

  const SliderState& state() const { return state_; }
  void restore(const SliderState& state) { state_ = state; }
  const SliderSpec& spec() const { return spec_; }

 private:
  void subStep(double h);

  SliderSpec spec_;
  SliderState state_;
};

}  // namespace flagella
