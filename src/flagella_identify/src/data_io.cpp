#include "flagella_identify/data_io.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <utility>

#include "csv.h"
#include "text_format.h"

namespace flagella {
namespace identify {

namespace {

namespace fs = std::filesystem;

bool contains(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

/// A measured column of a steady-state table: file name, output name, factor to SI.
struct MeasuredColumn {
  const char* column;
  const char* output;
  double to_si;
};

const std::vector<MeasuredColumn>& measuredColumns() {
  static const std::vector<MeasuredColumn> columns = {{"v_mm_s", "v", kMetresPerMm},
                                                      {"omega_h_rpm", "omega_h", kRadPerSecPerRpm},
                                                      {"omega_t_rpm", "omega_t", kRadPerSecPerRpm},
                                                      {"omega_yr_rad_s", "omega_yr", 1.0},
                                                      {"R_yr_mm", "R_yr", kMetresPerMm}};
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

std::vector<std::string> measuredColumnNames() {
  std::vector<std::string> names;
  for (const MeasuredColumn& m : measuredColumns()) names.push_back(m.column);
  return names;
}

/// Empty if `name` is a valid override name "section.field[.more]", else what is wrong.
std::string overrideNameProblem(const std::string& name) {
  const size_t dot = name.find('.');
  if (dot == std::string::npos || dot == 0 || name.back() == '.' ||
      name.find("..") != std::string::npos)
    return "must look like section.field";
  const std::string section = name.substr(0, dot);
  if (!contains(overrideSections(), section))
    return "addresses an unknown config section '" + section +
           "' (allowed: " + joined(overrideSections(), ", ") + ")";
  return "";
}

// ---------------------------------------------------------------- YAML metadata helpers

/// Metadata of one file: the error positions come from the YAML marks.
class Metadata {
 public:
  Metadata(std::string file, YAML::Node root) : file_(std::move(file)), root_(std::move(root)) {}

  const std::string& file() const { return file_; }
  const YAML::Node& root() const { return root_; }

  [[noreturn]] void fail(const YAML::Node& at, const std::string& message) const {
    int line = 0;
    int column = 0;
    if (at.IsDefined()) {
      const YAML::Mark mark = at.Mark();
      if (mark.line >= 0) {
        line = mark.line + 1;
        column = mark.column + 1;
      }
    }
    throw DataError(file_, line, column, message);
  }

  /// Throws for a key of `map` (field path `prefix`) that is not in `allowed`.
  void rejectUnknownKeys(const YAML::Node& map, const std::string& prefix,
                         const std::vector<std::string>& allowed) const {
    for (const auto& kv : map) {
      const std::string key = keyText(kv.first, prefix);
      if (!contains(allowed, key))
        fail(kv.first,
             "unknown key '" + prefix + key + "' (allowed: " + joined(allowed, ", ") + ")");
    }
  }

  std::string keyText(const YAML::Node& key, const std::string& prefix) const {
    if (!key.IsScalar())
      fail(key, "keys of " + (prefix.empty() ? "the metadata" : prefix) + " must be plain names");
    return key.Scalar();
  }

  /// The node of a key of the root map (invalid/undefined if absent or null).
  YAML::Node get(const std::string& key) const {
    YAML::Node node = root_[key];
    if (!node.IsDefined() || node.IsNull()) return YAML::Node(YAML::NodeType::Undefined);
    return node;
  }

  bool has(const std::string& key) const { return get(key).IsDefined(); }

  /// The key node of a root key (for messages about the key as a whole); the root if absent.
  YAML::Node keyNode(const std::string& key) const {
    for (const auto& kv : root_)
      if (kv.first.IsScalar() && kv.first.Scalar() == key) return kv.first;
    return root_;
  }

  std::string text(const YAML::Node& node, const std::string& field) const {
    if (!node.IsScalar()) fail(node, field + ": expected a text value");
    return node.Scalar();
  }

  double number(const YAML::Node& node, const std::string& field) const {
    if (!node.IsScalar()) fail(node, field + ": expected a number");
    const std::optional<double> value = csv::parseNumber(node.Scalar());
    if (!value) fail(node, field + ": expected a number, got '" + node.Scalar() + "'");
    if (!std::isfinite(*value))
      fail(node, field + ": expected a finite number, got '" + node.Scalar() + "'");
    return *value;
  }

  double positive(const YAML::Node& node, const std::string& field) const {
    const double value = number(node, field);
    if (!(value > 0.0)) fail(node, field + " must be > 0, got " + csv::formatNumber(value));
    return value;
  }

  double nonNegative(const YAML::Node& node, const std::string& field) const {
    const double value = number(node, field);
    if (!(value >= 0.0)) fail(node, field + " must be >= 0, got " + csv::formatNumber(value));
    return value;
  }

  std::string requiredText(const std::string& key) const {
    const YAML::Node node = get(key);
    if (!node.IsDefined()) fail(root_, "missing required key '" + key + "'");
    return text(node, key);
  }

  /// The path a file key names, relative to the metadata file's directory; it must exist.
  std::string filePath(const std::string& key) const {
    const std::string name = requiredText(key);
    if (name.empty()) fail(get(key), key + ": expected a file name");
    fs::path path(name);
    if (path.is_relative()) path = fs::path(file_).parent_path() / path;
    std::error_code ec;
    if (!fs::is_regular_file(path, ec))
      fail(get(key), key + ": cannot open '" + path.string() + "' (" +
                         (fs::exists(path, ec) ? "not a regular file" : "no such file") +
                         "; paths are relative to the metadata file's directory)");
    return path.string();
  }

  /// The "overrides" map: "section.field": value (scalar or flow text of a list/map).
  std::vector<ConfigOverride> overrides() const {
    std::vector<ConfigOverride> out;
    const YAML::Node node = get("overrides");
    if (!node.IsDefined()) return out;
    if (!node.IsMap()) fail(node, "overrides: expected a map of \"section.field\": value");
    for (const auto& kv : node) {
      const std::string name = keyText(kv.first, "overrides");
      const std::string problem = overrideNameProblem(name);
      if (!problem.empty()) fail(kv.first, "override '" + name + "' " + problem);
      const YAML::Node& value = kv.second;
      if (!value.IsDefined() || value.IsNull())
        fail(kv.first, "override '" + name + "' has no value");
      if (value.IsScalar()) {
        out.emplace_back(name, value.Scalar());
      } else {
        YAML::Emitter emitter;
        emitter << YAML::Flow << value;
        out.emplace_back(name, emitter.c_str());
      }
    }
    return out;
  }

  /// The "noise" map with its keys checked against `allowed`, values > 0 (in file units).
  std::map<std::string, double> noise(const std::vector<std::string>& allowed) const {
    std::map<std::string, double> out;
    const YAML::Node node = get("noise");
    if (!node.IsDefined()) return out;
    if (!node.IsMap()) fail(node, "noise: expected a map of name: standard deviation");
    rejectUnknownKeys(node, "noise.", allowed);
    for (const auto& kv : node) {
      const std::string key = kv.first.Scalar();
      if (!kv.second.IsDefined() || kv.second.IsNull())
        fail(kv.first, "noise." + key + " has no value; expected a number > 0");
      out[key] = positive(kv.second, "noise." + key);
    }
    return out;
  }

  /// Throws unless noise `key` is given; `why` says which data needs it.
  void requireNoise(const std::map<std::string, double>& noise, const std::string& key,
                    const std::string& why) const {
    if (noise.count(key)) return;
    fail(keyNode("noise"), "noise." + key + " is required: " + why);
  }

 private:
  std::string file_;
  YAML::Node root_;
};

// ---------------------------------------------------------------- CSV helpers

/// Header columns by name, with the duplicate and empty-name checks.
std::map<std::string, int> indexHeader(const csv::Table& table) {
  std::map<std::string, int> index;
  for (size_t i = 0; i < table.header.size(); ++i) {
    const std::string& name = table.header[i];
    const int column = static_cast<int>(i) + 1;
    if (name.empty()) throw DataError(table.path, table.header_line, column, "empty column name");
    const auto [it, inserted] = index.emplace(name, column - 1);
    if (!inserted)
      throw DataError(
          table.path, table.header_line, column,
          "duplicate column '" + name + "' (also column " + std::to_string(it->second + 1) + ")");
  }
  return index;
}

void checkFieldCount(const csv::Table& table, const csv::Row& row) {
  const size_t expected = table.header.size();
  if (row.fields.size() == expected) return;
  const int column = static_cast<int>(std::min(row.fields.size(), expected)) + 1;
  throw DataError(table.path, row.line, column,
                  "expected " + std::to_string(expected) + " fields as in the header (line " +
                      std::to_string(table.header_line) + "), got " +
                      std::to_string(row.fields.size()));
}

/// The number in a cell; nullopt for an empty cell if `optional`, else an error.
std::optional<double> cellNumber(const csv::Table& table, const csv::Row& row, int index,
                                 bool optional) {
  const std::string& text = row.fields[index];
  const std::string& name = table.header[index];
  if (text.empty()) {
    if (optional) return std::nullopt;
    throw DataError(table.path, row.line, index + 1,
                    "column '" + name + "': expected a number, got an empty cell");
  }
  const std::optional<double> value = csv::parseNumber(text);
  if (!value)
    throw DataError(table.path, row.line, index + 1,
                    "column '" + name + "': expected a number, got '" + text + "'");
  if (!std::isfinite(*value))
    throw DataError(table.path, row.line, index + 1,
                    "column '" + name + "': expected a finite number, got '" + text + "'");
  return value;
}

double requiredNumber(const csv::Table& table, const csv::Row& row, int index) {
  return *cellNumber(table, row, index, false);
}

[[noreturn]] void missingColumn(const csv::Table& table, const std::string& name) {
  throw DataError(
      table.path, table.header_line, 1,
      "missing required column '" + name + "' (header has: " + joined(table.header, ", ") + ")");
}

// ---------------------------------------------------------------- steady-state tables

SteadyStateTable readSteadyState(const Metadata& meta) {
  meta.rejectUnknownKeys(
      meta.root(), "",
      {"kind", "csv", "description", "settle_time_s", "window_s", "overrides", "noise"});
  SteadyStateTable table;
  table.source = meta.file();
  if (meta.has("description"))
    table.description = meta.text(meta.get("description"), "description");
  table.settle_time =
      meta.has("settle_time_s") ? meta.positive(meta.get("settle_time_s"), "settle_time_s") : 10.0;
  table.window = meta.has("window_s") ? meta.positive(meta.get("window_s"), "window_s") : 20.0;
  table.overrides = meta.overrides();
  const std::map<std::string, double> noise = meta.noise(measuredColumnNames());
  const std::string csv_path = meta.filePath("csv");

  const csv::Table csv = csv::read(csv_path);
  indexHeader(csv);  // duplicate and empty names
  int id_col = -1;
  int time_col = -1;
  int omega_col = -1;
  std::vector<std::pair<int, const MeasuredColumn*>> measured;
  std::vector<int> override_cols;
  for (size_t i = 0; i < csv.header.size(); ++i) {
    const std::string& name = csv.header[i];
    const int col = static_cast<int>(i);
    if (name == "id") {
      id_col = col;
    } else if (name == "time_s") {
      time_col = col;
    } else if (name == "omega_T_rpm") {
      omega_col = col;
    } else if (const MeasuredColumn* m = measuredByColumn(name)) {
      measured.emplace_back(col, m);
    } else if (name.find('.') != std::string::npos) {
      const std::string problem = overrideNameProblem(name);
      if (!problem.empty())
        throw DataError(csv.path, csv.header_line, col + 1,
                        "override column '" + name + "' " + problem);
      override_cols.push_back(col);
    } else {
      throw DataError(csv.path, csv.header_line, col + 1,
                      "unknown column '" + name + "' (allowed: id, time_s, omega_T_rpm, " +
                          joined(measuredColumnNames(), ", ") +
                          ", or a config override 'section.field' with section one of " +
                          joined(overrideSections(), ", ") + ")");
    }
  }
  if (omega_col < 0) missingColumn(csv, "omega_T_rpm");
  if (measured.empty())
    throw DataError(
        csv.path, csv.header_line, 1,
        "no measured column; expected at least one of " + joined(measuredColumnNames(), ", "));
  for (const auto& [col, m] : measured)
    meta.requireNoise(noise, m->column,
                      "'" + csv.path + "' has the measured column '" + m->column + "'");
  for (const auto& [key, sigma] : noise) {
    const MeasuredColumn* m = measuredByColumn(key);
    table.noise[m->output] = sigma * m->to_si;
  }
  if (csv.rows.empty())
    throw DataError(csv.path, csv.header_line, 1, "no data rows after the header");

  for (const csv::Row& r : csv.rows) {
    checkFieldCount(csv, r);
    SteadyStateRow row;
    row.line = r.line;
    if (id_col >= 0) row.id = r.fields[id_col];
    if (time_col >= 0) {
      const std::optional<double> t = cellNumber(csv, r, time_col, true);
      row.time = t ? *t : kMissing;
    }
    row.omega_T = requiredNumber(csv, r, omega_col) * kRadPerSecPerRpm;
    for (int col : override_cols)
      if (!r.fields[col].empty()) row.overrides.emplace_back(csv.header[col], r.fields[col]);
    for (const auto& [col, m] : measured) {
      const std::optional<double> value = cellNumber(csv, r, col, true);
      row.measured[m->output] = value ? *value * m->to_si : kMissing;
    }
    table.rows.push_back(std::move(row));
  }
  return table;
}

// ---------------------------------------------------------------- time series

constexpr int kMinSamples = 3;

void checkSeriesNoise(const Metadata& meta, const std::map<std::string, double>& noise,
                      const TimeSeries& s, const std::string& data_name) {
  meta.requireNoise(noise, "position_mm", "every time series has positions");
  if (!s.orientation.empty())
    meta.requireNoise(noise, "orientation_rad", data_name + " has orientations");
  if (!s.head_turns.empty() || !s.tail_turns.empty())
    meta.requireNoise(noise, "turns", data_name + " has counted turns");
}

TimeSeries readSeriesCsv(const std::string& csv_path) {
  const csv::Table csv = csv::read(csv_path);
  const std::map<std::string, int> index = indexHeader(csv);
  static const std::vector<std::string> allowed = {"t_s",        "x_mm",       "y_mm",       "z_mm",
                                                   "qw",         "qx",         "qy",         "qz",
                                                   "head_turns", "tail_turns", "omega_T_rpm"};
  for (size_t i = 0; i < csv.header.size(); ++i)
    if (!contains(allowed, csv.header[i]))
      throw DataError(
          csv.path, csv.header_line, static_cast<int>(i) + 1,
          "unknown column '" + csv.header[i] + "' (allowed: " + joined(allowed, ", ") + ")");
  const auto col = [&](const std::string& name) {
    const auto it = index.find(name);
    return it == index.end() ? -1 : it->second;
  };
  for (const char* name : {"t_s", "x_mm", "y_mm", "omega_T_rpm"})
    if (col(name) < 0) missingColumn(csv, name);
  const std::vector<std::string> q_names = {"qw", "qx", "qy", "qz"};
  std::vector<std::string> q_missing;
  int q_first = -1;
  for (const std::string& q : q_names) {
    if (col(q) < 0)
      q_missing.push_back(q);
    else if (q_first < 0 || col(q) < q_first)
      q_first = col(q);
  }
  if (!q_missing.empty() && q_missing.size() < q_names.size())
    throw DataError(csv.path, csv.header_line, q_first + 1,
                    "the quaternion columns come as a group of four (qw, qx, qy, qz); missing " +
                        joined(q_missing, ", "));
  const bool has_q = q_missing.empty();
  const int t_col = col("t_s");
  const int z_col = col("z_mm");

  TimeSeries s;
  s.has_z = z_col >= 0;
  for (const csv::Row& r : csv.rows) {
    checkFieldCount(csv, r);
    const double t = requiredNumber(csv, r, t_col);
    if (!s.t.empty() && !(t > s.t.back()))
      throw DataError(csv.path, r.line, t_col + 1,
                      "column 't_s': time must be strictly increasing, got " +
                          csv::formatNumber(t) + " after " + csv::formatNumber(s.t.back()));
    s.t.push_back(t);
    const double z = s.has_z ? requiredNumber(csv, r, z_col) * kMetresPerMm : kMissing;
    s.position.emplace_back(requiredNumber(csv, r, col("x_mm")) * kMetresPerMm,
                            requiredNumber(csv, r, col("y_mm")) * kMetresPerMm, z);
    if (has_q) {
      Eigen::Quaterniond q(requiredNumber(csv, r, col("qw")), requiredNumber(csv, r, col("qx")),
                           requiredNumber(csv, r, col("qy")), requiredNumber(csv, r, col("qz")));
      const double norm = q.norm();
      if (!(norm > 1e-12))
        throw DataError(csv.path, r.line, col("qw") + 1,
                        "quaternion (qw, qx, qy, qz) has zero norm; expected a rotation");
      q.coeffs() /= norm;
      s.orientation.push_back(q);
    }
    if (col("head_turns") >= 0) s.head_turns.push_back(requiredNumber(csv, r, col("head_turns")));
    if (col("tail_turns") >= 0) s.tail_turns.push_back(requiredNumber(csv, r, col("tail_turns")));
    s.omega_cmd.push_back(requiredNumber(csv, r, col("omega_T_rpm")) * kRadPerSecPerRpm);
  }
  if (static_cast<int>(s.t.size()) < kMinSamples)
    throw DataError(csv.path, csv.rows.empty() ? csv.header_line : csv.rows.back().line, 1,
                    "a time series needs at least " + std::to_string(kMinSamples) +
                        " data rows, got " + std::to_string(s.t.size()));
  return s;
}

std::mutex& bagReaderMutex() {
  static std::mutex mutex;
  return mutex;
}

BagReaderFn& bagReaderSlot() {
  static BagReaderFn reader;
  return reader;
}

TimeSeries readSeries(const Metadata& meta) {
  meta.rejectUnknownKeys(meta.root(), "",
                         {"kind", "csv", "bag", "description", "session_time_s", "overrides",
                          "noise", "bag_namespace", "bag_position"});
  const bool has_csv = meta.has("csv");
  const bool has_bag = meta.has("bag");
  if (has_csv && has_bag) meta.fail(meta.keyNode("bag"), "give either csv or bag, not both");
  if (!has_csv && !has_bag)
    meta.fail(meta.root(), "missing required key 'csv' or 'bag' (exactly one of the two)");
  if (has_csv)
    for (const char* key : {"bag_namespace", "bag_position"})
      if (meta.has(key))
        meta.fail(meta.keyNode(key), std::string(key) + " applies only to bag input (bag:)");
  const std::string description =
      meta.has("description") ? meta.text(meta.get("description"), "description") : "";
  const double session_time = meta.has("session_time_s")
                                  ? meta.nonNegative(meta.get("session_time_s"), "session_time_s")
                                  : 0.0;
  std::vector<ConfigOverride> overrides = meta.overrides();
  const std::map<std::string, double> noise =
      meta.noise({"position_mm", "orientation_rad", "turns"});

  TimeSeries s;
  std::string data_name;
  if (has_csv) {
    const std::string csv_path = meta.filePath("csv");
    data_name = "'" + csv_path + "'";
    s = readSeriesCsv(csv_path);
  } else {
    BagOptions options;
    if (meta.has("bag_namespace"))
      options.topic_namespace = meta.text(meta.get("bag_namespace"), "bag_namespace");
    if (meta.has("bag_position")) {
      const YAML::Node node = meta.get("bag_position");
      const std::string value = meta.text(node, "bag_position");
      if (value == "rod_state")
        options.position = BagOptions::Position::kRodState;
      else if (value == "camera_fix")
        options.position = BagOptions::Position::kCameraFix;
      else
        meta.fail(node, "bag_position: expected rod_state or camera_fix, got '" + value + "'");
    }
    BagReaderFn reader;
    {
      std::lock_guard<std::mutex> lock(bagReaderMutex());
      reader = bagReaderSlot();
    }
    if (!reader)
      meta.fail(meta.get("bag"),
                "bag input needs the flagella_identify_bag library: link it and call "
                "flagella::identify::enableBagInput() before reading");
    const std::string bag_path = meta.filePath("bag");
    data_name = "'" + bag_path + "'";
    s = reader(bag_path, options);
  }
  checkSeriesNoise(meta, noise, s, data_name);
  s.source = meta.file();
  s.description = description;
  s.session_time = session_time;
  s.overrides = std::move(overrides);
  const auto sigma = [&](const std::string& key, double to_si) {
    const auto it = noise.find(key);
    return it == noise.end() ? 0.0 : it->second * to_si;
  };
  s.position_noise = sigma("position_mm", kMetresPerMm);
  s.orientation_noise = sigma("orientation_rad", 1.0);
  s.turns_noise = sigma("turns", 1.0);
  return s;
}

// ---------------------------------------------------------------- writers

std::ofstream openForWriting(const std::string& path) {
  std::ofstream out(path);
  if (!out) throw DataError(path, 0, 0, "cannot open the file for writing");
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

}  // namespace

// ---------------------------------------------------------------- public functions

const std::vector<std::string>& overrideSections() {
  static const std::vector<std::string> sections = {"robot", "medium",     "effects",
                                                    "motor", "simulation", "solver"};
  return sections;
}

void append(MeasuredData& data, MeasuredData more) {
  for (SteadyStateTable& t : more.tables) data.tables.push_back(std::move(t));
  for (TimeSeries& s : more.series) data.series.push_back(std::move(s));
}

void registerBagReader(BagReaderFn reader) {
  std::lock_guard<std::mutex> lock(bagReaderMutex());
  bagReaderSlot() = std::move(reader);
}

bool bagReaderRegistered() {
  std::lock_guard<std::mutex> lock(bagReaderMutex());
  return static_cast<bool>(bagReaderSlot());
}

MeasuredData readMeasuredData(const std::string& metadata_yaml_path) {
  const std::string& path = metadata_yaml_path;
  std::error_code ec;
  if (!fs::is_regular_file(path, ec))
    throw DataError(path, 0, 0,
                    std::string("cannot open the metadata file (") +
                        (fs::exists(path, ec) ? "not a regular file" : "no such file") + ")");
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::ParserException& e) {
    throw DataError(path, e.mark.line + 1, e.mark.column + 1, "YAML syntax error: " + e.msg);
  } catch (const YAML::Exception& e) {
    throw DataError(path, 0, 0, std::string("cannot read the metadata file: ") + e.what());
  }
  if (!root.IsDefined() || root.IsNull())
    throw DataError(path, 0, 0,
                    "the metadata file is empty; expected a map with 'kind: steady_state' or "
                    "'kind: time_series'");
  const Metadata meta(path, root);
  if (!root.IsMap()) meta.fail(root, "expected a map of metadata fields (kind, csv, noise, ...)");
  const YAML::Node kind_node = meta.get("kind");
  if (!kind_node.IsDefined())
    meta.fail(root, "missing required key 'kind' (steady_state or time_series)");
  const std::string kind = meta.text(kind_node, "kind");
  MeasuredData data;
  if (kind == "steady_state")
    data.tables.push_back(readSteadyState(meta));
  else if (kind == "time_series")
    data.series.push_back(readSeries(meta));
  else
    meta.fail(kind_node, "kind: expected steady_state or time_series, got '" + kind + "'");
  return data;
}

MeasuredData readMeasuredData(const std::vector<std::string>& metadata_yaml_paths) {
  MeasuredData data;
  for (const std::string& path : metadata_yaml_paths) append(data, readMeasuredData(path));
  return data;
}

std::string csvPathForMetadata(const std::string& yaml_path) {
  return fs::path(yaml_path).replace_extension(".csv").string();
}

void writeSteadyStateTable(const SteadyStateTable& table, const std::string& yaml_path) {
  const auto fail = [&](const std::string& message) {
    throw DataError(yaml_path, 0, 0, "cannot write the steady-state table: " + message);
  };
  if (table.rows.empty()) fail("it has no rows");
  if (!(table.settle_time > 0.0) || !std::isfinite(table.settle_time))
    fail("settle_time must be > 0, got " + csv::formatNumber(table.settle_time));
  if (!(table.window > 0.0) || !std::isfinite(table.window))
    fail("window must be > 0, got " + csv::formatNumber(table.window));
  checkOverridesForWriting(yaml_path, table.overrides);

  // Columns: the outputs any row measures (in the documented order), the union of row overrides.
  std::set<std::string> used;
  bool any_id = false;
  bool any_time = false;
  std::vector<std::string> override_names;
  for (const SteadyStateRow& row : table.rows) {
    if (!std::isfinite(row.omega_T)) fail("a row has a non-finite omega_T");
    any_id = any_id || !row.id.empty();
    any_time = any_time || !std::isnan(row.time);
    if (std::isinf(row.time)) fail("a row has an infinite time");
    for (const auto& [name, value] : row.measured) {
      if (!measuredByOutput(name))
        fail("unknown output '" + name + "' (allowed: " + joined(steadyOutputNames(), ", ") + ")");
      if (std::isinf(value)) fail("output '" + name + "' has an infinite value");
      used.insert(name);
    }
    checkOverridesForWriting(yaml_path, row.overrides);
    for (const auto& [name, text] : row.overrides)
      if (!contains(override_names, name)) override_names.push_back(name);
  }
  for (const auto& [name, sigma] : table.noise)
    if (!measuredByOutput(name))
      fail("noise for unknown output '" + name +
           "' (allowed: " + joined(steadyOutputNames(), ", ") + ")");
  std::vector<const MeasuredColumn*> columns;
  for (const MeasuredColumn& m : measuredColumns()) {
    if (!used.count(m.output)) continue;
    const auto it = table.noise.find(m.output);
    if (it == table.noise.end())
      fail(std::string("no noise for measured output '") + m.output + "'");
    columns.push_back(&m);
  }
  if (columns.empty()) fail("no row measures any output");
  for (const auto& [name, sigma] : table.noise)
    if (!(sigma > 0.0) || !std::isfinite(sigma))
      fail("noise for '" + name + "' must be > 0, got " + csv::formatNumber(sigma));

  const std::string csv_path = csvPathForMetadata(yaml_path);
  std::string text;
  std::vector<std::string> header;
  if (any_id) header.push_back("id");
  if (any_time) header.push_back("time_s");
  header.push_back("omega_T_rpm");
  for (const MeasuredColumn* m : columns) header.push_back(m->column);
  for (const std::string& name : override_names) header.push_back(name);
  text += csv::joinLine(header) + "\n";
  for (const SteadyStateRow& row : table.rows) {
    std::vector<std::string> fields;
    if (any_id) fields.push_back(row.id);
    if (any_time) fields.push_back(csv::formatNumber(row.time));
    fields.push_back(csv::formatNumber(row.omega_T / kRadPerSecPerRpm));
    for (const MeasuredColumn* m : columns) {
      const auto it = row.measured.find(m->output);
      fields.push_back(it == row.measured.end() ? "" : csv::formatNumber(it->second / m->to_si));
    }
    for (const std::string& name : override_names) {
      std::string value;
      for (const auto& [n, v] : row.overrides)
        if (n == name) value = v;
      fields.push_back(csv::trim(value));
    }
    text += csv::joinLine(fields) + "\n";
  }
  writeText(csv_path, text);

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
  writeText(yaml_path, metadataText(y));
}

void writeTimeSeries(const TimeSeries& s, const std::string& yaml_path) {
  const auto fail = [&](const std::string& message) {
    throw DataError(yaml_path, 0, 0, "cannot write the time series: " + message);
  };
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

  const std::string csv_path = csvPathForMetadata(yaml_path);
  std::vector<std::string> header = {"t_s", "x_mm", "y_mm"};
  if (s.has_z) header.push_back("z_mm");
  if (!s.orientation.empty()) header.insert(header.end(), {"qw", "qx", "qy", "qz"});
  if (!s.head_turns.empty()) header.push_back("head_turns");
  if (!s.tail_turns.empty()) header.push_back("tail_turns");
  header.push_back("omega_T_rpm");
  std::string text = csv::joinLine(header) + "\n";
  for (size_t i = 0; i < n; ++i) {
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
  writeText(csv_path, text);

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
  writeText(yaml_path, metadataText(y));
}

}  // namespace identify
}  // namespace flagella
