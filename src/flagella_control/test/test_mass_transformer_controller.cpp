// The mass-transformer controller core (mass_transformer_controller.h) against an independent
// kinematic plant of the helical robot: the direction of travel turns by the cycle model of the
// calibration at the end of each buckle cycle, pitches at k (x - x_park + x_err) cos(elevation)
// under the slider (docs/model.md 5: the couple is proportional to l cos(elevation)), the head
// rolls at a constant rate, the robot advances at the cruise speed; the IMU reports the head frame
// (m1, m2, t = -f), the accelerometer gravity in the head frame, the camera the position at 1 Hz.
// Above 45 deg of elevation the azimuth precesses at `top_rate` while the motor turns, for
// `top_duration` after each pitch-up, and the robot's course runs `crab` to the left of its head
// axis plus `offset_crab` per metre of slider offset from the true neutral (followed with a 20 s
// lag), while that offset also turns the axis at `offset_turn` per metre up to 60 um
// (docs/model.md 7.4: what the simulator shows). Tests of the turn at elevation and of a constant
// learnt crab run the controller without offset steering (legacyGains) on a plant without the
// offset's crab.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "flagella_control/heading.h"
#include "flagella_control/mass_transformer_controller.h"
#include "flagella_sim/core/parameter_set.h"
#include "support/allocation_counter.h"
#include "support/temp_dir.h"

namespace fc = flagella::control;
using fc::Vec3;

namespace {

constexpr double kRate = 100.0;  // controller [Hz]
constexpr double kG = 9.80665;
constexpr double kDeg = M_PI / 180.0;

fc::SteeringCalibration calibration() {
  fc::SteeringCalibration c;
  c.buckling_threshold = 1.5;
  c.cruise_omega = 1.05;
  c.cruise_speed = 0.4e-3;
  for (fc::BuckleSchedule* s : {&c.relax, &c.three_level}) {
    s->pulse_omega = 3.0;
    s->pulse_duration = 2.0;
    s->deflection = 4.0 * kDeg;
    s->phase_offset = 0.3;
  }
  c.relax.kind = fc::BuckleScheduleKind::Relax;
  c.relax.relax_duration = 12.0;
  c.three_level.kind = fc::BuckleScheduleKind::ThreeLevel;
  c.three_level.lead_duration = 2.0;
  c.three_level.lead_omega = 0.1;
  c.pitch_rate_per_slider = 100.0;  // [rad/s per m]: 5.7 deg/s per mm
  c.crab_per_slider = -2.5e4;       // [rad/m]: 1.4 deg to the right per um of slider
  c.park_position = -1e-3;
  c.slider_min = -8e-3;
  c.slider_max = 8e-3;
  return c;
}

// The controller before offset steering: the slider holds the elevation, the crab is learnt as
// a constant, large turns at elevation.
fc::SteeringGains legacyGains() {
  fc::SteeringGains g;
  g.steer_by_offset = false;
  g.large_turn = g.blocked_turn = 0.8;
  return g;
}

fc::WaypointMission mission(const std::vector<Vec3>& points, double tolerance = 0.01) {
  fc::WaypointMission m;
  m.points = points;
  m.tolerance = tolerance;
  return m;
}

// Kinematic plant (see the file comment).
struct Plant {
  Vec3 forward = Vec3::UnitX(), position = Vec3::Zero();
  double roll = 0.0, roll_rate = -0.6, slider = -1e-3, slider_error = 0.0;
  double top_rate = -0.05;      // [rad/s] above 45 deg
  double top_duration = 1e9;    // [s] after each pitch-up
  double time_high = 0.0;       // [s] since the pitch-up
  double crab = 0.0;            // [rad], course minus axis azimuth
  double offset_crab = -2.5e4;  // [rad/m] of slider offset from the neutral (lagged)
  double offset_turn = -170.0;  // [rad/s per m]: azimuth rate of the head axis
  double slider_lag = -1e-3;    // [m]
  // Azimuth rate of the head axis per metre of slider offset from the neutral, at the cruise
  // rate, in proportion to the motor's signed rate: the turn that comes with the pitch changes
  // side with the motor's direction (docs/model.md 7.4, reorient; measured on the simulator).
  double reversible_turn = 0.0;  // [rad/s per m]
  fc::SteeringCalibration truth = calibration();
  fc::BuckleScheduleKind kind = fc::BuckleScheduleKind::Relax;
  double shaft = 0.0, cycle_left = -1.0, turn_up = 0.0, turn_left = 0.0, time = 0.0;
  // A cycle's extra turn per metre of the slider command at its start off the true park
  // (park_position - slider_error), as the schedule's up_per_slider and left_per_slider.
  double cycle_up_per_slider = 0.0, cycle_left_per_slider = 0.0;
  // A cycle's turn by phase (and its offset's turn) grows as exp(pulse_growth (f - f_0)) with
  // the pulse rate over the threshold f (f_0: the calibrated pulse's; relax cycles, whose first
  // level is the pulse), times turn_scale; its direction is phase_error further than the
  // calibration's. 0 growth: the calibrated turn.
  double pulse_growth = 0.0, turn_scale = 1.0, phase_error = 0.0;
  bool both_kinds = false;     // the kind of each cycle from its first level
  long cycles_of[2] = {0, 0};  // cycles started, relax and three_level
  double last_motor = 0.0;
  bool imu = true, camera = true;
  int steps = 0;

  fc::ControllerInputs sense() const {
    fc::ControllerInputs in;
    in.time = time;
    in.imu_valid = imu;
    const fc::NormalPlane plane = fc::normalPlane(forward);
    const Vec3 t = -forward;
    const Vec3 m1 = std::cos(roll) * plane.u + std::sin(roll) * plane.w;
    Eigen::Matrix3d R;
    R.col(0) = m1;
    R.col(1) = t.cross(m1);
    R.col(2) = t;
    const Eigen::Quaterniond q(R);
    in.orientation[0] = q.x(), in.orientation[1] = q.y(), in.orientation[2] = q.z(),
    in.orientation[3] = q.w();
    const Vec3 a = R.transpose() * Vec3(0, 0, kG);
    for (int k = 0; k < 3; ++k) in.linear_acceleration[k] = a[k];
    in.position_valid = camera && steps % static_cast<int>(kRate) == 0;
    for (int k = 0; k < 3; ++k) in.position[k] = position[k];
    return in;
  }

