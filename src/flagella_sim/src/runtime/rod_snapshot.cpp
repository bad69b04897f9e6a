#include "flagella_sim/runtime/rod_snapshot.h"

#include <cmath>

#include "flagella_sim/outputs/fits.h"
#include "flagella_sim/rod/rod_kinematics.h"
#include "flagella_sim/simulation/simulation.h"

namespace flagella {

namespace {
bool finite(const Eigen::Quaterniond& q) { return q.coeffs().allFinite(); }
}  // namespace

bool RodSnapshot::allFinite() const {
  for (const Vec3& x : nodes)
    if (!x.allFinite()) return false;
  for (double a : edge_twist)
    if (!std::isfinite(a)) return false;
  for (const auto& q : edge_frames)
    if (!finite(q)) return false;
  return std::isfinite(time) && std::isfinite(omega_h) && std::isfinite(omega_t) &&
         std::isfinite(omega_motor) && std::isfinite(head_angle) && std::isfinite(tail_angle) &&
         head_position.allFinite() && finite(head_orientation);
}

Eigen::Quaterniond outputFromSimulationFrame(const Vec3& up) {
  return Eigen::Quaterniond::FromTwoVectors(up.normalized(), Vec3::UnitZ());
}

RodSnapshot takeSnapshot(const Simulation& sim, const Eigen::Quaterniond& output_from_sim) {
  const RodNetwork& net = sim.network();
  const RodState& state = sim.state();
  const Eigen::Matrix3d rotation = output_from_sim.toRotationMatrix();
  RodSnapshot s;
  s.time = state.time;
  s.robot_name = sim.config().robotType();
  s.nodes.reserve(net.numNodes());
  for (int i = 0; i < net.numNodes(); ++i) s.nodes.push_back(rotation * nodePosition(state.q, i));
  for (int j = 0; j < net.numEdges(); ++j) {
    s.edge_start.push_back(net.edges[j].start_node);
    s.edge_end.push_back(net.edges[j].end_node);
    s.edge_twist.push_back(state.q(net.thetaIndex(j)));
    const Vec3 t = rotation * state.frames.tangent[j];
    const Vec3 m1 = rotation * materialDirector1(state.frames, state.q, net, j);
    s.edge_frames.push_back(quaternionFromFrame(m1, t.cross(m1), t));
  }
  s.head_nodes = net.parts.head_nodes;
  s.tail_nodes = net.parts.tail_nodes;
  const TrajectorySample sample = sim.sample();
  s.omega_h = sample.omega_h;
  s.omega_t = sample.omega_t;
  s.omega_motor = sim.lastMotorCommand();
  s.head_angle = sample.head_angle;
  s.tail_angle = sample.tail_angle;
  s.head_position = rotation * sample.head_position;
  s.head_orientation = (output_from_sim * sample.head_orientation).normalized();
  return s;
}

}  // namespace flagella
