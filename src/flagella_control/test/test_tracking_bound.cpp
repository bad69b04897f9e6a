// The dead-time switching model and the tracking bound (docs/model.md 7.5): the model against the
// closed forms of steady circling and against the measured advance it is fitted to; the bound's
// schedule flown again independently; its invariance under rigid motions of the path; its
// refinement; the errors.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <stdexcept>
#include <string>

#include "flagella_control/path_controllers.h"
#include "flagella_control/path_spec.h"
#include "flagella_control/switch_planner.h"
#include "flagella_control/switching_model.h"
#include "flagella_control/tracking_bound.h"
#include "flagella_control/tracking_bound_report.h"
#include "support/kinematic_plant.h"

using namespace flagella::control::testing;  // NOLINT: the plant's calibration

namespace {

const std::string kCalibration =
    std::string(FLAGELLA_CONFIG_DIR) + "/calibration/interface_path_planning.yaml";

/// A plant without transients (support/kinematic_plant.h): its dead time is 0.
fc::BinaryCalibration idealCalibration() { return nominalCalibration(); }

fc::Path square(double side) {
  fc::PathSpec spec;
  spec.path = fc::Path::polyline({{0, 0}, {side, 0}, {side, side}, {0, side}}, true);
  return spec.path;
}

}  // namespace

TEST(DeadTimeModel, HeldSignDrawsTheCalibratedCircle) {
  const fc::BinaryCalibration c = fc::loadCalibration(kCalibration);
  const fc::DeadTimeModel model(c);
  for (int sign : {+1, -1}) {
    const fc::SignResponse& r = sign > 0 ? c.plus : c.minus;
    const double radius = r.speed / std::abs(r.yaw_rate);
    // The measured least-squares circle agrees with speed / yaw rate (independent figures).
    EXPECT_NEAR(radius, r.circle_radius, 0.01 * r.circle_radius);
    // A held sign after a switch: still for the dead time, then on the circle. Half a turn
    // later the head is a diameter away; a whole turn brings it back.
    const double half_turn = M_PI / std::abs(r.yaw_rate);
    const double plus = sign > 0 ? c.switch_period : 0.0;  // the whole period at `sign`
    const double t_half = model.deadTime() + half_turn;
    ASSERT_LT(t_half, 10.0 * c.switch_period);
    // Fly whole periods holding the sign, then the rest.
    Vec2 p = Vec2::Zero();
    double heading = 0.3;
    int previous = -sign;
    double dead = 0.0, t = 0.0;
    while (t + c.switch_period <= t_half) {
      const fc::ModelMotion m = model.until(heading, previous, dead, plus, c.switch_period);
      p += m.displacement;
      heading += m.turn;
      dead = m.dead_remaining;
      previous = sign;
      t += c.switch_period;
    }
    const fc::ModelMotion m = model.until(heading, previous, dead, plus, t_half - t);
    p += m.displacement;
    // The calibrated heading drift per period (3e-6 rad) turns the pieces a little: 1e-4.
    EXPECT_NEAR(p.norm(), 2.0 * radius, 1e-4 * radius) << "sign " << sign;
  }
}

TEST(DeadTimeModel, SwitchingReproducesTheMeasuredAdvance) {
  const fc::BinaryCalibration c = fc::loadCalibration(kCalibration);
  const fc::DeadTimeModel model(c);
  EXPECT_GT(model.deadTime(), 0.0);
  EXPECT_LT(model.deadTime(), 0.5 * c.switch_period);
  // One period of steady switching (+ half entered from -).
  const fc::ModelMotion m = model.until(0.0, -1, 0.0, 0.5 * c.switch_period, c.switch_period);
  EXPECT_NEAR(m.displacement.norm(), c.advance_per_period, 1e-12);
  EXPECT_NEAR(m.displacement.norm(), model.modelAdvance(), 1e-12);
  // Its direction is not fitted: it agrees with the measured one to a few degrees.
  EXPECT_LT(std::abs(model.directionMismatch()), 3.0 * M_PI / 180.0);
  // A plant without transients needs no dead time.
  EXPECT_LT(fc::DeadTimeModel(idealCalibration()).deadTime(), 1e-3);
}

