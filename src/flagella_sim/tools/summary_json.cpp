#include "summary_json.h"

#include <nlohmann/json.hpp>

#include "flagella_sim/core/units.h"

namespace flagella {

namespace {

// docs/model.md 8.4: the helix that replaces n_tails and tail_length in the summary.
void addHelicalRobot(const HelicalGeometry& g, nlohmann::ordered_json& j) {
  j["robot"] = "helical";
  j["pitch_count"] = g.pitch_count;
  j["pitch_m"] = g.pitch;
  j["helix_radius_m"] = g.helix_radius;
  j["axial_length_m"] = g.axialLength();
  j["filament_radius_m"] = g.flagellum.radius;
  j["handedness"] = g.handedness == kLeftHanded ? "left" : "right";
  j["mount"] = g.mount == HelicalMount::kGimbal ? "gimbal" : "untethered";
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
  if (c.isHelical()) {
    addHelicalRobot(c.helical, j);
  } else {
    j["n_tails"] = c.geometry.n_tails;
    j["tail_length_m"] = c.geometry.tail_length;
  }
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
  if (c.isHelical()) addBucklingMetrics(c, m, j);
  j["newton_iterations"] = m.newton_iterations;
  j["subdivided_steps"] = m.subdivided_steps;
  j["damped_steps"] = m.damped_steps;
  j["wall_time_s"] = wall_seconds;
  j["real_time_factor"] = wall_seconds > 0.0 ? m.window_end / wall_seconds : 0.0;
  return j.dump(2) + "\n";
}

}  // namespace flagella
