// Time series from bags of the simulator node's own topics (<ns>/rod_state, optionally
// <ns>/camera_fix). The only ROS-dependent part of flagella_identify: link
// flagella_identify_bag and call enableBagInput() so that readMeasuredData accepts `bag:`
// metadata.
#pragma once

#include <string>

#include "flagella_identify/data_io.h"

namespace flagella {
namespace identify {

/// Reads <ns>/rod_state (flagella_msgs/RodState) and, for Position::kCameraFix,
/// <ns>/camera_fix (geometry_msgs/PointStamped) from a bag:
/// - t: header stamps minus the first (rod_state, or the camera fixes inside the rod_state
///   time span for kCameraFix); messages repeating the previous stamp are skipped;
/// - position: head_pose.position (or the fix), has_z = true;
/// - orientation: head_pose.orientation (normalised);
/// - head_turns / tail_turns: (angle - first angle) / (2 pi), signed;
/// - omega_cmd: omega_motor.
/// For kCameraFix the angles and the orientation are interpolated (linear / slerp) between
/// the neighbouring rod_state samples and omega_cmd is held from the last one at or before.
/// source = bag_path; noise and metadata are left at their defaults. Throws DataError naming
/// the bag (and the topic) for an unreadable file, an empty bag, a missing topic, a topic of
/// the wrong type, stamps going backwards or fewer than 3 samples.
TimeSeries readTimeSeriesFromBag(const std::string& bag_path, const BagOptions& options);

/// Registers readTimeSeriesFromBag with readMeasuredData (registerBagReader).
void enableBagInput();

}  // namespace identify
}  // namespace flagella
