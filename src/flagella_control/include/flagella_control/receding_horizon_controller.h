// Receding-horizon path following near the tracking bound (docs/model.md 7.5; ControllerCore
// contract: fixed step, no heap allocation in step(), binary output).
// At construction the bound's search (tracking_bound.h) plans the schedule of the smallest RMS
// error whose max error stays within 5 % of the max bound, on the calibrated model, with perfect
// state. Running, the pose estimate of the
// line-of-sight controller (PathFollowingController, run alongside) is matched to the plan once
// per switching period, and the share of +omega of the period begun is the first of the
// `horizon` shares whose predicted head path (DeadTimeModel) stays closest to the plan's next
// periods. Far from the plan, or past its end, the line-of-sight controller decides (fallback).
#pragma once

#include <vector>

#include "flagella_control/path_controllers.h"
#include "flagella_control/switching_model.h"
#include "flagella_control/tracking_bound.h"

namespace flagella::control {

struct RecedingHorizonGains {
  int horizon = 2;                  ///< switching periods looked ahead, 1..3
  int duty_steps = 20;              ///< candidate shares of +omega per period: k / duty_steps
  double heading_weight = 0.02;     ///< metres a radian of heading error counts as [m/rad]
  double fallback_distance = 0.04;  ///< further than this from the plan: fallback [m]
  /// Response scale estimate: forgetting factor per period, and the weight of the prior 1 as a
  /// turn [rad] (docs/model.md 7.5).
  double adaptation_forgetting = 0.9;
  double adaptation_prior = 0.1;
  bool adapt = true;          ///< scale the model's responses by the turns the IMU measures
  bool replan_at_fix = true;  ///< choose the switch time again at each camera fix
  double path_weight = 1.0;   ///< weight of the predicted distance to the path (to the plan's: 1)
  /// Throws std::invalid_argument naming the field and its range.
  void validate() const;
};

class RecedingHorizonController : public PathControllerBase {
 public:
  /// Plans the path (a few seconds). Throws std::invalid_argument for bad gains, a path no
  /// schedule completes, or an unusable calibration.
  RecedingHorizonController(PathSpec spec, BinaryCalibration calibration,
                            RecedingHorizonGains gains = {}, PathFollowingGains fallback = {},
                            TrackingBoundOptions plan_options = {});
  ControllerOutputs step(const ControllerInputs& inputs) override;
  void reset() override;
  const char* name() const override { return "receding_horizon_path_following"; }
  /// Estimated head position (world; the line-of-sight controller's estimator).
  const Vec2& estimatedPosition() const { return inner_.estimatedPosition(); }
  /// Periods decided by the plan and by the fallback so far.
  long plannedPeriods() const { return planned_periods_; }
  long fallbackPeriods() const { return fallback_periods_; }
  /// The tracking bound the plan came from (its `plan` schedule is the plan).
  const TrackingBound& bound() const { return bound_; }
  /// Measured / modelled turn of the held signs (1: the calibration is right).
  double responseScale() const { return response_scale_; }

 private:
  struct PlanState {  ///< the plan at one of its samples
    Vec2 position = Vec2::Zero();
    double heading = 0.0;
  };
  void anchorPlan();
  void decide(double time);
  void adaptModel();
  void replanAtFix(double time);
  double deadTimeLeft(double time) const;
  double sequenceCost(const Vec2& position, double heading, int sign, double dead, int base,
                      double elapsed, int depth, double& first_plus) const;

  RecedingHorizonGains gains_;
  TrackingBound bound_;
  PathFollowingController inner_;
  DeadTimeModel model_;   ///< as calibrated (the plan's)
  DeadTimeModel active_;  ///< scaled by the response estimate (the horizon's)
  int samples_per_period_ = 1;
  /// The plan every sample interval from its start (samples_per_period_ per period).
  std::vector<PlanState> plan_, plan_world_;
  Vec2 frame_start_ = Vec2::Zero();
  double frame_tangent_ = 0.0;
  bool plan_anchored_ = false;
  int base_ = 0;  ///< plan sample matched to the start of the period under way
  bool use_fallback_ = true;
  double period_start_ = 0.0, plus_ = 0.0, progress_ = 0.0;
  int applied_sign_ = 0;
  // Response estimate: turn measured by the IMU against the calibrated turn of the signs held.
  double last_switch_time_ = 0.0, last_step_time_ = 0.0, decided_heading_ = 0.0;
  double adapted_at_ = 0.0;
  double predicted_turn_ = 0.0, sum_mp_ = 0.0, sum_pp_ = 0.0, response_scale_ = 1.0;
  long planned_periods_ = 0, fallback_periods_ = 0;
};

}  // namespace flagella::control
