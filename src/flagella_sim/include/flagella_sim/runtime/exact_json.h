// Doubles in JSON without loss, for results passed between the ranks of an MPI run as text
// (distributed_for.h): finite values as JSON numbers (nlohmann prints them round-trip exact),
// non-finite ones as the strings "nan", "inf" and "-inf", which JSON numbers cannot hold.
#pragma once

#include <cmath>
#include <nlohmann/json.hpp>
#include <string>

namespace flagella {

inline nlohmann::json exactJson(double v) {
  if (std::isfinite(v)) return v;
  return std::isnan(v) ? "nan" : (v > 0 ? "inf" : "-inf");
}

inline double exactNumber(const nlohmann::json& j) {
  if (j.is_number()) return j.get<double>();
  const std::string s = j.get<std::string>();
  if (s == "nan") return std::nan("");
  return s == "inf" ? HUGE_VAL : -HUGE_VAL;
}

}  // namespace flagella