  void apply(const fc::ControllerOutputs& out) {
    const double dt = 1.0 / kRate;
    // A cycle starts when the rate jumps to the schedule's first level; its turn is applied at
    // its end, as the calibrated model predicts from the phase at the start.
    const bool high = std::abs(fc::elevationOf(forward)) > 45 * kDeg;
    time_high = high ? time_high + dt : 0.0;
    if (cycle_left < 0.0 && last_motor == truth.cruise_omega &&
        out.motor_command != truth.cruise_omega && out.motor_command > 0.0) {
      // With both_kinds the schedule is the one whose first level the command is.
      if (both_kinds)
        kind = out.motor_command == truth.three_level.lead_omega
                   ? fc::BuckleScheduleKind::ThreeLevel
                   : fc::BuckleScheduleKind::Relax;
      ++cycles_of[kind == fc::BuckleScheduleKind::ThreeLevel];
      const fc::BuckleSchedule& s = truth.schedule(kind);
      fc::BuckleSchedule sized = s;
      const double factor = out.motor_command / truth.buckling_threshold;
      const double size =
          turn_scale * std::exp(pulse_growth * (factor - s.pulse_omega / truth.buckling_threshold));
      sized.deflection *= size;
      sized.phase_offset += phase_error;
      sized.predictedTurn(roll, shaft, turn_up, turn_left);
      const double off_park = out.slider_position - (truth.park_position - slider_error);
      turn_up += size * cycle_up_per_slider * off_park;
      turn_left += size * cycle_left_per_slider * off_park;
      cycle_left = s.cycleDuration();
    }
    last_motor = out.motor_command;
    shaft += out.motor_command * dt;
    if (cycle_left >= 0.0) {
      cycle_left -= dt;
      if (cycle_left < 0.0) {
        const fc::NormalPlane plane = fc::normalPlane(forward);
        forward = (forward + turn_up * plane.u + turn_left * plane.w).normalized();
      }
    }
    // Slider at 2.5 mm/s toward its command; pitch under the couple.
    const double step = 2.5e-3 * dt;
    slider += std::clamp(out.slider_position - slider, -step, step);
    const double elevation = fc::elevationOf(forward);
    const double pitch_rate = truth.pitch_rate_per_slider *
                              (slider - truth.park_position + slider_error) * std::cos(elevation);
    const double new_elevation = std::clamp(elevation + pitch_rate * dt, -1.55, 1.55);
    const double precession =
        high && time_high < top_duration && out.motor_command > 0.0 ? top_rate * dt : 0.0;
    const double neutral = truth.park_position - slider_error;
    slider_lag += dt / 20.0 * (slider - slider_lag);
    // The turn saturates while the pitch grows with the offset: the simulator turns about
    // 1.5 deg per deg of elevation at small offsets and 0.7 when the slider pitches the robot
    // (docs/model.md 7.4).
    const double turn =
        offset_turn * std::clamp(slider - neutral, -60e-6, 60e-6) * dt +
        reversible_turn * (slider - neutral) * out.motor_command / truth.cruise_omega * dt;
    forward = fc::directionFrom(fc::azimuthOf(forward) + precession + turn, new_elevation);
    // The offset's crab saturates (docs/model.md 7.4: about 65 deg at 80 um).
    const double course_crab =
        crab + std::clamp(offset_crab * (slider_lag - neutral), -60 * kDeg, 60 * kDeg);
    const double speed =
        truth.cruise_speed * std::min(out.motor_command, truth.cruise_omega) / truth.cruise_omega;
    position += speed * dt *
                fc::directionFrom(fc::azimuthOf(forward) + course_crab, fc::elevationOf(forward));
    roll = fc::wrapAngle(roll + roll_rate * dt);
    time += dt;
    ++steps;
  }
};

// A plant whose slider offset does not move the course (for legacyGains).
Plant legacyPlant() {
  Plant p;
  p.offset_crab = p.offset_turn = 0.0;
  return p;
}

fc::ControllerOutputs run(fc::MassTransformerController& c, Plant& p, double seconds,
                          std::vector<double>* motor = nullptr) {
  fc::ControllerOutputs out;
  const long n = std::lround(seconds * kRate);
  for (long k = 0; k < n; ++k) {
    out = c.step(p.sense());
    if (motor) motor->push_back(out.motor_command);
    p.apply(out);
  }
  return out;
}

TEST(MassTransformerController, ModeFollowsTheHeadingErrorWithoutOffsetSteering) {
  struct Case {
    Vec3 waypoint;
    fc::SteeringMode mode;
    const char* what;
  };
  const Case cases[] = {
      {Vec3(0.5, 0.0, 0.0), fc::SteeringMode::Cruise, "ahead"},
      {Vec3(0.5, 0.5 * std::tan(30 * kDeg), 0.0), fc::SteeringMode::BuckleTurn, "30 deg left"},
      {Vec3(0.5, -0.5 * std::tan(30 * kDeg), 0.0), fc::SteeringMode::BuckleTurn, "30 deg right"},
      {Vec3(0.5, 0.0, 0.5 * std::tan(40 * kDeg)), fc::SteeringMode::MassTransformer, "climb"},
      {Vec3(-0.5, 0.05, 0.0), fc::SteeringMode::MassTransformer, "behind"},
  };
  for (const Case& c : cases) {
    fc::MassTransformerController controller(mission({c.waypoint}), calibration(), legacyGains());
    Plant plant = legacyPlant();
    plant.roll_rate = 0.0;
    // The elevation loop takes over once the error has lasted half a rotation period (3.0 s).
    run(controller, plant, 3.5);
    EXPECT_EQ(controller.status().mode, c.mode) << c.what << ": " << controller.status().message;
  }
  fc::MassTransformerController behind(mission({Vec3(-0.5, 0.05, 0.0)}), calibration(),
                                       legacyGains());
  Plant plant = legacyPlant();
  run(behind, plant, 0.5);
  EXPECT_TRUE(behind.status().flipping);
  EXPECT_NEAR(behind.status().target_elevation, behind.gains().flip_elevation, 1e-12);
}

TEST(MassTransformerController, BothBuckleSchedulesDriveTheirLevels) {
  for (const auto kind : {fc::BuckleScheduleKind::Relax, fc::BuckleScheduleKind::ThreeLevel}) {
    fc::SteeringGains gains;
    gains.schedule = kind;
    const fc::SteeringCalibration cal = calibration();
    const fc::BuckleSchedule& s = cal.schedule(kind);
    // 25 deg left: buckle turns (a turn at elevation starts beyond large_turn).
    fc::MassTransformerController controller(mission({Vec3(0.5, 0.5 * std::tan(25 * kDeg), 0.0)}),
                                             cal, gains);
    Plant plant;
    plant.kind = kind;
    std::vector<double> motor;
    run(controller, plant, 60.0, &motor);
    // The first sample off the cruise rate starts a cycle; from there the levels of the schedule.
    std::size_t start = 0;
    while (start < motor.size() && motor[start] == cal.cruise_omega) ++start;
    ASSERT_LT(start, motor.size()) << fc::scheduleName(kind) << ": no cycle in 60 s";
    EXPECT_GE(start / kRate, gains.settle_time - 1e-9);  // not before the first settling
    // The cycle, then cruise during the settling time.
    const auto span = static_cast<std::size_t>((s.cycleDuration() + gains.settle_time) * kRate);
    for (std::size_t k = start; k < std::min(motor.size(), start + span); ++k) {
      const double t = (k - start + 0.5) / kRate;
      EXPECT_EQ(motor[k], s.omegaAt(t, cal.cruise_omega))
          << fc::scheduleName(kind) << " at " << t << " s into the cycle";
    }
    EXPECT_GE(controller.status().cycles, 1);
  }
}

TEST(MassTransformerController, CyclesStartAtThePhaseThatTurnsTheWantedWay) {
  // Waypoints to either side: each cycle starts when its calibrated turn points along the
  // error of the direction of travel (up, left).
  for (const int side : {1, -1}) {
    const fc::SteeringCalibration cal = calibration();
    fc::MassTransformerController controller(mission({Vec3(0.5, side * 0.25, 0.0)}), cal);
    Plant plant;
    double previous = 0.0;
    int starts = 0;
    for (long k = 0; k < 200 * kRate; ++k) {
      const fc::ControllerInputs in = plant.sense();
      const double shaft = plant.shaft, roll = plant.roll;
      const fc::ControllerOutputs out = controller.step(in);
      if (previous == cal.cruise_omega && out.motor_command == cal.relax.pulse_omega) {
        ++starts;
        // The turn of a cycle started now points along the error (up, left) within the window.
        double up = 0.0, left = 0.0;
        cal.relax.predictedTurn(roll, shaft, up, left);
        const fc::SteeringStatus& st = controller.status();
        const double du = st.target_elevation - st.elevation;
        const double dl = st.azimuth_error * std::cos(st.elevation);
        const double size = std::hypot(du, dl);
        const double bias = (cal.relax.bias_up * du + cal.relax.bias_left * dl) / size;
        EXPECT_GT((up * du + left * dl) / size,
                  bias + cal.relax.deflection * std::cos(controller.gains().phase_window) - 1e-9)
            << "side " << side << ", cycle " << starts;
      }
      previous = out.motor_command;
      plant.apply(out);
    }
    EXPECT_GE(starts, 3) << "side " << side;
  }
}

TEST(MassTransformerController, ASideTheCyclesCannotTurnToIsTurnedAtElevation) {
  fc::SteeringCalibration cal = calibration();
  cal.relax.bias_left = -5 * kDeg;  // every cycle turns right by 1 to 9 deg
  fc::SteeringGains gains = legacyGains();
  gains.blocked_turn = 0.3;  // a 45 deg left error is beyond it
  fc::MassTransformerController controller(mission({Vec3(0.5, 0.5, 0.0)}), cal, gains);
  Plant plant = legacyPlant();
  plant.top_rate = 0.05;  // precesses left at elevation
  run(controller, plant, 1.0);
  EXPECT_FALSE(controller.status().turn_possible);
  EXPECT_TRUE(controller.status().flipping);
  // The robot pitches up, precesses to 45 deg left, and pitches back down.
  bool reached_top = false;
  for (int k = 0; k < 400 && controller.status().flipping; ++k) {
    run(controller, plant, 1.0);
    reached_top = reached_top || controller.status().at_top;
  }
  EXPECT_TRUE(reached_top);
  EXPECT_FALSE(controller.status().flipping);
  run(controller, plant, 60.0);
  EXPECT_EQ(controller.status().flips, 1);
  EXPECT_LT(std::abs(fc::elevationOf(plant.forward)), 10 * kDeg);
  // Within the exit window, plus the precession during the first degrees of the descent.
  EXPECT_NEAR(fc::azimuthOf(plant.forward), 45 * kDeg, controller.gains().exit_window + 0.15);
}

TEST(MassTransformerController,
     AWaypointBehindIsReachedByATurnAtElevationEitherWayWithoutOffsetSteering) {
  struct Case {
    double rate, duration;
    const char* what;
  };
  for (const Case& c : {Case{-0.05, 1e9, "precessing right"}, Case{0.04, 1e9, "precessing left"},
                        Case{-0.05, 40.0, "precessing right for 40 s per pitch-up"}}) {
    fc::MassTransformerController controller(mission({Vec3(-0.03, 0.01, 0.0)}, 0.006),
                                             calibration(), legacyGains());
    Plant plant = legacyPlant();
    plant.top_rate = c.rate;
    plant.top_duration = c.duration;
    double closest = 1.0;
    for (long k = 0; k < 900 * kRate && controller.status().mode != fc::SteeringMode::Finished;
         ++k) {
      plant.apply(controller.step(plant.sense()));
      closest = std::min(closest, (plant.position - controller.waypoints()[0]).norm());
    }
    EXPECT_EQ(controller.status().mode, fc::SteeringMode::Finished)
        << c.what << ": " << controller.status().message;
    EXPECT_GE(controller.status().flips, 1) << c.what;
    // 2 rad per pitch-up against 3.5 rad the long way round: it gives up once and goes again.
    if (c.duration < 1e9) {
      EXPECT_GE(controller.status().flips, 2) << c.what;
    }
    EXPECT_LT(closest, 0.009) << c.what;
  }
}

TEST(MassTransformerController,
     SliderStopsAtTheTargetTiltAndFindsAnUnknownOffsetWithoutOffsetSteering) {
  const double target = std::atan2(0.3, 1.0);  // waypoint 16.7 deg up
  for (const double slider_error : {0.0, 0.8e-3}) {
    fc::MassTransformerController controller(mission({Vec3(1.0, 0.0, 0.3)}), calibration(),
                                             legacyGains());
    Plant plant = legacyPlant();
    plant.slider_error = slider_error;  // COM offset unknown to the calibration
    plant.roll_rate = 0.0;
    run(controller, plant, 400.0);
    const double elevation = fc::elevationOf(plant.forward);
    EXPECT_NEAR(elevation, target, 0.5 * kDeg) << "slider error " << slider_error;
    // At rest on the target the couple vanishes: the slider cancels the offset.
    EXPECT_NEAR(plant.slider, calibration().park_position - slider_error, 0.05e-3);
    EXPECT_FALSE(controller.status().slider_saturated);
  }
}

// The source robot's way (cycle_pitch): a slider offset held through a cycle turns the robot up
// by the schedule's up_per_slider; the controller keeps the slider at its park estimate
// otherwise and learns that estimate from each cycle's measured up-turn.
fc::SteeringCalibration cyclePitchCalibration() {
  fc::SteeringCalibration c = calibration();
  c.relax.up_per_slider = 4e3;     // [rad/m]: 0.23 deg per um
  c.relax.left_per_slider = -3e3;  // [rad/m]
  c.relax.deflection = 10 * kDeg;  // the source robot's relax cycle
  return c;
}

fc::SteeringGains cyclePitchGains() {
  fc::SteeringGains g;
  g.steer_by_offset = false;
  g.cycle_pitch = true;
  g.settle_time = 8.0;
  return g;
}

// The plant's part of a cycle's up-turn per metre of offset beyond its pitching under the offset
// held through the cycle: the calibration measures both together (up_per_slider).
double amplifiedUpPerSlider(const fc::SteeringCalibration& c) {
  return c.relax.up_per_slider - c.pitch_rate_per_slider * c.relax.cycleDuration();
}

// Turns in place (reorient): on a plant whose slider offset pitches the robot whichever way the
// motor turns and turns it right when pitching up forward, left reversed, a waypoint 70 deg to
// the left at level is reached with the motor run both ways and no buckle cycle; with the turn's
// side taken the wrong way round (reorient_up_turns_right 0) every combination turns the robot
// away, and the waypoint is missed.
TEST(MassTransformerController, ReorientTurnsInPlaceByTheSlidersOffsetAndTheMotorsDirection) {
  for (const bool right_sign : {true, false}) {
    fc::SteeringGains gains = cyclePitchGains();
    gains.cycle_pitch = false;
    gains.reorient = true;
    gains.reorient_up_turns_right = right_sign;
    gains.reorient_omega = 0.5 * calibration().cruise_omega;
    fc::MassTransformerController controller(mission({Vec3(0.02, 0.055, 0.0)}), calibration(),
                                             gains);
    Plant plant = legacyPlant();
    plant.reversible_turn = -30.0;  // 1.5 mm of offset at cruise: 2.6 deg/s to the right
    std::vector<double> motor;
    run(controller, plant, 900.0, &motor);
    const fc::SteeringStatus& st = controller.status();
    std::printf("reorient_up_turns_right %d: %d reached, %ld dwells, distance %.1f mm\n",
                right_sign, st.reached, st.reorient_dwells, 1e3 * st.distance);
    EXPECT_EQ(st.cycles, 0);
    if (right_sign) {
      EXPECT_EQ(st.reached, 1) << "distance " << st.distance;
      EXPECT_GE(st.reorient_dwells, 2);
      EXPECT_LT(*std::min_element(motor.begin(), motor.end()), 0.0) << "never reversed";
    } else {
      EXPECT_EQ(st.reached, 0);
    }
  }
}

TEST(MassTransformerController, CyclePitchLearnsTheTrueParkFromTheCyclesTurns) {
  // The true park 15 um off the calibrated one: a cycle there turns 3.4 deg more up than
  // predicted. With learning the estimate comes within 2 um of the truth; without, it stays.
  constexpr double kParkError = 15e-6;  // [m]
  for (const double learning : {0.5, 0.0}) {
    fc::SteeringGains gains = cyclePitchGains();
    gains.park_learning = learning;
    const fc::SteeringCalibration c = cyclePitchCalibration();
    fc::MassTransformerController controller(
        mission({Vec3(0.5, 0.5 * std::tan(20 * kDeg), 0.5 * std::tan(10 * kDeg))}), c, gains);
    Plant plant = legacyPlant();
    plant.truth = c;
    plant.slider_error = kParkError;
    plant.cycle_up_per_slider = amplifiedUpPerSlider(c);
    plant.cycle_left_per_slider = c.relax.left_per_slider;
    run(controller, plant, 600.0);
    const fc::SteeringStatus& st = controller.status();
    const double truth = c.park_position - kParkError;
    ASSERT_GE(st.cycles, 3) << "learning " << learning;
    if (learning > 0.0) {
      EXPECT_GE(st.park_updates, 3);
      EXPECT_NEAR(st.park_estimate, truth, 2e-6);
    } else {
      EXPECT_NEAR(st.park_estimate, c.park_position, 1e-12);
    }
  }
}

TEST(MassTransformerController, CyclePitchReachesAClimbByCyclesWithTheSliderNearPark) {
  // A waypoint 20 deg up: no slider loop, the elevation comes from cycles whose slider offset
  // (at most max_cycle_offset from the park estimate) turns them up; the robot passes it.
  const fc::SteeringCalibration c = cyclePitchCalibration();
  const fc::SteeringGains gains = cyclePitchGains();
  const Vec3 waypoint(0.12, 0.0, 0.12 * std::tan(20 * kDeg));
  fc::MassTransformerController controller(mission({waypoint}, 0.01), c, gains);
  Plant plant = legacyPlant();
  plant.truth = c;
  plant.cycle_up_per_slider = amplifiedUpPerSlider(c);
  plant.cycle_left_per_slider = c.relax.left_per_slider;
  double farthest = 0.0, closest = INFINITY;
  for (long k = 0; k < 900 * kRate; ++k) {
    const fc::ControllerOutputs out = controller.step(plant.sense());
    farthest =
        std::max(farthest, std::abs(out.slider_position - controller.status().park_estimate));
    plant.apply(out);
    closest = std::min(closest, (plant.position - waypoint).norm());
    if (controller.status().mode == fc::SteeringMode::Finished) break;
  }
  EXPECT_LE(farthest, gains.max_cycle_offset + 1e-12);
  EXPECT_LT(closest, 0.01) << "closest approach " << closest;
  EXPECT_GE(controller.status().cycles, 2);
  // Without up_per_slider in the calibration the mode is refused, naming the field.
  fc::SteeringCalibration bare = c;
  bare.relax.up_per_slider = 0.0;
  try {
    fc::MassTransformerController refused(mission({waypoint}), bare, gains);
    ADD_FAILURE() << "cycle_pitch accepted without up_per_slider";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("up_per_slider"), std::string::npos) << e.what();
  }
  // With mixed_schedules the other schedule needs it too, and the message names it.
  fc::SteeringGains mixed = gains;
  mixed.mixed_schedules = true;
  try {
    fc::MassTransformerController refused(mission({waypoint}), c, mixed);
    ADD_FAILURE() << "mixed_schedules accepted without three_level's up_per_slider";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("three_level"), std::string::npos) << e.what();
  }
}

