// Small text helpers shared by error messages, listings and reports: joined name lists,
// numbers printed as a stream prints them, long user text abbreviated.
#pragma once

#include <sstream>
#include <string>
#include <vector>

namespace flagella {

/// The names separated by `separator` ("a, b" or "a + b").
inline std::string joined(const std::vector<std::string>& names,
                          const std::string& separator = ", ") {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : separator) + n;
  return out;
}

/// `x` in the stream's default format (6 significant digits: 0.001, 1e+06).
inline std::string formatNumber(double x) {
  std::ostringstream out;
  out << x;
  return out.str();
}

/// `text` as an error message quotes it: at most `max` characters, a longer text cut with its
/// length given ("abc... (102400 characters)").
inline std::string abbreviated(const std::string& text, size_t max = 60) {
  if (text.size() <= max) return text;
  return text.substr(0, max) + "... (" + std::to_string(text.size()) + " characters)";
}

}  // namespace flagella