TEST(DeadTimeModel, DeadTimeRunsOnAcrossAPeriodBoundary) {
  const fc::BinaryCalibration c = fc::loadCalibration(kCalibration);
  const fc::DeadTimeModel model(c);
  const double T = c.switch_period, tau = model.deadTime();
  ASSERT_GT(tau, 0.1);
  // + for T - 0.1 s, then - for 0.1 s: the switch's dead time is not over at the period's end.
  const fc::ModelMotion first = model.until(0.0, +1, 0.0, T - 0.1, T);
  EXPECT_NEAR(first.dead_remaining, tau - 0.1, 1e-12);
  // A whole period at - begun there moves for T - (tau - 0.1): the steady arc, closed form.
  const fc::ModelMotion second = model.until(1.0, -1, first.dead_remaining, 0.0, T);
  const double moving = T - (tau - 0.1);
  const Vec2 expected = fc::holdDisplacement(c.minus, 1.0, c.minus.yaw_rate * moving);
  EXPECT_LT((second.displacement - expected).norm(), 1e-12);
  EXPECT_NEAR(second.turn, c.minus.yaw_rate * moving + c.heading_drift_per_period, 1e-12);
  // Up to a time inside the period: the + part alone.
  const fc::ModelMotion part = model.until(0.0, -1, 0.0, 4.0, 4.0);
  const Vec2 arc = fc::holdDisplacement(c.plus, 0.0, c.plus.yaw_rate * (4.0 - tau));
  EXPECT_LT((part.displacement - arc).norm(), 1e-12);
}

TEST(DeadTimeModel, ScaledResponses) {
  const fc::BinaryCalibration c = fc::loadCalibration(kCalibration);
  const fc::DeadTimeModel model(c);
  const fc::DeadTimeModel same = model.scaled(1.0);
  EXPECT_DOUBLE_EQ(same.deadTime(), model.deadTime());
  const fc::DeadTimeModel slow = model.scaled(0.7);
  EXPECT_DOUBLE_EQ(slow.yawRate(+1), 0.7 * c.plus.yaw_rate);
  EXPECT_DOUBLE_EQ(slow.yawRate(-1), 0.7 * c.minus.yaw_rate);
  // The sideways velocity scaled, the axial one kept: a whole period at + after a switch moves
  // on the circle of radius speed / yaw rate, chord 2 R sin(w (T - tau) / 2) (closed form).
  const double T = c.switch_period;
  const double speed = std::hypot(c.plus.body_velocity[0], 0.7 * c.plus.body_velocity[1]);
  const double w = std::abs(slow.yawRate(+1));
  const fc::ModelMotion arc = slow.until(0.0, -1, 0.0, T, T);
  EXPECT_NEAR(arc.displacement.norm(), 2.0 * speed / w * std::sin(0.5 * w * (T - slow.deadTime())),
              1e-12);
  // Fitted again: the same advance per period as measured.
  const fc::ModelMotion m = slow.until(0.0, -1, 0.0, 0.5 * c.switch_period, c.switch_period);
  EXPECT_NEAR(m.displacement.norm(), c.advance_per_period, 1e-12);
}

TEST(TrackingBound, ScheduleFlownAgainGivesTheReportedErrors) {
  const fc::BinaryCalibration c = fc::loadCalibration(kCalibration);
  const fc::Path path = square(0.3);
  const fc::TrackingBoundOptions options;
  const fc::TrackingBound bound = fc::computeTrackingBound(path, 1, c, options);
  ASSERT_TRUE(bound.best_max.complete);
  ASSERT_TRUE(bound.best_rms.complete);
  ASSERT_TRUE(bound.plan.complete);
  EXPECT_LE(bound.best_rms.rms_error, bound.best_max.rms_error);
  EXPECT_LE(bound.best_max.max_error, bound.best_rms.max_error);
  // The plan stays in its tube about the max bound.
  EXPECT_LE(bound.plan.max_error, options.plan_error_cap_factor * bound.best_max.max_error);
  const fc::DeadTimeModel model(c);
  for (const fc::BoundSchedule* s : {&bound.best_max, &bound.best_rms, &bound.plan}) {
    // Fly the schedule with the model, sampled every 0.5 s, and measure as TrackingStats does.
    const fc::PathPoint start = path.at(0.0);
    Vec2 p = start.position;
    double heading = start.tangent - c.advance_angle, dead = 0.0, max_e = 0.0, sum_sq = 0.0;
    long samples = 1;
    int previous = 0;
    Vec2 last = p;
    const int per_period = 20;
    long remaining = static_cast<long>(std::lround(s->duration / 0.5));
    for (double plus : s->plus_durations) {
      fc::ModelMotion m;
      for (int k = 1; k <= per_period && remaining > 0; ++k, --remaining) {
        m = model.until(heading, previous, dead, plus, 0.5 * k);
        last = p + m.displacement;
        const double e = path.project(last).distance;
        max_e = std::max(max_e, e);
        sum_sq += e * e;
        ++samples;
      }
      p += m.displacement;
      heading += m.turn;
      dead = m.dead_remaining;
      previous = plus < c.switch_period ? -1 : 1;
    }
    EXPECT_NEAR(max_e, s->max_error, 1e-12);
    EXPECT_NEAR(std::sqrt(sum_sq / samples), s->rms_error, 1e-12);
    EXPECT_EQ(static_cast<size_t>(samples), s->samples.size());
    // It ends at the path's end (the square closes at its start), within the tolerance.
    EXPECT_LT((last - start.position).norm(), 0.02 + s->max_error);
    // Far better than the old controller's measured 52 mm, and not zero (the switching wiggle).
    EXPECT_GT(s->max_error, 1e-3);
  }
}