TEST(MassTransformerController, TurnLearningSizesTheCyclesAndLearnsTheTurnTheModelGotWrong) {
  // The robot's cycles turn 0.3 of the calibrated size at every pulse rate, 0.8 rad further
  // round than the phase law says (as a model 20 % too stiff: README, "The source's steering
  // robot"); the turn grows with the pulse rate as the gains assume. With turn learning the
  // learnt gain comes within 15 % of 0.3 (the direction filter's first stage shows 96 % of a turn
  // settle_time after it), the phase shift within 0.1 rad of 0.8, the pulses rise
  // above the calibrated one, and a waypoint 60 deg to the left and 15 deg up is passed; without,
  // nothing is learnt.
  constexpr double kScale = 0.3, kPhaseError = 0.8;
  const Vec3 waypoint(0.10, 0.10 * std::tan(60 * kDeg), 0.2 * std::tan(15 * kDeg));
  for (const double learning : {0.5, 0.0}) {
    fc::SteeringGains gains = cyclePitchGains();
    gains.turn_learning = learning;
    gains.max_pulse_factor = 3.0;  // the test calibration pulses at 2 omega_b
    gains.pulse_growth = 9.0;      // cycles sized by the pulse rate
    const fc::SteeringCalibration c = cyclePitchCalibration();
    fc::MassTransformerController controller(mission({waypoint}, 0.01), c, gains);
    Plant plant = legacyPlant();
    plant.truth = c;
    plant.cycle_up_per_slider = amplifiedUpPerSlider(c);
    plant.cycle_left_per_slider = c.relax.left_per_slider;
    plant.pulse_growth = gains.pulse_growth;
    plant.turn_scale = kScale;
    plant.phase_error = kPhaseError;
    double closest = INFINITY, highest_pulse = 0.0;
    for (long k = 0; k < 1500 * kRate; ++k) {
      const fc::ControllerOutputs out = controller.step(plant.sense());
      highest_pulse = std::max(highest_pulse, out.motor_command);
      plant.apply(out);
      closest = std::min(closest, (plant.position - waypoint).norm());
      if (controller.status().mode == fc::SteeringMode::Finished) break;
    }
    const fc::SteeringStatus& st = controller.status();
    if (learning > 0.0) {
      EXPECT_GE(st.turn_updates, 4);
      EXPECT_NEAR(st.turn_gain, kScale, 0.15 * kScale);
      EXPECT_NEAR(st.phase_shift, kPhaseError, 0.1);
      EXPECT_GT(highest_pulse, c.relax.pulse_omega * 1.05);
      EXPECT_LT(closest, 0.01) << "closest approach " << closest;
    } else {
      EXPECT_EQ(st.turn_updates, 0);
      EXPECT_EQ(st.turn_gain, 1.0);
      EXPECT_EQ(highest_pulse, c.relax.pulse_omega);
      EXPECT_GT(closest, 0.01) << "closest approach " << closest;
    }
  }
}

