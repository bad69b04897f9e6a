// The simulator's outputs in the message schema of flagella_msgs, as LCM twins (ROS-free). The
// ROS node converts these to ROS messages with flagella_msgs/lcm_conversions.h, so the schema
// is filled in exactly one place.
#pragma once

#include <flagella_lcm/imu_t.hpp>
#include <flagella_lcm/point_stamped_t.hpp>
#include <flagella_lcm/rod_state_t.hpp>
#include <string>

#include "flagella_sim/runtime/camera_model.h"
#include "flagella_sim/runtime/imu_model.h"
#include "flagella_sim/runtime/rod_snapshot.h"

namespace flagella {

/// LCM channel names of one robot: PREFIX + ROD_STATE, IMU, MOTOR_COMMAND, SLIDER_COMMAND,
/// CONTROLLER_STATUS, CAMERA_FIX (the bridge, the harness and any LCM controller agree on these).
struct LcmChannels {
  std::string rod_state, imu, motor_command, slider_command, controller_status, camera_fix;
  static LcmChannels withPrefix(const std::string& prefix);
};

/// Header stamp from simulated time [s].
flagella_lcm::header_t lcmHeader(double time, const std::string& frame_id, int seq = 0);

flagella_lcm::rod_state_t toRodStateMessage(const RodSnapshot& snapshot,
                                            const std::string& world_frame);

/// REP-145: diagonal covariances from the variances; orientation is provided, so its
/// covariance[0] is never -1.
flagella_lcm::imu_t toImuMessage(const ImuSample& sample, const std::string& imu_frame);

/// The camera fix as geometry_msgs/PointStamped in `world_frame` (z = 0).
flagella_lcm::point_stamped_t toCameraFixMessage(const CameraFix& fix,
                                                 const std::string& world_frame);

/// Seconds of a header stamp.
double stampSeconds(const flagella_lcm::header_t& header);

}  // namespace flagella
