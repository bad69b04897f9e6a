// Writing steady-state tables and time series as YAML metadata plus CSV, in the file units.
#include <yaml-cpp/yaml.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>

#include "data_io_internal.h"
#include "text_format.h"

namespace flagella {
namespace identify {

namespace {

namespace fs = std::filesystem;
using data_io::contains;
using data_io::kMinSamples;
using data_io::measuredByOutput;
using data_io::MeasuredColumn;
using data_io::measuredColumns;
using data_io::overrideNameProblem;

// ---------------------------------------------------------------- files and shared parts

std::ofstream openForWriting(const std::string& path) {
  std::ofstream out(path);
  if (!out) {
    const fs::path directory = fs::path(path).parent_path();
    std::error_code ignored;
    if (!directory.empty() && !fs::is_directory(directory, ignored))
      throw DataError(path, 0, 0,
                      "cannot open the file for writing: its directory '" + directory.string() +
                          "' does not exist");
    throw DataError(path, 0, 0, "cannot open the file for writing");
  }
  out.exceptions(std::ios::failbit | std::ios::badbit);
  return out;
}

void finish(std::ofstream& out, const std::string& path) {
  try {
    out.flush();
    out.close();
  } catch (const std::ios::failure&) {
    throw DataError(path, 0, 0, "error while writing the file");
  }
}

void emitOverrides(YAML::Emitter& y, const std::vector<ConfigOverride>& overrides) {
  if (overrides.empty()) return;
  y << YAML::Key << "overrides" << YAML::Value << YAML::BeginMap;
  for (const auto& [name, text] : overrides) {
    y << YAML::Key << name << YAML::Value;
    YAML::Node value;
    try {
      value = YAML::Load(text);
    } catch (const YAML::Exception&) {
      value = YAML::Node(text);
    }
    if (value.IsScalar() || !value.IsDefined() || value.IsNull()) {
      y << text;  // plain if it reads back as the same text, quoted otherwise
    } else {
      value.SetStyle(YAML::EmitterStyle::Flow);  // reads back as the same flow text
      y << value;
    }
  }
  y << YAML::EndMap;
}

void checkOverridesForWriting(const std::string& yaml_path,
                              const std::vector<ConfigOverride>& overrides) {
  for (const auto& [name, text] : overrides) {
    const std::string problem = overrideNameProblem(name);
    if (!problem.empty())
      throw DataError(yaml_path, 0, 0, "cannot write: override '" + name + "' " + problem);
    if (csv::trim(text).empty())
      throw DataError(yaml_path, 0, 0, "cannot write: override '" + name + "' has no value");
  }
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream out = openForWriting(path);
  try {
    out << text;
  } catch (const std::ios::failure&) {
    throw DataError(path, 0, 0, "error while writing the file");
  }
  finish(out, path);
}

std::string metadataText(YAML::Emitter& y) { return std::string(y.c_str()) + "\n"; }

// ---------------------------------------------------------------- steady-state tables

/// The columns a steady-state table is written with.
struct TableLayout {
  bool any_id = false;
  bool any_time = false;
  std::vector<const MeasuredColumn*> columns;        ///< measured outputs, in the documented order
  std::vector<const MeasuredColumn*> sigma_columns;  ///< outputs some row gives its own sigma of
  std::vector<std::string> override_names;  ///< union of the row overrides, first seen first
};

[[noreturn]] void failTable(const std::string& yaml_path, const std::string& message) {
  throw DataError(yaml_path, 0, 0, "cannot write the steady-state table: " + message);
}

/// The columns of `table`; throws DataError if the table could not be read back.
TableLayout tableLayout(const SteadyStateTable& table, const std::string& yaml_path) {
  const auto fail = [&](const std::string& message) { failTable(yaml_path, message); };
  if (table.rows.empty()) fail("it has no rows");
  if (!(table.settle_time > 0.0) || !std::isfinite(table.settle_time))
    fail("settle_time must be > 0, got " + csv::formatNumber(table.settle_time));
  if (!(table.window > 0.0) || !std::isfinite(table.window))
    fail("window must be > 0, got " + csv::formatNumber(table.window));
  checkOverridesForWriting(yaml_path, table.overrides);

  // Columns: the outputs any row measures (in the documented order), the union of row overrides.
  TableLayout layout;
  std::set<std::string> used;
  for (const SteadyStateRow& row : table.rows) {
    if (!std::isfinite(row.omega_T)) fail("a row has a non-finite omega_T");
    layout.any_id = layout.any_id || !row.id.empty();
    layout.any_time = layout.any_time || !std::isnan(row.time);
    if (std::isinf(row.time)) fail("a row has an infinite time");
    for (const auto& [name, value] : row.measured) {
      if (!measuredByOutput(name))
        fail("unknown output '" + name + "' (allowed: " + joined(steadyOutputNames(), ", ") + ")");
      if (std::isinf(value)) fail("output '" + name + "' has an infinite value");
      used.insert(name);
    }
    checkOverridesForWriting(yaml_path, row.overrides);
    for (const auto& [name, text] : row.overrides)
      if (!contains(layout.override_names, name)) layout.override_names.push_back(name);
  }
  for (const auto& [name, sigma] : table.noise)
    if (!measuredByOutput(name))
      fail("noise for unknown output '" + name +
           "' (allowed: " + joined(steadyOutputNames(), ", ") + ")");
  for (const MeasuredColumn& m : measuredColumns()) {
    if (!used.count(m.output)) continue;
    bool own = false;
    for (const SteadyStateRow& row : table.rows) {
      const auto value = row.measured.find(m.output);
      const double sigma = row.sigmaOf(m.output, table.noise);
      if (value != row.measured.end() && !std::isnan(value->second) && !std::isfinite(sigma))
        fail(std::string("no noise for measured output '") + m.output +
             "' (neither the table's nor the row's own)");
      if (row.sigma.count(m.output)) {
        own = true;
        if (!(sigma > 0.0) || !std::isfinite(sigma))
          fail("a row's own sigma of '" + std::string(m.output) + "' must be > 0, got " +
               csv::formatNumber(sigma));
      }
    }
    layout.columns.push_back(&m);
    if (own) layout.sigma_columns.push_back(&m);
  }
  for (const SteadyStateRow& row : table.rows)
    for (const auto& [name, sigma] : row.sigma)
      if (!used.count(name)) fail("a row gives a sigma of '" + name + "', which no row measures");
  if (layout.columns.empty()) fail("no row measures any output");
  for (const auto& [name, sigma] : table.noise)
    if (!(sigma > 0.0) || !std::isfinite(sigma))
      fail("noise for '" + name + "' must be > 0, got " + csv::formatNumber(sigma));
  return layout;
}

/// The CSV text of a table: header, then one line per row in the file units.
std::string tableCsvText(const SteadyStateTable& table, const TableLayout& layout) {
  std::string text;
  std::vector<std::string> header;
  if (layout.any_id) header.push_back("id");
  if (layout.any_time) header.push_back("time_s");
  header.push_back("omega_T_rpm");
  for (const MeasuredColumn* m : layout.columns) header.push_back(m->column);
  for (const MeasuredColumn* m : layout.sigma_columns)
    header.push_back(std::string("sigma_") + m->column);
  for (const std::string& name : layout.override_names) header.push_back(name);
  text += csv::joinLine(header) + "\n";
  for (const SteadyStateRow& row : table.rows) {
    std::vector<std::string> fields;
    if (layout.any_id) fields.push_back(row.id);
    if (layout.any_time) fields.push_back(csv::formatNumber(row.time));
    fields.push_back(csv::formatNumber(row.omega_T / kRadPerSecPerRpm));
    for (const MeasuredColumn* m : layout.columns) {
      const auto it = row.measured.find(m->output);
      fields.push_back(it == row.measured.end() ? "" : csv::formatNumber(it->second / m->to_si));
    }
    for (const MeasuredColumn* m : layout.sigma_columns) {
      const auto it = row.sigma.find(m->output);
      fields.push_back(it == row.sigma.end() ? "" : csv::formatNumber(it->second / m->to_si));
    }
    for (const std::string& name : layout.override_names) {
      std::string value;
      for (const auto& [n, v] : row.overrides)
        if (n == name) value = v;
      fields.push_back(csv::trim(value));
    }
    text += csv::joinLine(fields) + "\n";
  }
  return text;
}

/// The metadata YAML text of a table whose CSV is `csv_path`.
std::string tableMetadataText(const SteadyStateTable& table, const std::string& csv_path) {
  YAML::Emitter y;
  y << YAML::BeginMap;
  y << YAML::Key << "kind" << YAML::Value << "steady_state";
  y << YAML::Key << "csv" << YAML::Value << fs::path(csv_path).filename().string();
  y << YAML::Key << "description" << YAML::Value << table.description;
  y << YAML::Key << "settle_time_s" << YAML::Value << csv::formatNumber(table.settle_time);
  y << YAML::Key << "window_s" << YAML::Value << csv::formatNumber(table.window);
  emitOverrides(y, table.overrides);
  y << YAML::Key << "noise" << YAML::Value << YAML::BeginMap;
  for (const MeasuredColumn& m : measuredColumns()) {
    const auto it = table.noise.find(m.output);
    if (it == table.noise.end()) continue;
    y << YAML::Key << m.column << YAML::Value << csv::formatNumber(it->second / m.to_si);
  }
  y << YAML::EndMap << YAML::EndMap;
  return metadataText(y);
}

// ---------------------------------------------------------------- time series

[[noreturn]] void failSeries(const std::string& yaml_path, const std::string& message) {
  throw DataError(yaml_path, 0, 0, "cannot write the time series: " + message);
}

/// Throws DataError if `s` could not be read back (lengths, values, noise, overrides).
void checkSeriesForWriting(const TimeSeries& s, const std::string& yaml_path) {
  const auto fail = [&](const std::string& message) { failSeries(yaml_path, message); };
  const size_t n = s.t.size();
  if (n < static_cast<size_t>(kMinSamples))
    fail("it needs at least " + std::to_string(kMinSamples) + " samples, got " + std::to_string(n));
  const auto checkSize = [&](size_t size, const std::string& name, bool optional) {
    if (size != n && !(optional && size == 0))
      fail(name + " has " + std::to_string(size) + " samples, t has " + std::to_string(n));
  };
  checkSize(s.position.size(), "position", false);
  checkSize(s.omega_cmd.size(), "omega_cmd", false);
  checkSize(s.orientation.size(), "orientation", true);
  checkSize(s.head_turns.size(), "head_turns", true);
  checkSize(s.tail_turns.size(), "tail_turns", true);
  for (size_t i = 0; i < n; ++i) {
    const std::string at = " at sample " + std::to_string(i);
    if (!std::isfinite(s.t[i])) fail("t is not finite" + at);
    if (i > 0 && !(s.t[i] > s.t[i - 1])) fail("t must be strictly increasing" + at);
    const Vec3& p = s.position[i];
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()) || (s.has_z && !std::isfinite(p.z())))
      fail("position is not finite" + at);
    if (!s.orientation.empty()) {
      if (!s.orientation[i].coeffs().allFinite() || !(s.orientation[i].norm() > 1e-12))
        fail("orientation is not a finite non-zero quaternion" + at);
    }
    if (!s.head_turns.empty() && !std::isfinite(s.head_turns[i]))
      fail("head_turns is not finite" + at);
    if (!s.tail_turns.empty() && !std::isfinite(s.tail_turns[i]))
      fail("tail_turns is not finite" + at);
    if (!std::isfinite(s.omega_cmd[i])) fail("omega_cmd is not finite" + at);
  }
  if (!(s.session_time >= 0.0) || !std::isfinite(s.session_time))
    fail("session_time must be >= 0, got " + csv::formatNumber(s.session_time));
  if (!(s.position_noise > 0.0) || !std::isfinite(s.position_noise))
    fail("position_noise must be > 0, got " + csv::formatNumber(s.position_noise));
  if (!s.orientation.empty() &&
      (!(s.orientation_noise > 0.0) || !std::isfinite(s.orientation_noise)))
    fail("orientation_noise must be > 0, got " + csv::formatNumber(s.orientation_noise));
  const bool has_turns = !s.head_turns.empty() || !s.tail_turns.empty();
  if (has_turns && (!(s.turns_noise > 0.0) || !std::isfinite(s.turns_noise)))
    fail("turns_noise must be > 0, got " + csv::formatNumber(s.turns_noise));
  checkOverridesForWriting(yaml_path, s.overrides);
}

/// The CSV text of a series: header, then one line per sample in the file units.
std::string seriesCsvText(const TimeSeries& s) {
  std::vector<std::string> header = {"t_s", "x_mm", "y_mm"};
  if (s.has_z) header.push_back("z_mm");
  if (!s.orientation.empty()) header.insert(header.end(), {"qw", "qx", "qy", "qz"});
  if (!s.head_turns.empty()) header.push_back("head_turns");
  if (!s.tail_turns.empty()) header.push_back("tail_turns");
  header.push_back("omega_T_rpm");
  std::string text = csv::joinLine(header) + "\n";
  for (size_t i = 0; i < s.t.size(); ++i) {
    std::vector<std::string> fields = {csv::formatNumber(s.t[i]),
                                       csv::formatNumber(s.position[i].x() / kMetresPerMm),
                                       csv::formatNumber(s.position[i].y() / kMetresPerMm)};
    if (s.has_z) fields.push_back(csv::formatNumber(s.position[i].z() / kMetresPerMm));
    if (!s.orientation.empty()) {
      const Eigen::Quaterniond& q = s.orientation[i];
      for (double c : {q.w(), q.x(), q.y(), q.z()}) fields.push_back(csv::formatNumber(c));
    }
    if (!s.head_turns.empty()) fields.push_back(csv::formatNumber(s.head_turns[i]));
    if (!s.tail_turns.empty()) fields.push_back(csv::formatNumber(s.tail_turns[i]));
    fields.push_back(csv::formatNumber(s.omega_cmd[i] / kRadPerSecPerRpm));
    text += csv::joinLine(fields) + "\n";
  }
  return text;
}

/// The metadata YAML text of a series whose CSV is `csv_path`.
std::string seriesMetadataText(const TimeSeries& s, const std::string& csv_path) {
  const bool has_turns = !s.head_turns.empty() || !s.tail_turns.empty();
  YAML::Emitter y;
  y << YAML::BeginMap;
  y << YAML::Key << "kind" << YAML::Value << "time_series";
  y << YAML::Key << "csv" << YAML::Value << fs::path(csv_path).filename().string();
  y << YAML::Key << "description" << YAML::Value << s.description;
  y << YAML::Key << "session_time_s" << YAML::Value << csv::formatNumber(s.session_time);
  emitOverrides(y, s.overrides);
  y << YAML::Key << "noise" << YAML::Value << YAML::BeginMap;
  y << YAML::Key << "position_mm" << YAML::Value
    << csv::formatNumber(s.position_noise / kMetresPerMm);
  if (!s.orientation.empty())
    y << YAML::Key << "orientation_rad" << YAML::Value << csv::formatNumber(s.orientation_noise);
  if (has_turns) y << YAML::Key << "turns" << YAML::Value << csv::formatNumber(s.turns_noise);
  y << YAML::EndMap << YAML::EndMap;
  return metadataText(y);
}

}  // namespace

void writeSteadyStateTable(const SteadyStateTable& table, const std::string& yaml_path) {
  const TableLayout layout = tableLayout(table, yaml_path);
  const std::string csv_path = csvPathForMetadata(yaml_path);
  writeText(csv_path, tableCsvText(table, layout));
  writeText(yaml_path, tableMetadataText(table, csv_path));
}

void writeTimeSeries(const TimeSeries& s, const std::string& yaml_path) {
  checkSeriesForWriting(s, yaml_path);
  const std::string csv_path = csvPathForMetadata(yaml_path);
  writeText(csv_path, seriesCsvText(s));
  writeText(yaml_path, seriesMetadataText(s, csv_path));
}

}  // namespace identify
}  // namespace flagella
