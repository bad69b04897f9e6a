// The steering gains by name: their validation, units and meanings (what `--gain`, the ROS
// node's private parameters and `flagella_steer --list-gains` read); docs/model.md 7.4.
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "flagella_control/mass_transformer_controller.h"
#include "flagella_control/validation.h"
#include "flagella_control/yaml_text.h"
#include "flagella_sim/core/parameter_set.h"

namespace flagella::control {

namespace {
const char* const kContext = "steering gains";

// A numeric gain: its name, field, unit and meaning.
struct NamedGain {
  const char* name;
  double SteeringGains::*field;
  const char* unit;
  const char* meaning;
};
constexpr NamedGain kNamedGains[] = {
    {"heading_filter_time", &SteeringGains::heading_filter_time, "s",
     "each of the two cascaded filters of the head axis (they remove the wobble)"},
    {"tilt_filter_time", &SteeringGains::tilt_filter_time, "s",
     "filter of the accelerometer's elevation"},
    {"turn_threshold", &SteeringGains::turn_threshold, "rad",
     "error of the direction of travel that calls for buckle turns"},
    {"large_turn", &SteeringGains::large_turn, "rad",
     "azimuth error that calls for a turn at elevation (pi: never)"},
    {"blocked_turn", &SteeringGains::blocked_turn, "rad",
     "the same toward a side buckle cycles cannot turn to"},
    {"stall_time", &SteeringGains::stall_time, "s",
     "an azimuth error that has not shrunk for this long starts a turn at elevation (0: never)"},
    {"stall_error", &SteeringGains::stall_error, "rad", "... when it is beyond this"},
    {"stall_progress", &SteeringGains::stall_progress, "rad",
     "... and has shrunk by less than this"},
    {"flip_elevation", &SteeringGains::flip_elevation, "rad", "elevation of a turn at elevation"},
    {"top_margin", &SteeringGains::top_margin, "rad",
     "within this of flip_elevation the robot counts as turning"},
    {"lean_filter_time", &SteeringGains::lean_filter_time, "s",
     "filter of the head axis while turning at elevation"},
    {"exit_window", &SteeringGains::exit_window, "rad",
     "pitch back down this near the wanted azimuth"},
    {"exit_delay", &SteeringGains::exit_delay, "s",
     "the azimuth is extrapolated this far at its rate"},
    {"sweep_filter_time", &SteeringGains::sweep_filter_time, "s", "filter of that azimuth rate"},
    {"max_turn_time", &SteeringGains::max_turn_time, "s", "longest stay at elevation per pitch-up"},
    {"descent_holdoff", &SteeringGains::descent_holdoff, "s",
     "after pitching back: no new turn at elevation for this long"},
    {"tilt_mode_threshold", &SteeringGains::tilt_mode_threshold, "rad",
     "elevation error reported as mass-transformer mode"},
    {"tilt_entry_share", &SteeringGains::tilt_entry_share, "",
     "... once beyond it for this share of the flagellum's period at cruise"},
    {"max_buckle_error", &SteeringGains::max_buckle_error, "rad",
     "buckle turns only below this error (larger ones are the slider's)"},
    {"phase_window", &SteeringGains::phase_window, "rad",
     "a buckle cycle starts within this phase of the best one"},
    {"min_turn_share", &SteeringGains::min_turn_share, "",
     "turn to a side only if the best cycle turns that way by this share of the calibrated "
     "deflection"},
    {"settle_time", &SteeringGains::settle_time, "s", "after a buckle cycle, before the next"},
    {"max_cycle_offset", &SteeringGains::max_cycle_offset, "m",
     "cycle_pitch: largest slider offset from the park estimate through a cycle"},
    {"max_cycle_up", &SteeringGains::max_cycle_up, "rad",
     "cycle_pitch: largest up- or down-turn one cycle is asked for"},
    {"park_learning", &SteeringGains::park_learning, "",
     "cycle_pitch: share of a cycle's measured up-turn error corrected in the park estimate"},
    {"turn_learning", &SteeringGains::turn_learning, "",
     "cycle_pitch: share of a cycle's turn-size (log) and direction error corrected in the "
     "learnt size gain and the phase offset (0: off)"},
    {"max_cycle_turn", &SteeringGains::max_cycle_turn, "rad",
     "turn learning: largest turn one cycle is sized for"},
    {"pulse_growth", &SteeringGains::pulse_growth, "",
     "turn learning: d ln(turn by phase) / d(pulse rate over omega_b) for sizing cycles (0: the "
     "calibrated pulse)"},
    {"min_pulse_factor", &SteeringGains::min_pulse_factor, "",
     "turn learning keeps the pulse rate above this multiple of omega_b"},
    {"max_pulse_factor", &SteeringGains::max_pulse_factor, "",
     "turn learning keeps the pulse rate below this multiple of omega_b"},
    {"reorient_offset", &SteeringGains::reorient_offset, "m",
     "reorient: slider offset from the park estimate while turning in place"},
    {"reorient_omega", &SteeringGains::reorient_omega, "rad/s",
     "reorient: motor rate, forward or reversed, while turning in place"},
    {"reorient_dwell", &SteeringGains::reorient_dwell, "s",
     "reorient: each slider-and-motor combination held this long"},
    {"reorient_enter", &SteeringGains::reorient_enter, "rad",
     "reorient: error of the direction of travel that starts a turn in place"},
    {"reorient_exit", &SteeringGains::reorient_exit, "rad", "reorient: ... and ends it"},
    {"reorient_full_error", &SteeringGains::reorient_full_error, "rad",
     "reorient: the offset in full above this error, in proportion below"},
    {"reorient_min_share", &SteeringGains::reorient_min_share, "",
     "reorient: ... but at least this share of reorient_offset"},
    {"reorient_balance", &SteeringGains::reorient_balance, "",
     "reorient: an error component below this share of the error alternates its sign"},

    {"max_elevation", &SteeringGains::max_elevation, "rad", "limit of a leg's target elevation"},
    {"tilt_time_constant", &SteeringGains::tilt_time_constant, "s",
     "closed-loop time constant of the slider (elevation) loop"},
    {"max_pitch_rate", &SteeringGains::max_pitch_rate, "rad/s",
     "the slider loop asks for no faster pitch"},
    {"tilt_integral_time", &SteeringGains::tilt_integral_time, "s",
     "integral time of the slider loop"},
    {"tilt_exit_threshold", &SteeringGains::tilt_exit_threshold, "rad",
     "the elevation loop lets go below this error"},
    {"tilt_integral_delay", &SteeringGains::tilt_integral_delay, "s",
     "with offset steering, the loop integrates only after this long unsettled"},
    {"min_pitch_offset", &SteeringGains::min_pitch_offset, "m",
     "with offset steering: the elevation loop's least slider offset"},
    {"crab_lag_time", &SteeringGains::crab_lag_time, "s",
     "the course follows a slider offset with this lag"},
    {"max_steer_offset", &SteeringGains::max_steer_offset, "m",
     "largest steering offset of the slider from its neutral"},
    {"neutral_filter_time", &SteeringGains::neutral_filter_time, "s",
     "learning the slider's neutral from the course"},
    {"trim_sigmas", &SteeringGains::trim_sigmas, "",
     "standard errors by which the start frame's pitch must move the neutral to trim it"},
    {"pitch_forgetting_time", &SteeringGains::pitch_forgetting_time, "s",
     "forgetting time of the pitch model learnt over the mission"},
    {"retrim_threshold", &SteeringGains::retrim_threshold, "m",
     "re-trim the neutral when the pitch model's differs by more than this"},
    {"retrim_interval", &SteeringGains::retrim_interval, "s", "at most one re-trim per this"},
    {"slider_margin", &SteeringGains::slider_margin, "m",
     "keep the slider off its hard stops by this"},
    {"fix_gain", &SteeringGains::fix_gain, "", "position estimate: p += gain (camera fix - p)"},
    {"reach_fraction", &SteeringGains::reach_fraction, "",
     "a waypoint is reached within this share of the mission's tolerance"},
    {"pass_fraction", &SteeringGains::pass_fraction, "",
     "... or within this share of it once the distance grew by pass_margin past its minimum"},
    {"pass_margin", &SteeringGains::pass_margin, "m",
     "the growth past the closest approach that counts a pass (see pass_fraction)"},
    {"course_filter_time", &SteeringGains::course_filter_time, "s",
     "filter of the velocity from camera fixes"},
    {"crab_filter_time", &SteeringGains::crab_filter_time, "s",
     "filter of the crab angle (course minus axis azimuth)"},
    {"max_crab", &SteeringGains::max_crab, "rad", "the crab estimate is held within +-this"},
    {"min_course_speed", &SteeringGains::min_course_speed, "",
     "the course is used above this share of the cruise speed"},
    {"imu_timeout", &SteeringGains::imu_timeout, "s",
     "IMU older than this: no new cycles, slider held"},
    {"fix_timeout", &SteeringGains::fix_timeout, "s", "camera fix older than this: reported stale"},
    {"sensor_fault_timeout", &SteeringGains::sensor_fault_timeout, "s",
     "no IMU for this long: fault, motor stopped"},
};
// The on/off gains (0 or 1 by name).
struct NamedFlag {
  const char* name;
  bool SteeringGains::*field;
  const char* meaning;
};
constexpr NamedFlag kNamedFlags[] = {
    {"steer_by_offset", &SteeringGains::steer_by_offset,
     "1: steer the azimuth by small slider offsets around the neutral (crab angle); 0: the slider "
     "only holds the elevation"},
    {"trim_neutral", &SteeringGains::trim_neutral,
     "1: trim the neutral from the head's pitch while the start frame's course is measured"},
    {"retrim_neutral", &SteeringGains::retrim_neutral,
     "1: re-trim the neutral from the pitch model learnt over the mission"},
    {"hold_in_cycle", &SteeringGains::hold_in_cycle,
     "1: the slider at the neutral during a buckle cycle and its settle_time (no elevation loop)"},
    {"mixed_schedules", &SteeringGains::mixed_schedules,
     "1 (cycle_pitch): each cycle by the schedule, relax or three_level, whose best phase comes "
     "nearer the wanted turn"},
    {"cycle_pitch", &SteeringGains::cycle_pitch,
     "1: the elevation by buckle cycles alone, through the slider's offset held through each "
     "cycle (the slider otherwise at the park estimate, learnt from the cycles' turns)"},
    {"reorient", &SteeringGains::reorient,
     "1: turns in place by the slider's offset with the motor forward or reversed (the four "
     "combinations turn the robot along the four diagonals), straight cruise between; no "
     "buckle cycles"},
    {"reorient_up_turns_right", &SteeringGains::reorient_up_turns_right,
     "reorient: 1 if, forward, an offset that pitches the robot up turns it right (measured on "
     "the source's left-handed robot); 0: left"},

};
}  // namespace

void SteeringGains::validate() const {
  requireInRange(kContext, "heading_filter_time", heading_filter_time, 0.0, 60.0);
  requireInRange(kContext, "tilt_filter_time", tilt_filter_time, 0.0, 60.0);
  requireInRange(kContext, "turn_threshold", turn_threshold, 1e-3, M_PI / 2);
  requireInRange(kContext, "large_turn", large_turn, turn_threshold, M_PI);
  requireInRange(kContext, "blocked_turn", blocked_turn, turn_threshold, large_turn);
  requireInRange(kContext, "stall_time", stall_time, 0.0, 1e4);
  requireInRange(kContext, "stall_error", stall_error, 1e-3, M_PI);
  requireInRange(kContext, "stall_progress", stall_progress, 0.0, M_PI);
  requireInRange(kContext, "flip_elevation", flip_elevation, 0.35, 1.50);
  requireInRange(kContext, "top_margin", top_margin, 0.01, 0.5);
  requireInRange(kContext, "lean_filter_time", lean_filter_time, 0.0, 30.0);
  requireInRange(kContext, "exit_window", exit_window, 0.01, M_PI);
  requireInRange(kContext, "exit_delay", exit_delay, 0.0, 60.0);
  requireInRange(kContext, "sweep_filter_time", sweep_filter_time, 0.0, 600.0);
  requireInRange(kContext, "max_turn_time", max_turn_time, 1.0, 3600.0);
  requireInRange(kContext, "descent_holdoff", descent_holdoff, 0.0, 600.0);
  requireInRange(kContext, "tilt_mode_threshold", tilt_mode_threshold, 0.0, M_PI);
  requireInRange(kContext, "tilt_entry_share", tilt_entry_share, 0.0, 10.0);
  requireInRange(kContext, "max_buckle_error", max_buckle_error, turn_threshold, 2 * M_PI);
  requireInRange(kContext, "phase_window", phase_window, 0.01, M_PI);
  requireInRange(kContext, "min_turn_share", min_turn_share, 0.0, 1.0);
  requireInRange(kContext, "settle_time", settle_time, 0.0, 600.0);
  requireInRange(kContext, "max_cycle_offset", max_cycle_offset, 0.0, 0.01);
  requireInRange(kContext, "max_cycle_up", max_cycle_up, 0.0, M_PI / 2);
  requireInRange(kContext, "park_learning", park_learning, 0.0, 1.0);
  requireInRange(kContext, "turn_learning", turn_learning, 0.0, 1.0);
  requireInRange(kContext, "max_cycle_turn", max_cycle_turn, 1e-3, M_PI / 2);
  requireInRange(kContext, "pulse_growth", pulse_growth, 0.0, 100.0);
  requireInRange(kContext, "min_pulse_factor", min_pulse_factor, 1.0, 10.0);
  requireInRange(kContext, "max_pulse_factor", max_pulse_factor, min_pulse_factor, 10.0);
  requireInRange(kContext, "reorient_offset", reorient_offset, 1e-6, 0.01);
  requireInRange(kContext, "reorient_omega", reorient_omega, 0.01, 100.0);
  requireInRange(kContext, "reorient_dwell", reorient_dwell, 0.1, 600.0);
  requireInRange(kContext, "reorient_exit", reorient_exit, 1e-3, M_PI);
  requireInRange(kContext, "reorient_enter", reorient_enter, reorient_exit, M_PI);
  requireInRange(kContext, "reorient_full_error", reorient_full_error, 1e-3, M_PI);
  requireInRange(kContext, "reorient_min_share", reorient_min_share, 0.0, 1.0);
  requireInRange(kContext, "reorient_balance", reorient_balance, 0.0, 1.0);
  requireInRange(kContext, "max_elevation", max_elevation, 0.0, flip_elevation);
  requireInRange(kContext, "tilt_time_constant", tilt_time_constant, 0.1, 600.0);
  requireInRange(kContext, "max_pitch_rate", max_pitch_rate, 1e-3, 10.0);
  requireInRange(kContext, "tilt_integral_time", tilt_integral_time, 0.1, 1e4);
  requireInRange(kContext, "tilt_integral_delay", tilt_integral_delay, 0.0, 1e4);
  requireInRange(kContext, "tilt_exit_threshold", tilt_exit_threshold, 0.0, tilt_mode_threshold);
  requireInRange(kContext, "min_pitch_offset", min_pitch_offset, 0.0, 0.01);
  requireInRange(kContext, "crab_lag_time", crab_lag_time, 0.0, 600.0);
  requireInRange(kContext, "max_steer_offset", max_steer_offset, 0.0, 0.01);
  requireInRange(kContext, "neutral_filter_time", neutral_filter_time, 1.0, 1e5);
  requireInRange(kContext, "trim_sigmas", trim_sigmas, 0.0, 100.0);
  requireInRange(kContext, "pitch_forgetting_time", pitch_forgetting_time, 1.0, 1e5);
  requireInRange(kContext, "retrim_threshold", retrim_threshold, 0.0, 0.01);
  requireInRange(kContext, "retrim_interval", retrim_interval, 0.0, 1e5);
  requireInRange(kContext, "slider_margin", slider_margin, 0.0, 0.01);
  requireInRange(kContext, "fix_gain", fix_gain, 0.0, 1.0);
  requireInRange(kContext, "reach_fraction", reach_fraction, 0.0, 1.0);
  requireInRange(kContext, "pass_fraction", pass_fraction, 0.0, 1.0);
  requireInRange(kContext, "pass_margin", pass_margin, 0.0, 1.0);
  requireInRange(kContext, "course_filter_time", course_filter_time, 0.0, 600.0);
  requireInRange(kContext, "crab_filter_time", crab_filter_time, 0.0, 3600.0);
  requireInRange(kContext, "max_crab", max_crab, 0.0, M_PI);
  requireInRange(kContext, "min_course_speed", min_course_speed, 0.0, 10.0);
  requireInRange(kContext, "imu_timeout", imu_timeout, 1e-3, 60.0);
  requireInRange(kContext, "fix_timeout", fix_timeout, 1e-3, 1e4);
  requireInRange(kContext, "sensor_fault_timeout", sensor_fault_timeout, imu_timeout, 1e4);
}

std::vector<std::string> SteeringGains::names() {
  std::vector<std::string> all;
  for (const NamedGain& g : kNamedGains) all.emplace_back(g.name);
  for (const NamedFlag& f : kNamedFlags) all.emplace_back(f.name);
  return all;
}

bool SteeringGains::isFlag(const std::string& name) {
  for (const NamedFlag& f : kNamedFlags)
    if (name == f.name) return true;
  return false;
}

void SteeringGains::set(const std::string& name, double value) {
  for (const NamedFlag& f : kNamedFlags) {
    if (name != f.name) continue;
    if (value != 0.0 && value != 1.0)
      throw std::invalid_argument(std::string("steering gains: ") + f.name +
                                  " must be 0 or 1, got " + std::to_string(value));
    this->*f.field = value == 1.0;
    return;
  }
  for (const NamedGain& g : kNamedGains) {
    if (name == g.name) {
      this->*g.field = value;
      return;
    }
  }
  std::string known;
  for (const std::string& n : names()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("steering gains: unknown gain '" + name + "' (known: " + known + ")");
}

double SteeringGains::get(const std::string& name) const {
  for (const NamedFlag& f : kNamedFlags)
    if (name == f.name) return this->*f.field ? 1.0 : 0.0;
  for (const NamedGain& g : kNamedGains)
    if (name == g.name) return this->*g.field;
  throw std::invalid_argument("steering gains: unknown gain '" + name + "'");
}

std::string SteeringGains::table() const {
  std::string text = "gain                   value      unit    meaning\n";
  char line[512];
  for (const NamedGain& g : kNamedGains) {
    std::snprintf(line, sizeof(line), "%-22s %-10g %-7s %s\n", g.name, this->*g.field, g.unit,
                  g.meaning);
    text += line;
  }
  for (const NamedFlag& f : kNamedFlags) {
    std::snprintf(line, sizeof(line), "%-22s %-10d %-7s %s\n", f.name, this->*f.field ? 1 : 0,
                  "0/1", f.meaning);
    text += line;
  }
  return text;
}

void SteeringGains::load(const std::string& path) {
  const YAML::Node node = loadSingleKeyFile(path, "steering_gains", kContext);
  MapReader reader(node, "steering_gains", path, kContext);
  for (const auto& entry : node) {
    const std::string name = entry.first.as<std::string>();
    const double value = reader.number(name);
    try {
      set(name, value);
    } catch (const std::invalid_argument& e) {
      throw flagella::InputFileError(path + ": " + e.what());
    }
  }
}

}  // namespace flagella::control
