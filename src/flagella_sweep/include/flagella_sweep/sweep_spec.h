// A sweep file (YAML) and the points it expands to. Format (README "Sweeps"):
//   sweep:
//     tool: run                # run | buckling | steer: the tool run once per point
//     config: ../config/helical_robot.yaml   # base config, relative to the sweep file
//     args: [--tolerance, "0.5"]             # optional extra arguments for the tool
//     grid:                    # every combination, the first key varying slowest ...
//       motor.omega_rpm: [5, 10, 15]
//     points:                  # ... or an explicit list of settings (exactly one of the two)
//       - {motor.omega_rpm: 5, robot.pitch_count: 2.5}
// Parameters are config fields (section.field), passed to the tool as --set overrides. Paths in
// `config` and `args` are relative to the sweep file's folder, where every point's tool runs.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace flagella::sweep {

enum class SweepTool { Run, Buckling, Steer };
const char* toolName(SweepTool tool);

/// One point: (field, value text) in the sweep file's key order.
using PointSettings = std::vector<std::pair<std::string, std::string>>;

struct SweepSpec {
  std::string file;       ///< the sweep file as given
  std::string directory;  ///< its folder (absolute): the tool's working directory
  SweepTool tool = SweepTool::Run;
  std::string config;  ///< base config as written (relative to directory)
  std::vector<std::string> args;
  std::vector<std::string> parameters;  ///< field names, in file order
  std::vector<PointSettings> points;
};

/// Largest number of points a sweep may have.
constexpr int kMaxPoints = 100000;

/// Reads and validates a sweep file: structure, tool, fields, values, point count; then loads
/// every point's config (base config + its settings) so a bad value fails before anything runs.
/// Throws flagella::ConfigError naming the file, the field and the allowed values.
SweepSpec loadSweepSpec(const std::string& path);

/// The `--set` overrides of one point ("field=value").
std::vector<std::string> pointOverrides(const SweepSpec& spec, int index);

}  // namespace flagella::sweep
