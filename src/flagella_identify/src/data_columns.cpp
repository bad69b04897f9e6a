// The measured columns of steady-state tables and the names config overrides may use.
#include <algorithm>

#include "data_io_internal.h"
#include "flagella_sim/core/text_lists.h"
#include "flagella_sim/core/units.h"
#include "text_format.h"

namespace flagella {
namespace identify {
namespace data_io {

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

const std::vector<MeasuredColumn>& measuredColumns() {
  static const std::vector<MeasuredColumn> columns = {
      {"v_mm_s", "v", kMetresPerMm, -kMaxSpeedMmS, kMaxSpeedMmS, "mm/s"},
      {"omega_h_rpm", "omega_h", kRadPerSecPerRpm, -kMaxRpm, kMaxRpm, "rpm"},
      {"omega_t_rpm", "omega_t", kRadPerSecPerRpm, -kMaxRpm, kMaxRpm, "rpm"},
      {"omega_yr_rad_s", "omega_yr", 1.0, -kMaxYawRateRadS, kMaxYawRateRadS, "rad/s"},
      {"R_yr_mm", "R_yr", kMetresPerMm, 0.0, kMaxLengthMm, "mm"},
      {"buckling_threshold_rpm", "buckling_threshold", kRadPerSecPerRpm, 0.0, kMaxRpm, "rpm"},
      {"tilt_deg", "tilt", units::degToRad(1.0), 0.0, 180.0, "deg"}};
  return columns;
}

const MeasuredColumn* measuredByColumn(const std::string& column) {
  for (const MeasuredColumn& m : measuredColumns())
    if (column == m.column) return &m;
  return nullptr;
}

const MeasuredColumn* measuredByOutput(const std::string& output) {
  for (const MeasuredColumn& m : measuredColumns())
    if (output == m.output) return &m;
  return nullptr;
}

const MeasuredColumn* sigmaColumnOf(const std::string& column) {
  const std::string prefix = "sigma_";
  if (column.compare(0, prefix.size(), prefix) != 0) return nullptr;
  return measuredByColumn(column.substr(prefix.size()));
}

std::vector<std::string> measuredColumnNames() {
  std::vector<std::string> names;
  for (const MeasuredColumn& m : measuredColumns()) names.push_back(m.column);
  return names;
}

std::string overrideNameProblem(const std::string& name) {
  const size_t dot = name.find('.');
  if (dot == std::string::npos || dot == 0 || name.back() == '.' ||
      name.find("..") != std::string::npos)
    return "must look like section.field";
  const std::string section = name.substr(0, dot);
  if (!contains(overrideSections(), section))
    return "addresses an unknown config section '" + abbreviated(section) +
           "' (allowed: " + joined(overrideSections(), ", ") + ")";
  return "";
}

}  // namespace data_io

const std::vector<std::string>& overrideSections() {
  static const std::vector<std::string> sections = {"robot", "medium",     "effects",
                                                    "motor", "simulation", "solver"};
  return sections;
}

}  // namespace identify
}  // namespace flagella
