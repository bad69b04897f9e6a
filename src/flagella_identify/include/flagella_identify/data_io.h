// Reading and writing measured data: a YAML metadata file (kind, noise, overrides, ...) that
// names a CSV file (steady-state table or time series) or a bag (time series). Everything is
// converted to SI units on reading and back to the documented file units on writing. Every
// malformed input throws DataError naming file, line and column. ROS-free: bags are read
// through a reader that the flagella_identify_bag library registers (enableBagInput()).
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "flagella_identify/data_error.h"
#include "flagella_identify/measured_data.h"
#include "flagella_sim/core/units.h"

namespace flagella {
namespace identify {

/// Unit factors from the file units to SI.
using units::kMetresPerMm;
using units::kRadPerSecPerRpm;

/// Everything read from one or more metadata files.
struct MeasuredData {
  std::vector<SteadyStateTable> tables;
  std::vector<TimeSeries> series;
};

/// Appends the tables and series of `more` to `data`.
void append(MeasuredData& data, MeasuredData more);

/// Reads one metadata YAML file (kind: steady_state or kind: time_series) and the CSV or bag
/// it names (paths relative to the YAML file's directory). Gives one table or one series.
MeasuredData readMeasuredData(const std::string& metadata_yaml_path);

/// Reads several metadata files and merges them, in order.
MeasuredData readMeasuredData(const std::vector<std::string>& metadata_yaml_paths);

/// How a bag's topics become a time series.
struct BagOptions {
  enum class Position {
    kRodState,  ///< head position from <ns>/rod_state head_pose (the true head pose)
    kCameraFix  ///< head position from <ns>/camera_fix (measured fixes); other signals
                ///< interpolated (angles, orientation) or held (motor rate) at the fix times
  };
  std::string topic_namespace;  ///< topic prefix, e.g. "/robot_a"; "" for the root namespace
  Position position = Position::kRodState;
};

/// Reads a bag into a time series (t, position, has_z, orientation, turns, omega_cmd; source =
/// the bag path; noise and metadata left at their defaults).
using BagReaderFn = std::function<TimeSeries(const std::string&, const BagOptions&)>;

/// Installs the bag reader readMeasuredData uses for `bag:` metadata (an empty function removes
/// it). flagella_identify_bag's enableBagInput() installs readTimeSeriesFromBag.
void registerBagReader(BagReaderFn reader);
bool bagReaderRegistered();

/// Writes `table` as YAML metadata at `yaml_path` plus a CSV next to it (same stem, .csv), in
/// the documented file units with 10 significant digits. Row override names become CSV columns
/// (the union over rows). Throws DataError if the table could not be read back (no rows,
/// unknown output name, missing or non-positive noise, bad override name) or a file cannot be
/// written.
void writeSteadyStateTable(const SteadyStateTable& table, const std::string& yaml_path);

/// Writes `series` as YAML metadata at `yaml_path` plus a CSV next to it (same stem, .csv).
/// Throws DataError if the series could not be read back (inconsistent lengths, fewer than 3
/// samples, non-increasing t, missing or non-positive noise) or a file cannot be written.
void writeTimeSeries(const TimeSeries& series, const std::string& yaml_path);

/// The CSV path the writers use for `yaml_path`: same directory and stem, extension .csv.
std::string csvPathForMetadata(const std::string& yaml_path);

/// The config sections an override "section.field" may address.
const std::vector<std::string>& overrideSections();

}  // namespace identify
}  // namespace flagella