TEST(MassTransformerController,
     MixedSchedulesTakeLargeTurnsByTheLargerCycleAndSmallOnesByTheSmaller) {
  // Relax cycles turn 4 deg by phase, three-level ones 20 deg (as 3 omega_b, 2 s pulses on the
  // source's robot: 8.8 and 28.9 deg). A waypoint 70 deg to the left: with mixed_schedules the
  // first cycle is three-level (the error is beyond what a relax cycle can come near), the
  // later small corrections relax, and the robot passes within the tolerance sooner than with
  // relax cycles alone, which take every turn 4 deg at a time.
  fc::SteeringCalibration c = cyclePitchCalibration();
  c.relax.deflection = 4 * kDeg;
  c.three_level.deflection = 20 * kDeg;
  c.three_level.up_per_slider = c.relax.up_per_slider;
  c.three_level.left_per_slider = c.relax.left_per_slider;
  const Vec3 waypoint(0.15 * std::cos(70 * kDeg), 0.15 * std::sin(70 * kDeg), 0.0);
  double reach_time[2] = {INFINITY, INFINITY};
  for (const bool mixed : {true, false}) {
    fc::SteeringGains gains = cyclePitchGains();
    gains.mixed_schedules = mixed;
    fc::MassTransformerController controller(mission({waypoint}, 0.01), c, gains);
    Plant plant = legacyPlant();
    plant.truth = c;
    plant.both_kinds = true;
    plant.cycle_up_per_slider = amplifiedUpPerSlider(c);
    plant.cycle_left_per_slider = c.relax.left_per_slider;
    long first_kind = -1;
    for (long k = 0; k < 1500 * kRate; ++k) {
      plant.apply(controller.step(plant.sense()));
      if (first_kind < 0 && plant.cycles_of[0] + plant.cycles_of[1] > 0)
        first_kind = plant.cycles_of[1] > 0 ? 1 : 0;
      if (controller.status().mode == fc::SteeringMode::Finished) {
        reach_time[mixed] = plant.time;
        break;
      }
    }
    if (mixed) {
      EXPECT_EQ(first_kind, 1);
      EXPECT_GE(plant.cycles_of[1], 1);
      EXPECT_GE(plant.cycles_of[0], 1);
    } else {
      EXPECT_EQ(plant.cycles_of[1], 0);
    }
  }
  EXPECT_LT(reach_time[1], 1500.0);
  EXPECT_LT(reach_time[1], reach_time[0])
      << "mixed " << reach_time[1] << " s, relax alone " << reach_time[0] << " s";
}

