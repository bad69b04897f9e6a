// printf-style formatting of numbers into report text (library-internal).
#pragma once

#include <cstdio>
#include <string>
#include <vector>

#include "flagella_sim/core/text_lists.h"  // joined(), found from flagella::identify

namespace flagella {
namespace identify {

/// `format` with up to four numeric conversions (%g, %.1f, ...); the text must not contain
/// other conversions.
inline std::string formatted(const std::string& format, double a, double b = 0.0, double c = 0.0,
                             double d = 0.0) {
  char buffer[512];
  std::snprintf(buffer, sizeof buffer, format.c_str(), a, b, c, d);
  return buffer;
}

}  // namespace identify
}  // namespace flagella
