// Library-internal pieces shared by the measured-data readers and writers (data_io.h).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

#include "csv.h"
#include "flagella_identify/data_io.h"

namespace flagella {
namespace identify {
namespace data_io {

class Metadata;

/// Fewest samples a time series may have (reading and writing).
constexpr int kMinSamples = 3;

bool contains(const std::vector<std::string>& names, const std::string& name);

// ---------------------------------------------------------------- columns and overrides

/// A measured column of a steady-state table: file name, output name, factor to SI.
struct MeasuredColumn {
  const char* column;
  const char* output;
  double to_si;
};

/// The measured columns in the documented order.
const std::vector<MeasuredColumn>& measuredColumns();
const MeasuredColumn* measuredByColumn(const std::string& column);
const MeasuredColumn* measuredByOutput(const std::string& output);
std::vector<std::string> measuredColumnNames();

/// Empty if `name` is a valid override name "section.field[.more]", else what is wrong.
std::string overrideNameProblem(const std::string& name);

// ---------------------------------------------------------------- CSV header and cell checks

/// Header columns by name, with the duplicate and empty-name checks.
std::map<std::string, int> indexHeader(const csv::Table& table);

void checkFieldCount(const csv::Table& table, const csv::Row& row);

/// The number in a cell; nullopt for an empty cell if `optional`, else an error.
std::optional<double> cellNumber(const csv::Table& table, const csv::Row& row, int index,
                                 bool optional);

double requiredNumber(const csv::Table& table, const csv::Row& row, int index);

[[noreturn]] void missingColumn(const csv::Table& table, const std::string& name);

// ---------------------------------------------------------------- readers of one metadata kind

/// kind: steady_state (the metadata keys, then the CSV it names).
SteadyStateTable readSteadyState(const Metadata& meta);

/// kind: time_series (the metadata keys, then the CSV or bag it names).
TimeSeries readSeries(const Metadata& meta);

}  // namespace data_io
}  // namespace identify
}  // namespace flagella
