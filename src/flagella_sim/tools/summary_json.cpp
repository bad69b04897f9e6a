#include "summary_json.h"

#include <nlohmann/json.hpp>
#include <variant>

#include "flagella_sim/core/units.h"

namespace flagella {

namespace {

// The robot's own fields (robot_model.h: n_tails and tail_length, or the helix).
void addRobot(const RobotModel& robot, nlohmann::ordered_json& j) {
  for (const SummaryField& f : robot.summaryFields())
    std::visit([&](const auto& value) { j[f.key] = value; }, f.value);
}

// docs/model.md 8.4.4: heading change and buckling indicator.
void addBucklingMetrics(const SimulationConfig& c, const SummaryMetrics& m,
                        nlohmann::ordered_json& j) {
  j["heading_change_deg"] = units::radToDeg(m.heading_change);
  j["flagellum_tilt_max_deg"] = units::radToDeg(m.flagellum_tilt_max);
  j["buckled"] = m.buckled;
  j["buckling_tilt_deg"] = c.buckling_tilt_deg;
}

}  // namespace

std::string summaryJson(const SimulationConfig& c, const SummaryMetrics& m, double wall_seconds) {
  nlohmann::ordered_json j;
  j["config"] = c.source;
  addRobot(*c.robot, j);
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
  if (c.robot->hasFlagellumTilt()) addBucklingMetrics(c, m, j);
  j["newton_iterations"] = m.newton_iterations;
  j["subdivided_steps"] = m.subdivided_steps;
  j["damped_steps"] = m.damped_steps;
  j["wall_time_s"] = wall_seconds;
  j["real_time_factor"] = wall_seconds > 0.0 ? m.window_end / wall_seconds : 0.0;
  return j.dump(2) + "\n";
}

}  // namespace flagella