TEST(TrackingBound, SameForThePathMovedRigidly) {
  const fc::BinaryCalibration c = idealCalibration();
  const fc::Path path = square(0.2);
  const fc::TrackingBound here = fc::computeTrackingBound(path, 1, c);
  const fc::TrackingBound there =
      fc::computeTrackingBound(path.transformed(Vec2(0.37, -1.2), 2.1), 1, c);
  ASSERT_TRUE(here.best_max.complete && there.best_max.complete);
  EXPECT_NEAR(there.best_max.max_error, here.best_max.max_error, 0.05 * here.best_max.max_error);
  EXPECT_NEAR(there.best_rms.rms_error, here.best_rms.rms_error, 0.05 * here.best_rms.rms_error);
}

TEST(TrackingBound, NoWorseThanSteadySwitchingOnALine) {
  // Straight line: periodic switching with equal halves is one schedule among those searched.
  const fc::BinaryCalibration c = fc::loadCalibration(kCalibration);
  const fc::Path line = fc::Path::polyline({{0, 0}, {0.15, 0}}, false);
  const fc::TrackingBound bound = fc::computeTrackingBound(line, 1, c);
  ASSERT_TRUE(bound.best_max.complete);
  const fc::DeadTimeModel model(c);
  Vec2 p = line.at(0.0).position;
  double heading = -c.advance_angle, dead = 0.0, max_e = 0.0;
  int previous = 0;
  for (int period = 0; period < 100 && (p - Vec2(0.15, 0)).norm() > 0.02; ++period) {
    fc::ModelMotion m;
    for (int k = 1; k <= 20; ++k) {
      m = model.until(heading, previous, dead, 0.5 * c.switch_period, 0.5 * k);
      max_e = std::max(max_e, line.project(p + m.displacement).distance);
    }
    p += m.displacement;
    heading += m.turn;
    dead = m.dead_remaining;
    previous = -1;
  }
  EXPECT_LE(bound.best_max.max_error, max_e);
}

TEST(TrackingBound, SettlesAsTheGridRefines) {
  const fc::BinaryCalibration c = fc::loadCalibration(kCalibration);
  const fc::Path path = startFramePolyline().path;  // an open zigzag (faster than the square)
  const fc::TrackingBound coarse = fc::computeTrackingBound(path, 1, c);
  const fc::TrackingBound fine =
      fc::computeTrackingBound(path, 1, c, fc::refinedOptions(fc::TrackingBoundOptions{}));
  EXPECT_NEAR(fine.best_max.max_error, coarse.best_max.max_error, 0.15 * coarse.best_max.max_error);
  EXPECT_NEAR(fine.best_rms.rms_error, coarse.best_rms.rms_error, 0.15 * coarse.best_rms.rms_error);
}

TEST(TrackingBound, ErrorsNameTheField) {
  const fc::BinaryCalibration c = idealCalibration();
  const auto message = [&](fc::TrackingBoundOptions o, const fc::Path& path, int laps) {
    try {
      fc::computeTrackingBound(path, laps, c, o);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  fc::TrackingBoundOptions o;
  o.duty_steps = 0;
  EXPECT_NE(message(o, square(0.2), 1).find("duty_steps"), std::string::npos);
  o = {};
  o.sample_interval = NAN;
  EXPECT_NE(message(o, square(0.2), 1).find("sample_interval"), std::string::npos);
  o = {};
  o.rms_time_factor = 0.5;
  EXPECT_NE(message(o, square(0.2), 1).find("rms_time_factor"), std::string::npos);
  EXPECT_NE(message({}, fc::Path(), 1).find("empty"), std::string::npos);
  EXPECT_NE(message({}, square(0.2), 0).find("laps"), std::string::npos);
  // A path no schedule can keep within the largest cap: incomplete, said so.
  o = {};
  o.max_duration = 50.0;  // 5 periods: the square cannot be flown
  const fc::TrackingBound none = fc::computeTrackingBound(square(0.2), 1, c, o);
  EXPECT_FALSE(none.best_max.complete);
  EXPECT_EQ(fc::describeBound(none, 0.11), "bound: no schedule completes the path");
}
