#include "flagella_control/waypoint_mission.h"

#include <cmath>
#include <stdexcept>

#include "flagella_control/validation.h"
#include "flagella_control/yaml_text.h"
#include "flagella_sim/core/parameter_set.h"

namespace flagella::control {

namespace {
constexpr double kMaxCoordinate = 100.0;  // [m]
constexpr std::size_t kMaxPoints = 1000;
}  // namespace

void WaypointMission::validate() const {
  if (points.empty() || points.size() > kMaxPoints)
    throw std::invalid_argument("waypoints: points must hold 1 to " + std::to_string(kMaxPoints) +
                                " points, got " + std::to_string(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i)
    for (int k = 0; k < 3; ++k)
      requireInRange("waypoints", "points[" + std::to_string(i) + "][" + std::to_string(k) + "]",
                     points[i][k], -kMaxCoordinate, kMaxCoordinate);
  requireInRange("waypoints", "tolerance", tolerance, 1e-4, 10.0);
  requireInRange("waypoints", "course_time", course_time, 0.0, 600.0);
}

WaypointMission loadWaypointMission(const std::string& path) {
  const YAML::Node node = loadSingleKeyFile(path, "waypoints", "waypoints");
  MapReader m(node, "waypoints", path, "waypoints");
  WaypointMission mission;
  const std::string frame = m.string("frame");
  if (frame == "start") {
    mission.frame = PathFrame::Start;
  } else if (frame == "world") {
    mission.frame = PathFrame::World;
  } else {
    m.fail("waypoints.frame", "must be 'start' or 'world', got '" + frame + "'");
  }
  mission.tolerance = m.number("tolerance");
  const YAML::Node points = m.get("points");
  if (!points.IsSequence()) m.fail("waypoints.points", "must be a list of [x, y, z] points");
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::string name = "waypoints.points[" + std::to_string(i) + "]";
    if (!points[i].IsSequence() || points[i].size() != 3) m.fail(name, "must be [x, y, z] in m");
    Eigen::Vector3d p;
    for (int k = 0; k < 3; ++k)
      p[k] = m.parseNumber(points[i][k], name + "[" + std::to_string(k) + "]");
    mission.points.push_back(p);
  }
  if (m.has("description")) mission.description = m.string("description");
  if (m.has("course_time")) mission.course_time = m.number("course_time");
  m.rejectUnknown();
  try {
    mission.validate();
  } catch (const std::invalid_argument& e) {
    throw InputFileError(path + ": " + e.what());
  }
  if (mission.description.empty())
    mission.description = std::to_string(mission.points.size()) + " waypoints";
  return mission;
}

Eigen::Vector3d worldWaypoint(const WaypointMission& mission, const Eigen::Vector3d& p,
                              const Eigen::Vector3d& origin, double azimuth) {
  if (mission.frame == PathFrame::World) return p;
  const double c = std::cos(azimuth), s = std::sin(azimuth);
  return origin + Eigen::Vector3d(c * p.x() - s * p.y(), s * p.x() + c * p.y(), p.z());
}

}  // namespace flagella::control
