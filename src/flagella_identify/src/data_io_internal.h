// Library-internal pieces shared by the measured-data readers and writers (data_io.h).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "csv.h"
#include "data_io_names.h"
#include "flagella_identify/data_io.h"

namespace flagella {
namespace identify {
namespace data_io {

class Metadata;

/// Fewest samples a time series may have (reading and writing).
constexpr int kMinSamples = 3;

// ---------------------------------------------------------------- columns and overrides

/// A measured column of a steady-state table: file name, output name, factor to SI, and the
/// range a measurement of any robot of this kind can take (file units; README, measured data).
struct MeasuredColumn {
  const char* column;
  const char* output;
  double to_si;
  double min;
  double max;
  const char* unit;
};

/// Plausible ranges of measured and commanded values, in file units (README, measured data): far
/// beyond any palm-sized robot, so they only catch values that cannot be measurements (1e308, a
/// negative time, a unit mix-up by orders of magnitude).
constexpr double kMaxRpm = 1e4;          ///< motor and body rates [rpm], the config's motor limit
constexpr double kMaxSpeedMmS = 1e4;     ///< swimming speed [mm/s] (10 m/s)
constexpr double kMaxYawRateRadS = 1e3;  ///< yaw rate [rad/s] (about kMaxRpm)
constexpr double kMaxLengthMm = 1e9;     ///< positions and radii [mm] (1000 km)
constexpr double kMaxTimeS = 1e6;        ///< times [s], the simulator's longest session
constexpr double kMaxTurns = 1e9;        ///< counted turns (kMaxRpm over kMaxTimeS is 1.7e8)
constexpr double kQuaternionNormTolerance = 1e-3;  ///< |q| - 1 allowed before normalising

/// The measured columns in the documented order.
const std::vector<MeasuredColumn>& measuredColumns();
const MeasuredColumn* measuredByColumn(const std::string& column);
const MeasuredColumn* measuredByOutput(const std::string& output);
std::vector<std::string> measuredColumnNames();
/// The measured column whose per-row uncertainty `column` is ("sigma_v_mm_s" -> v_mm_s), or
/// nullptr.
const MeasuredColumn* sigmaColumnOf(const std::string& column);

// ---------------------------------------------------------------- CSV header and cell checks

/// Header columns by name, with the duplicate and empty-name checks.
std::map<std::string, int> indexHeader(const csv::Table& table);

void checkFieldCount(const csv::Table& table, const csv::Row& row);

/// The number in a cell; nullopt for an empty cell if `optional`, else an error.
std::optional<double> cellNumber(const csv::Table& table, const csv::Row& row, int index,
                                 bool optional);

double requiredNumber(const csv::Table& table, const csv::Row& row, int index);

/// The number in a cell (as cellNumber), which must lie in [min, max] (`unit` for messages).
std::optional<double> rangedNumber(const csv::Table& table, const csv::Row& row, int index,
                                   bool optional, double min, double max, const std::string& unit);

[[noreturn]] void missingColumn(const csv::Table& table, const std::string& name);

// ---------------------------------------------------------------- readers of one metadata kind

/// kind: steady_state (the metadata keys, then the CSV it names).
SteadyStateTable readSteadyState(const Metadata& meta);

/// kind: time_series (the metadata keys, then the CSV or bag it names).
TimeSeries readSeries(const Metadata& meta);

}  // namespace data_io
}  // namespace identify
}  // namespace flagella
