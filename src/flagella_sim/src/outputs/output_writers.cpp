#include "flagella_sim/outputs/output_writers.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <nlohmann/json.hpp>
#include <stdexcept>

#include "flagella_sim/core/units.h"

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
         "newton_iterations,subdivided_steps,omega_motor";
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
        << s.newton_iterations << "," << s.subdivided_steps << "," << s.omega_motor << "\n";
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

std::string summaryJson(const SimulationConfig& c, const SummaryMetrics& m, double wall_seconds) {
  nlohmann::ordered_json j;
  j["config"] = c.source;
  j["n_tails"] = c.geometry.n_tails;
  j["tail_length_m"] = c.geometry.tail_length;
  j["dt_s"] = c.dt;
  j["duration_s"] = m.window_end;
  j["steady_window_s"] = {m.window_start, m.window_end};
  j["omega_T_rpm"] = units::radPerSecToRpm(c.motor.omega);
  j["omega_T_mean_abs_rad_s"] = m.omega_T_mean;
  j["omega_motor_mean_abs_rad_s"] = m.omega_motor_mean;
  j["omega_h_rad_s"] = m.omega_h;
  j["omega_t_rad_s"] = m.omega_t;
  j["omega_h_rpm"] = units::radPerSecToRpm(m.omega_h);
  j["omega_t_rpm"] = units::radPerSecToRpm(m.omega_t);
  j["omega_h_signed_rad_s"] = m.omega_h_signed;
  j["omega_t_signed_rad_s"] = m.omega_t_signed;
  j["speed_m_s"] = m.speed;
  j["speed_mm_s"] = units::metresToMm(m.speed);
  j["net_speed_m_s"] = m.net_speed;
  j["path_speed_m_s"] = m.path_speed;
  j["yaw_rate_rad_s"] = m.yaw_rate;
  j["circle_radius_m"] =
      m.circle_valid ? nlohmann::ordered_json(m.circle_radius) : nlohmann::ordered_json(nullptr);
  j["axis_path_angle_deg"] = units::radToDeg(m.axis_path_angle);
  j["efficiency"] =
      m.efficiency_valid ? nlohmann::ordered_json(m.efficiency) : nlohmann::ordered_json(nullptr);
  j["newton_iterations"] = m.newton_iterations;
  j["subdivided_steps"] = m.subdivided_steps;
  j["damped_steps"] = m.damped_steps;
  j["wall_time_s"] = wall_seconds;
  j["real_time_factor"] = wall_seconds > 0.0 ? m.window_end / wall_seconds : 0.0;
  return j.dump(2) + "\n";
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out = openOrThrow(path);
  out << text;
}

}  // namespace flagella