TEST(MassTransformerController, HoldInCycleKeepsTheSliderAtTheNeutralThroughCycleAndSettling) {
  // A waypoint 25 deg left and 17 deg up: buckle cycles for the azimuth while the elevation loop
  // wants the slider hundreds of micrometres off the neutral. With hold_in_cycle the slider sits
  // at the neutral from each cycle's start until its settle_time has passed; without, the loop
  // moves it during the cycles (the check can fail).
  for (const bool hold : {true, false}) {
    fc::SteeringGains gains = legacyGains();
    gains.hold_in_cycle = hold;
    gains.max_buckle_error = M_PI;  // every error by cycles, as on the source's robot
    fc::MassTransformerController controller(mission({Vec3(0.5, 0.5 * std::tan(25 * kDeg), 0.15)}),
                                             calibration(), gains);
    Plant plant = legacyPlant();
    double cycle_end = -1.0, largest_off = 0.0;
    long held_steps = 0;
    for (long k = 0; k < 150 * kRate; ++k) {
      const fc::ControllerOutputs out = controller.step(plant.sense());
      const fc::SteeringStatus& st = controller.status();
      if (st.in_cycle) cycle_end = plant.time + gains.settle_time;
      if (st.in_cycle || plant.time < cycle_end) {
        largest_off = std::max(largest_off, std::abs(out.slider_position - st.neutral));
        ++held_steps;
      }
      plant.apply(out);
    }
    ASSERT_GT(held_steps, 10 * kRate) << "no buckle cycle, hold " << hold;
    if (hold)
      EXPECT_LT(largest_off, 1e-12);
    else
      EXPECT_GT(largest_off, 1e-4);
  }
}

