#include "csv.h"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <system_error>

#include "flagella_identify/data_error.h"

namespace flagella {
namespace identify {
namespace csv {

namespace {
bool isBlank(char c) { return c == ' ' || c == '\t'; }
}  // namespace

std::string trim(const std::string& text) {
  size_t begin = 0;
  size_t end = text.size();
  while (begin < end && isBlank(text[begin])) ++begin;
  while (end > begin && isBlank(text[end - 1])) --end;
  return text.substr(begin, end - begin);
}

std::vector<std::string> splitLine(const std::string& text, const std::string& path, int line) {
  std::vector<std::string> fields;
  size_t i = 0;
  const size_t n = text.size();
  while (true) {
    const int column = static_cast<int>(fields.size()) + 1;
    while (i < n && isBlank(text[i])) ++i;
    std::string field;
    if (i < n && text[i] == '"') {
      ++i;
      bool closed = false;
      while (i < n) {
        if (text[i] == '"') {
          if (i + 1 < n && text[i + 1] == '"') {
            field += '"';
            i += 2;
            continue;
          }
          ++i;
          closed = true;
          break;
        }
        field += text[i++];
      }
      if (!closed) throw DataError(path, line, column, "unterminated quote (missing closing '\"')");
      while (i < n && isBlank(text[i])) ++i;
      if (i < n && text[i] != ',')
        throw DataError(path, line, column,
                        "unexpected text after a quoted field; expected ',' or the end of the "
                        "line");
    } else {
      const size_t comma = text.find(',', i);
      const size_t stop = comma == std::string::npos ? n : comma;
      field = trim(text.substr(i, stop - i));
      i = stop;
    }
    fields.push_back(field);
    if (i >= n) break;
    ++i;  // the comma; a trailing comma gives an empty last field
  }
  return fields;
}

Table read(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw DataError(path, 0, 0, "cannot open the CSV file");
  Table table;
  table.path = path;
  std::string text;
  int line = 0;
  while (std::getline(in, text)) {
    ++line;
    if (!text.empty() && text.back() == '\r') text.pop_back();
    if (line == 1 && text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);  // UTF-8 BOM
    const std::string trimmed = trim(text);
    if (trimmed.empty() || trimmed[0] == '#') continue;
    std::vector<std::string> fields = splitLine(text, path, line);
    if (table.header_line == 0) {
      table.header_line = line;
      table.header = std::move(fields);
    } else {
      table.rows.push_back(Row{line, std::move(fields)});
    }
  }
  if (in.bad()) throw DataError(path, 0, 0, "error while reading the CSV file");
  if (table.header_line == 0)
    throw DataError(path, 0, 0, "no header line (the file is empty or holds only comments)");
  return table;
}

std::optional<double> parseNumber(const std::string& text) {
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  if (begin != end && *begin == '+') ++begin;  // from_chars takes '-' only
  if (begin == end || *begin == '+' || (*begin == '-' && begin != text.data())) return std::nullopt;
  double value = 0.0;
  const std::from_chars_result r = std::from_chars(begin, end, value);
  if (r.ptr != end) return std::nullopt;
  if (r.ec == std::errc::result_out_of_range) {
    // from_chars leaves `value` untouched: a negative exponent underflowed (-> 0), anything
    // else overflowed (-> infinity, which callers reject as non-finite).
    const bool negative = *begin == '-';
    const size_t e = text.find_first_of("eE");
    const bool underflow = e != std::string::npos && e + 1 < text.size() && text[e + 1] == '-';
    const double magnitude = underflow ? 0.0 : std::numeric_limits<double>::infinity();
    return negative ? -magnitude : magnitude;
  }
  if (r.ec != std::errc()) return std::nullopt;
  return value;
}

std::string formatNumber(double value) {
  if (std::isnan(value)) return "";
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.10g", value);
  return buffer;
}

std::string quote(const std::string& field) {
  const bool needs =
      field.find_first_of(",\"\r\n") != std::string::npos ||
      (!field.empty() && (isBlank(field.front()) || isBlank(field.back()) || field.front() == '#'));
  if (!needs) return field;
  std::string out = "\"";
  for (char c : field) {
    if (c == '"') out += '"';
    out += c;
  }
  return out + "\"";
}

std::string joinLine(const std::vector<std::string>& fields) {
  std::string out;
  for (size_t i = 0; i < fields.size(); ++i) out += (i ? "," : "") + quote(fields[i]);
  return out;
}

}  // namespace csv
}  // namespace identify
}  // namespace flagella
