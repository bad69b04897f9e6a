#include "flagella_sim/outputs/output_writers.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <stdexcept>

namespace flagella {

namespace {
std::ofstream openOrThrow(const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  out << std::setprecision(10);
  return out;
}
}  // namespace

std::string trajectoryCsvHeader() {
  return "time,head_x,head_y,head_z,head_qw,head_qx,head_qy,head_qz,head_axis_x,head_axis_y,"
         "head_axis_z,omega_h,omega_t,omega_T,speed,yaw,yaw_rate,head_angle,tail_angle,"
         "newton_iterations,subdivided_steps,omega_motor,flagellum_tilt";
}

void writeTrajectoryCsv(const std::string& path, const std::vector<TrajectorySample>& samples) {
  std::ofstream out = openOrThrow(path);
  out << trajectoryCsvHeader() << "\n";
  for (const TrajectorySample& s : samples) {
    const Eigen::Quaterniond& q = s.head_orientation;
    out << s.time << "," << s.head_position.x() << "," << s.head_position.y() << ","
        << s.head_position.z() << "," << q.w() << "," << q.x() << "," << q.y() << "," << q.z()
        << "," << s.head_axis.x() << "," << s.head_axis.y() << "," << s.head_axis.z() << ","
        << s.omega_h << "," << s.omega_t << "," << s.omega_T << "," << s.head_velocity.norm() << ","
        << s.yaw << "," << s.yaw_rate << "," << s.head_angle << "," << s.tail_angle << ","
        << s.newton_iterations << "," << s.subdivided_steps << "," << s.omega_motor << ","
        << s.flagellum_tilt << "\n";
  }
}

void writeNodesCsv(const std::string& path, const std::vector<TrajectorySample>& samples) {
  std::ofstream out = openOrThrow(path);
  out << "time,node,x,y,z\n";
  for (const TrajectorySample& s : samples)
    for (size_t i = 0; i < s.nodes.size(); ++i)
      out << s.time << "," << i << "," << s.nodes[i].x() << "," << s.nodes[i].y() << ","
          << s.nodes[i].z() << "\n";
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out = openOrThrow(path);
  out << text;
}

}  // namespace flagella
