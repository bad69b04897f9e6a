#include "flagella_identify/report.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "flagella_sim/core/units.h"
#include "report_json.h"
#include "text_format.h"

namespace flagella {
namespace identify {

using nlohmann::json;

json finiteOrNull(double v) { return std::isfinite(v) ? json(v) : json(nullptr); }

json parametersJson(const std::vector<FitParameter>& ps) {
  json a = json::array();
  for (const FitParameter& p : ps)
    a.push_back({{"name", p.name},
                 {"value", p.value},
                 {"uncertainty", finiteOrNull(p.uncertainty)},
                 {"unit", p.unit},
                 {"range", {p.lower, p.upper}},
                 {"log_scale", p.log_scale}});
  return a;
}

json diagnosisJson(const Diagnosis& d) {
  json outputs = json::array(), where = json::array(), signatures = json::array();
  for (const OutputStats& o : d.outputs)
    outputs.push_back({{"output", o.output},
                       {"unit", o.unit},
                       {"count", o.count},
                       {"rms_z", o.rms_z},
                       {"mean_z", o.mean_z},
                       {"rms_error", o.rms_error},
                       {"mean_error", o.mean_error},
                       {"noise_z", o.noise_z}});
  for (const GroupStats& g : d.where)
    where.push_back(
        {{"group", g.group}, {"count", g.count}, {"rms_z", g.rms_z}, {"mean_z", g.mean_z}});
  for (const Signature& s : d.signatures)
    signatures.push_back(
        {{"kind", s.kind}, {"output", s.output}, {"statistic", s.statistic}, {"text", s.text}});
  return {{"count", d.count},     {"chi_square", d.chi_square},   {"rms_z", d.rms_z},
          {"noise_z", d.noise_z}, {"significant", d.significant}, {"outputs", outputs},
          {"where", where},       {"signatures", signatures}};
}

namespace {

std::string num(double v, int digits = 4) {
  if (!std::isfinite(v)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*g", digits, v);
  return buf;
}

json outcomeJson(const ModelOutcome& m) {
  return {{"label", m.label},
          {"effects", m.effects},
          {"fitted", m.fitted},
          {"note", m.note},
          {"off_the_map", m.warnings},
          {"continuation", m.continuation},
          {"parameters", parametersJson(m.parameters)},
          {"train_chi_square", m.train_chi_square},
          {"train_count", m.train_count},
          {"held_out_chi_square", m.held_out_chi_square},
          {"held_out_count", m.held_out_count},
          {"held_out_rms_z", m.held_out_rms_z},
          {"noise_z", m.noise_z},
          {"explained_share", m.explained},
          {"improvement", m.improvement},
          {"penalty", m.penalty},
          {"critical", m.critical},
          {"significant", m.significant},
          {"evaluations", m.evaluations},
          {"fit_iterations", m.iterations},
          {"fit_converged", m.converged},
          {"fit_gradient_max_norm",
           std::isfinite(m.gradient_max_norm) ? json(m.gradient_max_norm) : json(nullptr)},
          {"fit_starts", m.starts}};
}

/// How a fit ended, for the Markdown tables: iterations, convergence, largest gradient.
std::string fitEnding(const ModelOutcome& m) {
  return std::to_string(m.iterations) + " it., " + (m.converged ? "converged" : "not converged") +
         (std::isfinite(m.gradient_max_norm) ? ", max gradient " + num(m.gradient_max_norm, 3)
                                             : std::string());
}

std::string parameterTable(const std::vector<FitParameter>& ps) {
  std::ostringstream md;
  md << "| parameter | value | 1 sigma | unit |\n|---|---|---|---|\n";
  for (const FitParameter& p : ps)
    md << "| `" << p.name << "` | " << num(p.value) << " | "
       << (std::isfinite(p.uncertainty) ? num(p.uncertainty, 2) : "not identifiable") << " | "
       << p.unit << " |\n";
  return md.str();
}

std::string diagnosisTables(const Diagnosis& d) {
  std::ostringstream md;
  md << "| output | residuals | RMS error | mean error | RMS z | noise test z |\n"
     << "|---|---|---|---|---|---|\n";
  for (const OutputStats& o : d.outputs)
    md << "| " << o.output << " | " << o.count << " | " << num(o.rms_error, 3) << " " << o.unit
       << " | " << num(o.mean_error, 3) << " " << o.unit << " | " << num(o.rms_z, 3) << " | "
       << num(o.noise_z, 3) << " |\n";
  md << "\nWhere (held-out residuals grouped):\n\n| group | residuals | RMS z | mean z |\n"
     << "|---|---|---|---|\n";
  for (const GroupStats& g : d.where)
    md << "| " << g.group << " | " << g.count << " | " << num(g.rms_z, 3) << " | "
       << num(g.mean_z, 3) << " |\n";
  md << "\nSignatures:\n\n";
  if (d.signatures.empty()) md << "- none above " << kSignificanceZ << " standard deviations\n";
  for (const Signature& s : d.signatures)
    md << "- **" << s.kind << "** (" << s.output << ", " << num(s.statistic, 3)
       << " sigma): " << s.text << "\n";
  return md.str();
}

/// extended_config.yaml: the named effects on the baseline (or the calibrated baseline alone).
void writeExtendedConfig(const std::string& yaml_path, const IdentifyResult& r,
                         const ReportInputs& inputs, const Model& config_model, bool named) {
  std::ofstream out(yaml_path);
  out << "# " << (named ? "Extended" : "Calibrated baseline") << " robot config from "
      << inputs.baseline_config << "\n# identification verdict: " << verdictText(r.verdict);
  if (named) out << " (" << joined(r.named, " + ") << ")";
  out << "\n# run it: flagella_run run " << yaml_path << "\n";
  YAML::Emitter e;
  e << config_model.extendedConfig();
  out << e.c_str() << "\n";
}

/// plot_data.csv: every residual of the whole data set, with both models.
void writePlotData(const std::string& csv_path, const Split& split, const Evaluation& base_all,
                   const Evaluation& ext_all) {
  std::ofstream out(csv_path);
  out << "kind,source,row,output,omega_T_rpm,session_time_s,run_time_s,held_out,data,sigma,"
         "baseline,extended\n";
  for (size_t i = 0; i < base_all.points.size() && i < ext_all.points.size(); ++i) {
    const ResidualPoint& p = base_all.points[i];
    const bool held = p.from_series ? p.run_time >= split.series_split_time[p.source]
                                    : static_cast<bool>(split.table_row_held_out[p.source][p.row]);
    char line[512];
    std::snprintf(line, sizeof line, "%s,%d,%d,%s,%.6g,%.6g,%.6g,%d,%.10g,%.6g,%.10g,%.10g\n",
                  p.from_series ? "series" : "table", p.source, p.row, p.output.c_str(),
                  p.omega_T * 60.0 / (2.0 * M_PI),
                  std::isfinite(p.session_time) ? p.session_time : -1.0, p.run_time, held ? 1 : 0,
                  p.data, p.sigma, p.model, ext_all.points[i].model);
    out << line;
  }
}

/// report.json: everything, machine-readable.
json reportJson(const IdentifyResult& r, const ReportInputs& inputs, const std::string& yaml_path,
                bool named) {
  json j;
  j["verdict"] = verdictText(r.verdict);
  j["named_causes"] = r.named;
  j["summary"] = r.summary;
  j["pair_check"] = r.pair_check;  // docs/model.md 7.6: a pair against its effects refit alone
  j["pair_refits"] = json::array();
  for (const ModelOutcome& m : r.pair_refits) j["pair_refits"].push_back(outcomeJson(m));
  j["inputs"] = {{"data", inputs.data_files},
                 {"baseline_config", inputs.baseline_config},
                 {"command", inputs.command_line}};
  j["baseline"] = outcomeJson(r.baseline);
  j["baseline_diagnosis"] = diagnosisJson(r.baseline_diagnosis);
  j["candidates"] = json::array();
  for (const ModelOutcome& m : r.candidates) j["candidates"].push_back(outcomeJson(m));
  j["combinations"] = json::array();
  for (const ModelOutcome& m : r.combinations) j["combinations"].push_back(outcomeJson(m));
  j["chosen"] = r.chosen ? outcomeJson(*r.chosen) : json(nullptr);
  j["chosen_diagnosis"] = r.chosen ? diagnosisJson(r.chosen_diagnosis) : json(nullptr);
  j["gain"] = {
      {"held_out_rms_z_before", r.baseline_diagnosis.rms_z},
      {"held_out_rms_z_after", r.chosen ? r.chosen->held_out_rms_z : r.baseline_diagnosis.rms_z},
      {"gain", named ? r.gain : 0.0},
      {"definition",
       "1 - (held-out RMS of (model-data)/sigma with the effect) / (same "
       "for the calibrated baseline)"}};
  j["validation"] = {{"method", r.validation}, {"notes", r.validation_notes}};
  j["power"] = json::array();
  for (const PowerCheck& p : r.power)
    j["power"].push_back({{"candidate", p.candidate},
                          {"strength", p.strength},
                          {"checked", p.checked},
                          {"note", p.note},
                          {"chi_square_increase", p.chi_square_increase},
                          {"threshold", p.threshold},
                          {"excluded", p.excluded}});
  j["suggested_measurements"] = json::array();
  for (const SuggestedMeasurement& s : r.suggestions) {
    json overrides = json::object();
    for (const ConfigOverride& o : s.overrides) overrides[o.first] = o.second;
    j["suggested_measurements"].push_back({{"candidate", s.candidate},
                                           {"reference", s.reference},
                                           {"omega_T_rpm", s.omega_T * units::kRpmPerRadPerSec},
                                           {"output", s.output},
                                           {"overrides", overrides},
                                           {"reference_si", s.reference_value},
                                           {"candidate_si", s.candidate_value},
                                           {"sigma_si", s.sigma},
                                           {"separation_sigma", s.separation}});
  }
  j["extended_config"] = yaml_path;
  j["model_evaluations"] = r.total_evaluations;
  j["fits_at_once"] = r.fits_at_once;
  return j;
}

/// The Markdown report up to its gain table: verdict, summary, inputs, held-out gain.
void markdownHead(std::ostringstream& md, const IdentifyResult& r, const ReportInputs& inputs,
                  bool named) {
  md << "# Model discovery report\n\n";
  md << "**Verdict: " << verdictText(r.verdict);
  if (named) {
    md << " — ";
    for (size_t i = 0; i < r.named.size(); ++i)
      md << (i ? " + " : "") << candidateByName(r.named[i]).title << " (`" << r.named[i] << "`)";
  }
  md << "**\n\n" << r.summary << "\n\n";
  md << "- Data: ";
  for (size_t i = 0; i < inputs.data_files.size(); ++i)
    md << (i ? ", " : "") << "`" << inputs.data_files[i] << "`";
  md << "\n- Baseline config: `" << inputs.baseline_config << "`\n";
  md << "- Validation: " << r.validation << "\n";
  for (const std::string& note : r.validation_notes) md << "  - " << note << "\n";
  md << "- Model evaluations (each simulates the training experiments): " << r.total_evaluations
     << (r.fits_at_once > 1 ? " (candidate fits two at a time)" : "")
     << "\n- Plots: `report.png` (data, calibrated baseline, extended model)\n\n";
  md << "## Gain on held-out data\n\n| model | held-out RMS z | noise test z |\n|---|---|---|\n";
  md << "| calibrated baseline | " << num(r.baseline_diagnosis.rms_z, 3) << " | "
     << num(r.baseline_diagnosis.noise_z, 3) << " |\n";
  if (r.chosen)
    md << "| " << r.chosen->label << " | " << num(r.chosen->held_out_rms_z, 3) << " | "
       << num(r.chosen->noise_z, 3) << " |\n";
  md << "\nGain: " << (named ? num(100.0 * r.gain, 3) + " %" : std::string("none (no cause named)"))
     << " (1 - RMS z after / before; RMS z = 1 is the measurement noise).\n\n";
}

/// One row of section 3: a candidate, a pair, or a refit of the pair rule.
void candidateRow(std::ostringstream& md, const ModelOutcome& m, const std::string& label) {
  if (!m.fitted) {
    md << "| " << label << " | no: " << m.note << " | | | | | | | | |\n";
    return;
  }
  md << "| " << label << " | yes | " << num(m.held_out_rms_z, 3) << " | " << num(m.improvement, 4)
     << " | " << num(m.penalty + m.critical, 3) << " | " << (m.significant ? "yes" : "no") << " | "
     << num(100.0 * m.explained, 3) << " % | " << num(m.noise_z, 3) << " | " << fitEnding(m)
     << " | " << joined(m.starts, "; ") << " |\n";
}

/// Section 3 of the Markdown report: one line per candidate and pair, and the pair rule's
/// refits (docs/model.md 7.6).
void candidateSection(std::ostringstream& md, const IdentifyResult& r) {
  md << "## 3. Candidate effects\n\n| candidate | fitted | held-out RMS z | chi^2 drop | penalty + "
        "critical | significant | share of excess explained | remaining noise z | fit | starts "
        "|\n|---|---|---|---|---|---|---|---|---|---|\n";
  for (const auto* list : {&r.candidates, &r.combinations})
    for (const ModelOutcome& m : *list) candidateRow(md, m, m.label);
  for (const ModelOutcome& m : r.pair_refits)
    candidateRow(md, m, m.label + " (refit alone, pair rule)");
  if (!r.pair_check.empty()) md << "\nPair check (docs/model.md 7.6): " << r.pair_check << ".\n";
}

/// Section 3b of the Markdown report: the power of the data and the measurements that decide.
void powerSection(std::ostringstream& md, const IdentifyResult& r) {
  if (r.power.empty() && r.suggestions.empty()) return;
  md << "\n## 3b. Could these data have decided?\n";
  if (!r.power.empty()) {
    md << "\nEach steady-state candidate at its weakest realistic strength, baseline parameters "
          "refitted on every row:\n\n| candidate | chi^2 increase | rules it out above | excluded "
          "|\n|---|---|---|---|\n";
    for (const PowerCheck& p : r.power) {
      if (!p.checked) {
        md << "| " << p.candidate << " | not checked: " << p.note << " | | |\n";
        continue;
      }
      md << "| " << p.candidate << " | " << num(p.chi_square_increase, 3) << " | "
         << num(p.threshold, 3) << " | " << (p.excluded ? "yes" : "no") << " |\n";
    }
  }
  if (r.suggestions.empty()) return;
  md << "\nMeasurements that would decide (model predictions, SI units):\n\n| reference | "
        "candidate | omega_T [rpm] | config | output | reference predicts | candidate predicts | "
        "noise | sigmas apart |\n|---|---|---|---|---|---|---|---|---|\n";
  for (const SuggestedMeasurement& s : r.suggestions) {
    md << "| " << s.reference << " | " << s.candidate << " | "
       << num(s.omega_T * units::kRpmPerRadPerSec, 4) << " | " << configurationText(s) << " | "
       << s.output << " | " << num(s.reference_value, 4) << " | " << num(s.candidate_value, 4)
       << " | " << num(s.sigma, 3) << " | " << num(s.separation, 3) << " |\n";
  }
}

/// report.md: for a reader.
std::string reportMarkdown(const IdentifyResult& r, const ReportInputs& inputs,
                           const std::string& yaml_path, bool named) {
  std::ostringstream md;
  markdownHead(md, r, inputs, named);
  md << "## 1. Calibrated baseline\n\n"
     << parameterTable(r.baseline.parameters) << "\nTraining chi^2 "
     << num(r.baseline.train_chi_square) << " over " << r.baseline.train_count << " residuals"
     << (r.baseline.continuation ? " (fitted through the series' summary features first)" : "")
     << "; fit: " << fitEnding(r.baseline) << ", " << joined(r.baseline.starts, "; ") << ".\n\n";
  for (const std::string& w : r.baseline.warnings) md << "- **Off its map:** " << w << "\n";
  if (!r.baseline.warnings.empty()) md << "\n";
  md << "## 2. Diagnosis of the calibrated baseline (held-out data)\n\nHeld-out RMS z "
     << num(r.baseline_diagnosis.rms_z, 3) << " over " << r.baseline_diagnosis.count
     << " residuals; noise test z = " << num(r.baseline_diagnosis.noise_z, 3)
     << " (significant above " << kSignificanceZ << ").\n\n"
     << diagnosisTables(r.baseline_diagnosis) << "\n";
  candidateSection(md, r);
  powerSection(md, r);
  if (r.chosen) {
    md << "\n## 4. "
       << (named ? "Named cause and fitted parameters" : "Best partial model (no cause named)")
       << "\n\n"
       << parameterTable(r.chosen->parameters) << "\nHeld-out diagnosis with the effect:\n\n"
       << diagnosisTables(r.chosen_diagnosis) << "\n";
  }
  md << "\n## 5. Extended config\n\n`" << yaml_path << "` (runnable: `flagella_run run "
     << yaml_path << "`).\n";
  return md.str();
}

}  // namespace

std::vector<std::string> writeReport(const Identification& identification, const IdentifyResult& r,
                                     const ReportInputs& inputs, const std::string& directory) {
  namespace fs = std::filesystem;
  fs::create_directories(directory);
  const std::string json_path = (fs::path(directory) / "report.json").string();
  const std::string md_path = (fs::path(directory) / "report.md").string();
  const std::string yaml_path = (fs::path(directory) / "extended_config.yaml").string();
  const std::string csv_path = (fs::path(directory) / "plot_data.csv").string();

  const Model baseline = identification.modelOf(r.baseline);
  const Model extended = r.chosen ? identification.modelOf(*r.chosen) : baseline;
  const bool named = r.verdict == Verdict::kNamedCause;

  // ---- extended config (only the named effects; the baseline calibrated otherwise) ----
  writeExtendedConfig(yaml_path, r, inputs, named ? extended : baseline, named);

  // ---- plot data: every residual of the whole data set, both models ----
  const Evaluation base_all =
      identification.evaluator().evaluate(baseline, baseline.values(), Part::kAll);
  const Evaluation ext_all =
      identification.evaluator().evaluate(extended, extended.values(), Part::kAll);
  writePlotData(csv_path, identification.heldOutRows(), base_all, ext_all);

  std::ofstream(json_path) << reportJson(r, inputs, yaml_path, named).dump(2) << "\n";
  std::ofstream(md_path) << reportMarkdown(r, inputs, yaml_path, named);
  return {md_path, json_path, yaml_path, csv_path};
}

}  // namespace identify
}  // namespace flagella
