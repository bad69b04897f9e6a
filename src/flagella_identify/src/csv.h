// Minimal CSV reading and writing for the measured-data files: comma separated, one record per
// line, '#' comment lines and blank lines skipped (but counted), fields trimmed, optional
// double quotes ("a, b" and "" for a quote inside). Errors are DataError with file:line:column.
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace flagella {
namespace identify {
namespace csv {

struct Row {
  int line = 0;                     ///< 1-based line in the file
  std::vector<std::string> fields;  ///< trimmed, unquoted
};

struct Table {
  std::string path;
  int header_line = 0;              ///< 1-based line of the header
  std::vector<std::string> header;  ///< column names
  std::vector<Row> rows;
};

/// Reads a CSV file. Throws DataError if it cannot be opened, has no header line, or a line
/// cannot be split (unterminated quote). The field count is not checked here.
Table read(const std::string& path);

/// Splits one line into trimmed fields; `path` and `line` are for error messages.
std::vector<std::string> splitLine(const std::string& text, const std::string& path, int line);

/// Parses a whole cell as a decimal number (leading '+' allowed; inf/nan parse to non-finite
/// values). Empty or partial text gives nullopt.
std::optional<double> parseNumber(const std::string& text);

/// "%.10g"; NaN gives "" (a missing value).
std::string formatNumber(double value);

/// Quotes a field if it would not survive splitLine unchanged.
std::string quote(const std::string& field);

/// Joins fields (quoted as needed) with commas.
std::string joinLine(const std::vector<std::string>& fields);

std::string trim(const std::string& text);

}  // namespace csv
}  // namespace identify
}  // namespace flagella
