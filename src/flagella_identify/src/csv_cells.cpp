// Checks of CSV headers and cells shared by the steady-state table and time-series readers.
#include <algorithm>
#include <cmath>

#include "data_io_internal.h"
#include "flagella_sim/core/text_lists.h"
#include "text_format.h"

namespace flagella {
namespace identify {
namespace data_io {

std::map<std::string, int> indexHeader(const csv::Table& table) {
  std::map<std::string, int> index;
  for (size_t i = 0; i < table.header.size(); ++i) {
    const std::string& name = table.header[i];
    const int column = static_cast<int>(i) + 1;
    if (name.empty()) throw DataError(table.path, table.header_line, column, "empty column name");
    const auto [it, inserted] = index.emplace(name, column - 1);
    if (!inserted)
      throw DataError(table.path, table.header_line, column,
                      "duplicate column '" + abbreviated(name) + "' (also column " +
                          std::to_string(it->second + 1) + ")");
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

std::optional<double> cellNumber(const csv::Table& table, const csv::Row& row, int index,
                                 bool optional) {
  const std::string& text = row.fields[index];
  const std::string& name = table.header[index];
  if (text.empty()) {
    if (optional) return std::nullopt;
    throw DataError(table.path, row.line, index + 1,
                    "column '" + abbreviated(name) + "': expected a number, got an empty cell");
  }
  const std::optional<double> value = csv::parseNumber(text);
  if (!value)
    throw DataError(
        table.path, row.line, index + 1,
        "column '" + abbreviated(name) + "': expected a number, got '" + abbreviated(text) + "'");
  if (!std::isfinite(*value))
    throw DataError(table.path, row.line, index + 1,
                    "column '" + abbreviated(name) + "': expected a finite number, got '" +
                        abbreviated(text) + "'");
  return value;
}

double requiredNumber(const csv::Table& table, const csv::Row& row, int index) {
  return *cellNumber(table, row, index, false);
}

std::optional<double> rangedNumber(const csv::Table& table, const csv::Row& row, int index,
                                   bool optional, double min, double max, const std::string& unit) {
  const std::optional<double> value = cellNumber(table, row, index, optional);
  if (value && !(*value >= min && *value <= max))
    throw DataError(table.path, row.line, index + 1,
                    "column '" + abbreviated(table.header[index]) +
                        "': " + csv::formatNumber(*value) + " " + unit +
                        " is outside the plausible range [" + csv::formatNumber(min) + ", " +
                        csv::formatNumber(max) + "] " + unit);
  return value;
}

void missingColumn(const csv::Table& table, const std::string& name) {
  throw DataError(table.path, table.header_line, 1,
                  "missing required column '" + name + "' (header has: " +
                      abbreviated(joined(table.header, ", "), kMaxListedText) + ")");
}

}  // namespace data_io
}  // namespace identify
}  // namespace flagella
