// Small text helpers shared by error messages, listings and reports: joined name lists and
// numbers printed as a stream prints them.
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

}  // namespace flagella
