// Reading a time series: its metadata keys, then the CSV or (through the registered reader) bag.
#include <cmath>
#include <mutex>
#include <utility>

#include "data_io_internal.h"
#include "flagella_sim/core/text_lists.h"
#include "metadata.h"
#include "text_format.h"

namespace flagella {
namespace identify {
namespace data_io {

namespace {

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
      throw DataError(csv.path, csv.header_line, static_cast<int>(i) + 1,
                      "unknown column '" + abbreviated(csv.header[i]) +
                          "' (allowed: " + joined(allowed, ", ") + ")");
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
    const double t = *rangedNumber(csv, r, t_col, false, 0.0, kMaxTimeS, "s");
    if (!s.t.empty() && !(t > s.t.back()))
      throw DataError(csv.path, r.line, t_col + 1,
                      "column 't_s': time must be strictly increasing, got " +
                          csv::formatNumber(t) + " after " + csv::formatNumber(s.t.back()));
    s.t.push_back(t);
    const auto length = [&](int c) {
      return *rangedNumber(csv, r, c, false, -kMaxLengthMm, kMaxLengthMm, "mm") * kMetresPerMm;
    };
    const auto turns = [&](int c) {
      return *rangedNumber(csv, r, c, false, -kMaxTurns, kMaxTurns, "turns");
    };
    const double z = s.has_z ? length(z_col) : kMissing;
    s.position.emplace_back(length(col("x_mm")), length(col("y_mm")), z);
    if (has_q) {
      Eigen::Quaterniond q(requiredNumber(csv, r, col("qw")), requiredNumber(csv, r, col("qx")),
                           requiredNumber(csv, r, col("qy")), requiredNumber(csv, r, col("qz")));
      const double norm = q.norm();
      if (!(std::abs(norm - 1.0) <= kQuaternionNormTolerance))
        throw DataError(csv.path, r.line, col("qw") + 1,
                        "quaternion (qw, qx, qy, qz) has norm " + csv::formatNumber(norm) +
                            "; expected a unit quaternion (norm within " +
                            csv::formatNumber(kQuaternionNormTolerance) + " of 1)");
      q.coeffs() /= norm;
      s.orientation.push_back(q);
    }
    if (col("head_turns") >= 0) s.head_turns.push_back(turns(col("head_turns")));
    if (col("tail_turns") >= 0) s.tail_turns.push_back(turns(col("tail_turns")));
    s.omega_cmd.push_back(
        *rangedNumber(csv, r, col("omega_T_rpm"), false, -kMaxRpm, kMaxRpm, "rpm") *
        kRadPerSecPerRpm);
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

/// The bag_namespace and bag_position keys.
BagOptions bagOptions(const Metadata& meta) {
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
      meta.fail(node,
                "bag_position: expected rod_state or camera_fix, got '" + abbreviated(value) + "'");
  }
  return options;
}

/// The series in the bag the metadata names, read by the registered bag reader; `data_name`
/// is set to the quoted bag path (for messages).
TimeSeries readSeriesBag(const Metadata& meta, std::string& data_name) {
  const BagOptions options = bagOptions(meta);
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
  return reader(bag_path, options);
}

}  // namespace

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
  const double session_time =
      meta.has("session_time_s")
          ? meta.inRange(meta.get("session_time_s"), "session_time_s", 0.0, true, kMaxTimeS, "s")
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
    s = readSeriesBag(meta, data_name);
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

}  // namespace data_io

void registerBagReader(BagReaderFn reader) {
  std::lock_guard<std::mutex> lock(data_io::bagReaderMutex());
  data_io::bagReaderSlot() = std::move(reader);
}

bool bagReaderRegistered() {
  std::lock_guard<std::mutex> lock(data_io::bagReaderMutex());
  return static_cast<bool>(data_io::bagReaderSlot());
}

}  // namespace identify
}  // namespace flagella
