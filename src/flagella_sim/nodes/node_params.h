// Reading and validating the sim node's private parameters. Every error names the parameter
// and its allowed range (flagella::ConfigError).
#pragma once

#include <ros/ros.h>

#include <string>
#include <vector>

#include "flagella_sim/runtime/sim_session.h"

namespace flagella::sim_node {

struct SimNodeOptions;

/// A double parameter in [min, max], or `fallback` if unset.
double rangedParam(const ros::NodeHandle& nh, const std::string& name, double fallback, double min,
                   double max, const std::string& unit);
/// A 3-vector parameter (list of 3 numbers), or `fallback` if unset.
flagella::Vec3 vectorParam(const ros::NodeHandle& nh, const std::string& name,
                           const flagella::Vec3& fallback);
/// Config overrides "a.b=v c.d=w" (whitespace separated) as a list.
std::vector<std::string> splitOverrides(const std::string& text);
/// The session options (motor range, failsafe, slider, IMU, camera) from parameters.
flagella::SessionOptions sessionOptionsFromParams(const ros::NodeHandle& nh);
/// The node's own options (config path, frames, rates, waits, lockstep, followers, markers) from
/// the private handle `pnh`; the default tf_prefix is `nh`'s namespace ('/' -> '_', "" ->
/// "flagella").
SimNodeOptions nodeOptionsFromParams(const ros::NodeHandle& nh, const ros::NodeHandle& pnh);

}  // namespace flagella::sim_node
