// The calibration report: calibration.json (machine-readable), calibration.md (for a reader) and
// calibrated_config.yaml (runnable with flagella_run).
#include <filesystem>
#include <fstream>
#include <sstream>

#include "flagella_identify/calibration.h"
#include "report_json.h"
#include "text_format.h"

namespace flagella {
namespace identify {

namespace {

using nlohmann::json;

/// The experiment a residual belongs to: "table row id (line L)" or "series S sample K".
std::string experimentLabel(const ResidualPoint& p, const MeasuredData& data) {
  if (p.from_series) return data.series[p.source].source + " sample " + std::to_string(p.row);
  const SteadyStateRow& row = data.tables[p.source].rows[p.row];
  return (row.id.empty() ? "" : row.id + " ") + data.tables[p.source].source + ":" +
         std::to_string(row.line);
}

json pointsJson(const Evaluation& e, const MeasuredData& data) {
  json a = json::array();
  for (const ResidualPoint& p : e.points) {
    const auto [unit, factor] = displayUnit(p.output);
    a.push_back({{"experiment", experimentLabel(p, data)},
                 {"output", p.output},
                 {"unit", unit},
                 {"data", p.data * factor},
                 {"model", p.model * factor},
                 {"sigma", p.sigma * factor},
                 {"z", p.z()}});
  }
  return a;
}

std::string markdown(const CalibrationResult& r, const MeasuredData& data,
                     const std::vector<std::string>& data_files, const std::string& config) {
  std::ostringstream md;
  md << "# Calibration report\n\n- Data: " << joined(data_files, ", ") << "\n- Baseline config: `"
     << config << "`\n- Model evaluations: " << r.fit.evaluations << " (" << r.fit.method << ", "
     << r.fit.iterations << " iterations; " << r.fit.message << ")\n\n";
  md << "| parameter | start | fitted | one sigma | unit |\n|---|---|---|---|---|\n";
  for (size_t i = 0; i < r.parameters.size(); ++i)
    md << "| `" << r.parameters[i].name << "` | " << formatted("%.4g", r.start[i].value) << " | "
       << formatted("%.4g", r.parameters[i].value) << " | "
       << formatted("%.2g", r.parameters[i].uncertainty) << " | " << r.parameters[i].unit << " |\n";
  for (const std::string& w : offTheMap(r.parameters)) md << "\n- **Off its map:** " << w;
  md << formatted("\nFit quality: chi^2 %.4g over %.0f residuals, RMS z %.3g", r.quality.chi_square,
                  r.quality.count, r.quality.rms_z)
     << formatted(" (1 = the stated noise; noise test z = %.2f).\n\n", r.quality.noise_z);
  md << "| experiment | output | data | model | z |\n|---|---|---|---|---|\n";
  for (const ResidualPoint& p : r.evaluation.points) {
    const auto [unit, factor] = displayUnit(p.output);
    md << "| " << experimentLabel(p, data) << " | " << p.output << " [" << unit << "] | "
       << formatted("%.4g | %.4g | %.2f", p.data * factor, p.model * factor, p.z()) << " |\n";
  }
  return md.str();
}

}  // namespace

std::vector<std::string> writeCalibrationReport(const CalibrationResult& r,
                                                const MeasuredData& data,
                                                const std::vector<std::string>& data_files,
                                                const std::string& baseline_config,
                                                const std::string& directory) {
  namespace fs = std::filesystem;
  fs::create_directories(directory);
  const std::string yaml_path = (fs::path(directory) / "calibrated_config.yaml").string();
  const std::string json_path = (fs::path(directory) / "calibration.json").string();
  const std::string md_path = (fs::path(directory) / "calibration.md").string();
  {
    std::ofstream out(yaml_path);
    out << "# Calibrated robot config from " << baseline_config << " on " << joined(data_files)
        << "\n# run it: flagella_run run " << yaml_path << "\n";
    YAML::Emitter e;
    e << r.calibrated_config;
    out << e.c_str() << "\n";
  }
  json j;
  j["inputs"] = {{"data", data_files}, {"baseline_config", baseline_config}};
  j["start"] = parametersJson(r.start);
  j["parameters"] = parametersJson(r.parameters);
  j["off_the_map"] = offTheMap(r.parameters);
  j["fit"] = {{"method", r.fit.method},
              {"evaluations", r.fit.evaluations},
              {"iterations", r.fit.iterations},
              {"message", r.fit.message},
              {"chi_square", r.quality.chi_square},
              {"count", r.quality.count},
              {"rms_z", r.quality.rms_z},
              {"noise_z", r.quality.noise_z}};
  j["quality"] = diagnosisJson(r.quality);
  j["experiments"] = pointsJson(r.evaluation, data);
  j["calibrated_config"] = yaml_path;
  std::ofstream(json_path) << j.dump(2) << "\n";
  std::ofstream(md_path) << markdown(r, data, data_files, baseline_config);
  return {json_path, md_path, yaml_path};
}

}  // namespace identify
}  // namespace flagella