TEST(SteeringGains, AGainsFileSetsTheGainsItNamesAndNamesTheFieldItCannotRead) {
  flagella::testing::TempDir dir;
  const std::string good = dir.write("gains.yaml",
                                     "steering_gains:\n  settle_time: 8\n  "
                                     "hold_in_cycle: 1\n  turn_threshold: 0.04\n");
  fc::SteeringGains gains;
  gains.load(good);
  EXPECT_EQ(gains.settle_time, 8.0);
  EXPECT_TRUE(gains.hold_in_cycle);
  EXPECT_EQ(gains.turn_threshold, 0.04);
  EXPECT_EQ(gains.max_buckle_error, fc::SteeringGains().max_buckle_error);  // not named: default
  // The shipped file for the source's robot reads and validates.
  fc::SteeringGains source;
  source.load(std::string(FLAGELLA_CONFIG_DIR) + "/calibration/helical_steering_source_gains.yaml");
  EXPECT_NO_THROW(source.validate());
  EXPECT_TRUE(source.cycle_pitch);
  // ... and drives the controller with the shipped calibration of that robot (up_per_slider).
  source.schedule = fc::BuckleScheduleKind::ThreeLevel;
  EXPECT_NO_THROW(fc::MassTransformerController(
      mission({Vec3(0.1, 0.0, 0.0)}),
      fc::loadSteeringCalibration(std::string(FLAGELLA_CONFIG_DIR) +
                                  "/calibration/helical_steering_source.yaml"),
      source));
  // The turns-in-place file for that robot too.
  fc::SteeringGains reorient;
  reorient.load(std::string(FLAGELLA_CONFIG_DIR) +
                "/calibration/helical_steering_source_reorient_gains.yaml");
  EXPECT_NO_THROW(reorient.validate());
  EXPECT_TRUE(reorient.reorient);
  EXPECT_FALSE(reorient.cycle_pitch);
  EXPECT_NO_THROW(fc::MassTransformerController(
      mission({Vec3(0.1, 0.0, 0.0)}),
      fc::loadSteeringCalibration(std::string(FLAGELLA_CONFIG_DIR) +
                                  "/calibration/helical_steering_source.yaml"),
      reorient));
  struct Case {
    const char *text, *needle;
  };
  for (const Case& c : {Case{"steering_gains:\n  settle_tim: 8\n", "settle_tim"},
                        Case{"steering_gains:\n  settle_time: slow\n", "settle_time"},
                        Case{"steering_gains:\n  hold_in_cycle: 2\n", "hold_in_cycle"},
                        Case{"gains:\n  settle_time: 8\n", "steering_gains"}}) {
    const std::string path = dir.write("bad.yaml", c.text);
    try {
      fc::SteeringGains g;
      g.load(path);
      ADD_FAILURE() << "accepted: " << c.text;
    } catch (const flagella::InputFileError& e) {
      EXPECT_NE(std::string(e.what()).find(c.needle), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
    }
  }
}

TEST(MassTransformerController, ImuDropoutHoldsThenFaults) {
  fc::MassTransformerController controller(mission({Vec3(0.5, 0.0, 0.2)}), calibration());
  Plant plant;
  run(controller, plant, 20.0);
  plant.imu = false;
  const long cycles = controller.status().cycles;
  fc::ControllerOutputs out = run(controller, plant, 1.0);
  const double held = out.slider_position;
  out = run(controller, plant, 5.0);
  EXPECT_TRUE(controller.status().imu_stale);
  EXPECT_EQ(out.slider_position, held);
  EXPECT_EQ(controller.status().cycles, cycles);
  out = run(controller, plant, controller.gains().sensor_fault_timeout);
  EXPECT_EQ(controller.status().mode, fc::SteeringMode::Fault);
  EXPECT_EQ(out.motor_command, 0.0);
  EXPECT_EQ(out.mode, fc::ControllerMode::Fault);
}

TEST(MassTransformerController, StaleFixesLeaveDeadReckoning) {
  fc::MassTransformerController controller(mission({Vec3(0.5, 0.0, 0.0)}), calibration());
  Plant plant;
  plant.camera = false;
  plant.roll_rate = 0.0;
  run(controller, plant, controller.gains().fix_timeout + 1.0);
  EXPECT_TRUE(controller.status().fix_stale);
  // Straight cruise: the estimate moved as the robot did.
  EXPECT_NEAR((controller.estimatedPosition() - plant.position).norm(), 0.0, 0.05e-3);
  EXPECT_GT(plant.position.x(), 0.5 * calibration().cruise_speed * 20.0);
}

TEST(MassTransformerController, ReachesWaypointsWithTheRightModel) {
  // Ahead, a climb, then a turn of about 20 deg to the left going down (the slider turns the
  // robot left as it dives, docs/model.md 7.4): every waypoint within 5 mm of the true path.
  fc::MassTransformerController controller(
      mission({Vec3(0.02, 0.0, 0.0), Vec3(0.04, 0.0, 0.008), Vec3(0.06, 0.008, 0.0)}, 0.005),
      calibration());
  Plant plant;
  double closest[3] = {1, 1, 1};
  for (long k = 0; k < 1200 * kRate && controller.status().mode != fc::SteeringMode::Finished;
       ++k) {
    plant.apply(controller.step(plant.sense()));
    for (int i = 0; i < 3; ++i)
      closest[i] = std::min(closest[i], (plant.position - controller.waypoints()[i]).norm());
  }
  EXPECT_EQ(controller.status().mode, fc::SteeringMode::Finished) << controller.status().message;
  for (int i = 0; i < 3; ++i) EXPECT_LT(closest[i], 0.0075) << "waypoint " << i;
}

TEST(MassTransformerController, LearnsAConstantCrabAngleFromTheFixesWithoutOffsetSteering) {
  // The course runs 25 deg right of the head axis: the controller learns the offset from the
  // camera fixes, points the axis left of the waypoint, and reaches it.
  const double crab = -25 * kDeg;
  fc::MassTransformerController controller(mission({Vec3(0.12, 0.0, 0.0)}, 0.005), calibration(),
                                           legacyGains());
  Plant plant = legacyPlant();
  plant.crab = crab;
  double closest = 1.0;
  for (long k = 0; k < 900 * kRate && controller.status().mode != fc::SteeringMode::Finished; ++k) {
    plant.apply(controller.step(plant.sense()));
    closest = std::min(closest, (plant.position - controller.waypoints()[0]).norm());
    if (k == static_cast<long>(150 * kRate)) {
      EXPECT_NEAR(controller.status().crab, crab, 5 * kDeg) << "after 150 s";
    }
  }
  EXPECT_EQ(controller.status().mode, fc::SteeringMode::Finished) << controller.status().message;
  EXPECT_LT(closest, 0.0075);
}

TEST(MassTransformerController, AStartFrameOnTheCourseLiesAlongTheMeasuredCourse) {
  // The course runs 25 deg right of the head axis. With course_time, the start frame's x is
  // that course: the waypoint straight ahead lies on it, and the robot reaches it.
  const double crab = -25 * kDeg;
  fc::WaypointMission m = mission({Vec3(0.08, 0.0, 0.0)}, 0.005);
  m.course_time = 40.0;
  fc::MassTransformerController controller(m, calibration());
  Plant plant;
  plant.crab = crab;
  run(controller, plant, 20.0);
  EXPECT_EQ(controller.status().mode, fc::SteeringMode::Waiting) << "still measuring at 20 s";
  double closest = 1.0;
  for (long k = 0; k < 900 * kRate && controller.status().mode != fc::SteeringMode::Finished; ++k) {
    plant.apply(controller.step(plant.sense()));
    if (controller.status().mode != fc::SteeringMode::Waiting)
      closest = std::min(closest, (plant.position - controller.waypoints()[0]).norm());
  }
  const Vec3 ahead = controller.waypoints()[0];  // from the start (the origin)
  EXPECT_NEAR(std::atan2(ahead.y(), ahead.x()), crab, 3 * kDeg);
  EXPECT_NEAR(ahead.norm(), 0.08, 1e-3);
  EXPECT_EQ(controller.status().mode, fc::SteeringMode::Finished) << controller.status().message;
  EXPECT_LT(closest, 0.0075);
}

TEST(MassTransformerController, OffsetSteeringTurnsEitherWayAndLearnsTheNeutral) {
  // The course follows micrometres of slider offset (plant: -1.4 deg per um, lagged 20 s) and
  // the head axis turns with it, right and up for a positive offset (docs/model.md 7.4); the
  // neutral is 15 um off the calibration's park position. Waypoints 30 deg to either side (down
  // to the left, up to the right, as the slider turns the robot) are reached without a turn at
  // elevation, the offset stays within max_steer_offset, and the neutral is learnt. The
  // waypoint behind is reached too: its descending left turn stalls while the elevation loop
  // pitches the robot back up (and so right), and after stall_time it is turned at elevation.
  struct Case {
    Vec3 waypoint;
    const char* what;
    long flips;
  };
  const double slider_error = 15e-6;
  for (const Case& c : {Case{Vec3(0.06, 0.035, -0.015), "30 deg left, down", 0},
                        Case{Vec3(0.06, -0.035, 0.015), "30 deg right, up", 0},
                        Case{Vec3(-0.06, 0.05, -0.03), "behind: 140 deg left, down", 1}}) {
    fc::MassTransformerController controller(mission({c.waypoint}, 0.005), calibration());
    Plant plant;
    plant.slider_error = slider_error;
    plant.roll_rate = 0.0;
    double closest = 1.0;
    double max_offset = 0.0;
    for (long k = 0; k < 1800 * kRate && controller.status().mode != fc::SteeringMode::Finished;
         ++k) {
      const fc::ControllerOutputs out = controller.step(plant.sense());
      plant.apply(out);
      closest = std::min(closest, (plant.position - controller.waypoints()[0]).norm());
      if (!controller.status().pitching)
        max_offset =
            std::max(max_offset, std::abs(out.slider_position - controller.status().neutral));
    }
    EXPECT_EQ(controller.status().mode, fc::SteeringMode::Finished)
        << c.what << ": " << controller.status().message;
    EXPECT_LT(closest, 0.005) << c.what;
    EXPECT_EQ(controller.status().flips, c.flips) << c.what;
    EXPECT_LE(max_offset, controller.gains().max_steer_offset + 1e-12) << c.what;
    // The neutral: within 5 um of the truth (a 7 deg crab error).
    EXPECT_NEAR(controller.status().neutral, calibration().park_position - slider_error, 5e-6)
        << c.what;
  }
}

TEST(MassTransformerController, ANewWaypointBehindIsTurnedToTheShortWay) {
  // The first waypoint lies a little to the right, so the robot last steered right; the next
  // lies 120 deg to the left of the way it came. Its side is its own: the slider steers left at
  // once (a negative offset here) instead of keeping the last side the long way round.
  const Vec3 first(0.04, -0.004, 0.0);
  const Vec3 second = first + 0.04 * Vec3(std::cos(120 * kDeg), std::sin(120 * kDeg), 0.0);
  fc::MassTransformerController controller(mission({first, second}, 0.005), calibration());
  Plant plant;
  plant.roll_rate = 0.0;
  bool seen_right = false;
  for (long k = 0; k < 600 * kRate && controller.status().reached == 0; ++k) {
    plant.apply(controller.step(plant.sense()));
    seen_right = seen_right || controller.status().steer_offset > 0.0;
  }
  ASSERT_EQ(controller.status().reached, 1) << controller.status().message;
  EXPECT_TRUE(seen_right) << "the approach steered right";
  double sum = 0.0;
  int steps = 0;
  for (int k = 0; k < 5 * kRate; ++k, ++steps) {
    plant.apply(controller.step(plant.sense()));
    if (!controller.status().pitching) sum += controller.status().steer_offset;
  }
  EXPECT_LT(sum / steps, -0.5 * controller.gains().max_steer_offset) << "steers left";
}

TEST(MassTransformerController, OffsetSteeringLeavesTheElevationToTheSliderLoop) {
  // A climb of 16.7 deg: once the error has lasted half a rotation period at cruise (3.0 s
  // here), the elevation loop pitches the robot until within tilt_exit_threshold, then lets go;
  // the slider returns near the neutral.
  const double target = std::atan2(0.3, 1.0);
  fc::MassTransformerController controller(mission({Vec3(1.0, 0.0, 0.3)}), calibration());
  Plant plant;
  plant.roll_rate = 0.0;
  run(controller, plant, 2.5);
  EXPECT_NE(controller.status().mode, fc::SteeringMode::MassTransformer) << "within 3.0 s";
  EXPECT_FALSE(controller.status().pitching);
  run(controller, plant, 1.0);
  EXPECT_EQ(controller.status().mode, fc::SteeringMode::MassTransformer);
  EXPECT_TRUE(controller.status().pitching);
  fc::ControllerOutputs out;
  for (int k = 0; k < 60 && controller.status().pitching; ++k) out = run(controller, plant, 1.0);
  EXPECT_FALSE(controller.status().pitching);
  out = run(controller, plant, 30.0);
  EXPECT_NEAR(fc::elevationOf(plant.forward), target, controller.gains().tilt_mode_threshold);
  EXPECT_LE(std::abs(out.slider_position - calibration().park_position),
            controller.gains().max_steer_offset + 2e-5);
  EXPECT_FALSE(controller.status().slider_saturated);
}

TEST(MassTransformerController, AnElevationSpikeShorterThanTheEntryTimeLeavesTheSliderAlone) {
  // The head's elevation wobbles with the flagellum's rotation: with tilt_entry_share 0.5 (the
  // default), an error beyond tilt_mode_threshold for less than half the rotation period
  // (3.0 s) is not pitched against; one that lasts is. With 0 the spike is.
  fc::MassTransformerController controller(mission({Vec3(1.0, 0.0, 0.0)}), calibration());
  Plant plant;
  plant.roll_rate = 0.0;
  run(controller, plant, 10.0);
  ASSERT_FALSE(controller.status().pitching);
  const double azimuth = fc::azimuthOf(plant.forward);
  plant.forward = fc::directionFrom(azimuth, 20 * kDeg);  // a 20 deg spike for 2 s
  bool pitched = false;
  for (int k = 0; k < 2 * kRate; ++k) {
    plant.forward = fc::directionFrom(azimuth, 20 * kDeg);
    plant.apply(controller.step(plant.sense()));
    pitched = pitched || controller.status().pitching;
  }
  plant.forward = fc::directionFrom(azimuth, 0.0);
  for (int k = 0; k < 5 * kRate; ++k) {
    plant.apply(controller.step(plant.sense()));
    pitched = pitched || controller.status().pitching;
  }
  EXPECT_FALSE(pitched) << "a 2 s spike";
  for (int k = 0; k < 5 * kRate && !pitched; ++k) {  // held at 20 deg
    plant.forward = fc::directionFrom(azimuth, 20 * kDeg);
    plant.apply(controller.step(plant.sense()));
    pitched = controller.status().pitching;
  }
  EXPECT_TRUE(pitched) << "20 deg held for 5 s";

  fc::SteeringGains gains;
  gains.tilt_entry_share = 0.0;
  fc::MassTransformerController at_once(mission({Vec3(1.0, 0.0, 0.0)}), calibration(), gains);
  Plant other;
  other.roll_rate = 0.0;
  run(at_once, other, 10.0);
  ASSERT_FALSE(at_once.status().pitching);
  for (int k = 0; k < 1 * kRate; ++k) {
    other.forward = fc::directionFrom(azimuth, 20 * kDeg);
    other.apply(at_once.step(other.sense()));
  }
  EXPECT_TRUE(at_once.status().pitching) << "tilt_entry_share 0: a 1 s spike is pitched against";
}

TEST(MassTransformerController, ANeutralFarOffIsTrimmedFromThePitchOfTheStartCruise) {
  // The true neutral is 250 um (or 20 um) off the calibration's park position; the start
  // frame's 30 s cruise pitches the robot. Beyond what the course can show (max_crab /
  // |crab_per_slider| = 40 um here) the trim takes the neutral from that pitch at once; within
  // it the course's learning is left to do it. With trim_neutral off, nothing is taken.
  struct Case {
    double slider_error;
    bool trim, taken;
  };
  for (const Case& c : {Case{250e-6, true, true}, Case{-250e-6, true, true},
                        Case{20e-6, true, false}, Case{250e-6, false, false}}) {
    fc::WaypointMission m = mission({Vec3(0.2, 0.0, 0.0)}, 0.005);
    m.course_time = 30.0;
    fc::SteeringGains gains;
    gains.trim_neutral = c.trim;
    fc::MassTransformerController controller(m, calibration(), gains);
    Plant plant;
    plant.slider_error = c.slider_error;
    plant.roll_rate = 0.0;
    run(controller, plant, 30.5);
    const double truth = calibration().park_position - c.slider_error;
    const std::string what = "slider error " + std::to_string(c.slider_error * 1e6) + " um" +
                             (c.trim ? "" : ", trim off");
    ASSERT_NE(controller.status().mode, fc::SteeringMode::Waiting) << what;
    // The plant pitches as the trim's model says, but its slider travels at 2.5 mm/s to the
    // commands the trim sees: within 3 um.
    EXPECT_NEAR(controller.status().trim_neutral, truth, 3e-6) << what;
    EXPECT_EQ(controller.status().trimmed, c.taken) << what;
    if (c.taken) {
      EXPECT_NEAR(controller.status().neutral, truth, 3e-6) << what;
    }
  }
}

TEST(MassTransformerController, ANeutralAndPitchRateTheModelGetsWrongAreReTrimmedFromThePitch) {
  // The true neutral 40 um off the park position and the pitch rate 25 % below the calibrated
  // one; the start frame's trim off, so only the re-trim can find them: from the pitch over
  // the mission (its cruise and its pitching offsets) it sets the neutral near the truth. Off,
  // it still reports its estimate and takes nothing.
  for (const bool retrim : {true, false}) {
    fc::SteeringGains gains;
    gains.trim_neutral = false;
    gains.retrim_neutral = retrim;
    gains.retrim_threshold = 8e-6;
    fc::MassTransformerController controller(mission({Vec3(0.5, 0.0, 0.0)}), calibration(), gains);
    Plant plant;
    plant.roll_rate = 0.0;
    plant.slider_error = -4e-5;
    plant.truth.pitch_rate_per_slider *= 0.75;
    run(controller, plant, 400.0);
    const double truth = calibration().park_position - plant.slider_error;
    const fc::SteeringStatus& s = controller.status();
    const std::string what = retrim ? "re-trim on" : "re-trim off";
    EXPECT_TRUE(std::isfinite(s.pitch_neutral) && std::isfinite(s.pitch_gain)) << what;
    if (retrim) {
      EXPECT_GE(s.retrims, 1) << what;
      EXPECT_NEAR(s.pitch_neutral, truth, 8e-6) << what;
      EXPECT_NEAR(s.neutral, truth, 1e-5) << what;
    } else {
      EXPECT_EQ(s.retrims, 0) << what;
    }
  }
}

TEST(MassTransformerController, AnAzimuthTheOffsetCannotTurnIsTurnedAtElevationAfterStallTime) {
  // A robot whose slider offset neither crabs nor turns it (a model wrong in the crab), a
  // waypoint 100 deg to the right: after stall_time with the error beyond stall_error the
  // controller pitches up, precesses right, and pitches back down once turned. With stall_time
  // 0 it never does.
  for (const double stall_time : {60.0, 0.0}) {
    fc::SteeringGains gains;
    gains.stall_time = stall_time;
    const double azimuth = -100 * kDeg;
    fc::MassTransformerController controller(
        mission({Vec3(0.5 * std::cos(azimuth), 0.5 * std::sin(azimuth), 0.0)}), calibration(),
        gains);
    Plant plant;
    plant.offset_crab = plant.offset_turn = 0.0;
    plant.roll_rate = 0.0;
    run(controller, plant, 55.0);
    EXPECT_EQ(controller.status().flips, 0) << "stall_time " << stall_time;
    bool reached_top = false;
    for (int k = 0; k < 400 && !(reached_top && !controller.status().flipping); ++k) {
      run(controller, plant, 1.0);
      reached_top = reached_top || controller.status().at_top;
    }
    if (stall_time > 0.0) {
      EXPECT_TRUE(reached_top);
      EXPECT_GE(controller.status().flips, 1);
      run(controller, plant, 60.0);
      EXPECT_LT(std::abs(fc::elevationOf(plant.forward)), 12 * kDeg);
      // Turned right by more than 45 deg (not to the waypoint's 100: the exit adds the crab the
      // controller believes its offset gives, and this plant has none).
      EXPECT_LT(fc::azimuthOf(plant.forward), -45 * kDeg);
    } else {
      EXPECT_EQ(controller.status().flips, 0);
    }
  }
}

// The earlier design's gains that never turn (no cycles, no offset steering, no turn at
// elevation): the kinematic plant swims straight on.
fc::SteeringGains straightOnGains() {
  fc::SteeringGains gains = legacyGains();
  gains.turn_threshold = gains.max_buckle_error = 1.5;
  gains.large_turn = gains.blocked_turn = M_PI;
  return gains;
}

TEST(MassTransformerController, AWaypointPassedWithinTheToleranceCountsAfterTheClosestApproach) {
  // No turning at all: the straight path passes the waypoint 6 mm to the side, beyond
  // reach_fraction x 10 mm but within the tolerance. It counts once the estimated distance has
  // grown by pass_margin past its minimum, not before.
  const fc::SteeringGains gains = straightOnGains();
  fc::MassTransformerController controller(mission({Vec3(0.03, 0.006, 0.0)}, 0.01), calibration(),
                                           gains);
  Plant plant = legacyPlant();
  plant.roll_rate = 0.0;
  double finished_x = -1.0;
  for (long k = 0; k < 200 * kRate && finished_x < 0.0; ++k) {
    plant.apply(controller.step(plant.sense()));
    if (controller.status().mode == fc::SteeringMode::Finished) finished_x = plant.position.x();
  }
  ASSERT_GT(finished_x, 0.0) << controller.status().message;
  EXPECT_EQ(controller.status().cycles, 0);
  // Past the closest approach (x = 30 mm) by the margin: sqrt((x-30)^2 + 6^2) = 7 mm.
  const double passed =
      std::sqrt(std::pow(0.006 + controller.gains().pass_margin, 2) - 0.006 * 0.006);
  EXPECT_NEAR(finished_x, 0.03 + passed, 1.5e-3);
}

TEST(MassTransformerController, APassBeyondPassFractionOfTheToleranceDoesNotCount) {
  // The same straight path, 6 mm to the side of the waypoint, with pass_fraction 0.5: a pass
  // counts within 5 mm only, so the waypoint is still ahead 10 mm past its closest approach.
  fc::SteeringGains gains = straightOnGains();
  gains.pass_fraction = 0.5;
  fc::MassTransformerController controller(mission({Vec3(0.03, 0.006, 0.0)}, 0.01), calibration(),
                                           gains);
  Plant plant = legacyPlant();
  plant.roll_rate = 0.0;
  for (long k = 0; k < 200 * kRate && plant.position.x() < 0.04; ++k)
    plant.apply(controller.step(plant.sense()));
  ASSERT_GE(plant.position.x(), 0.04) << "the plant did not get past the waypoint";
  EXPECT_EQ(controller.status().reached, 0);
  EXPECT_NE(controller.status().mode, fc::SteeringMode::Finished);
}

TEST(MassTransformerController, StepDoesNotAllocate) {
  fc::MassTransformerController controller(mission({Vec3(0.5, 0.1, 0.1), Vec3(0.0, 0.0, 0.0)}),
                                           calibration());
  Plant plant;
  g_allocations = 0;
  g_count_allocations = true;
  for (int k = 0; k < 5000; ++k) plant.apply(controller.step(plant.sense()));
  g_count_allocations = false;
  EXPECT_EQ(g_allocations.load(), 0);
}

TEST(MassTransformerController, InvalidGainsAndMissionsNameTheField) {
  fc::SteeringGains gains;
  gains.tilt_time_constant = -1.0;
  try {
    fc::MassTransformerController c(mission({Vec3(1, 0, 0)}), calibration(), gains);
    ADD_FAILURE() << "accepted a negative time constant";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("tilt_time_constant"), std::string::npos) << e.what();
  }
  try {
    fc::MassTransformerController c(mission({}), calibration());
    ADD_FAILURE() << "accepted an empty mission";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("points"), std::string::npos) << e.what();
  }
  // Gains by name (the node's parameters, --gain): every name reads back what it set.
  fc::SteeringGains named;
  for (const std::string& name : fc::SteeringGains::names()) {
    const double value = fc::SteeringGains::isFlag(name) ? 1.0 - named.get(name) : 0.123;
    named.set(name, value);
    EXPECT_EQ(named.get(name), value) << name;
  }
  try {
    named.set("max_steer_ofset", 1e-5);
    ADD_FAILURE() << "accepted an unknown gain";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("max_steer_offset"), std::string::npos) << e.what();
  }
  EXPECT_THROW(named.set("steer_by_offset", 0.5), std::invalid_argument);
  EXPECT_THROW(named.set("trim_neutral", 2.0), std::invalid_argument);
  fc::SteeringCalibration bad = calibration();
  bad.cruise_omega = 2.0;  // above the threshold
  EXPECT_THROW(fc::MassTransformerController(mission({Vec3(1, 0, 0)}), bad), std::invalid_argument);
}

}  // namespace
