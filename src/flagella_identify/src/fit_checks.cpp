// The checks around a fit (fit.h): its options before it runs, and where its parameters ended
// (on a bound, unidentifiable, or less certain than their range is wide).
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "flagella_identify/fit.h"
#include "text_format.h"

namespace flagella {
namespace identify {

std::vector<std::string> offTheMap(const std::vector<FitParameter>& parameters) {
  std::vector<std::string> out;
  for (const FitParameter& p : parameters) {
    const auto u = [&](double v) { return p.log_scale ? std::log(v) : v; };
    const double width = u(p.upper) - u(p.lower);
    const double sigma_u = p.log_scale ? p.uncertainty / p.value : p.uncertainty;
    char line[240];
    if (u(p.value) - u(p.lower) <= 1e-3 * width)
      std::snprintf(line, sizeof line, "%s ended on its lower bound %.4g", p.name.c_str(), p.lower);
    else if (u(p.upper) - u(p.value) <= 1e-3 * width)
      std::snprintf(line, sizeof line, "%s ended on its upper bound %.4g", p.name.c_str(), p.upper);
    else if (!std::isfinite(sigma_u))
      std::snprintf(line, sizeof line, "%s has no uncertainty (not identifiable)", p.name.c_str());
    else if (sigma_u > width)
      std::snprintf(line, sizeof line, "%s = %.4g has an uncertainty wider than its range",
                    p.name.c_str(), p.value);
    else
      continue;
    out.push_back(line);
  }
  return out;
}

void validateFitOptions(const FitOptions& o) {
  auto refuse = [](const char* field, const char* range, double got) {
    throw std::invalid_argument(std::string("FitOptions::") + field + " must be " + range +
                                formatted(", got %g", got));
  };
  if (o.max_iterations < 1) refuse("max_iterations", ">= 1", o.max_iterations);
  if (!(o.function_tolerance > 0.0 && o.function_tolerance < 1.0))
    refuse("function_tolerance", "in (0, 1)", o.function_tolerance);
  if (o.max_line_search_trials < 0)
    refuse("max_line_search_trials", ">= 0 (0: no line search)", o.max_line_search_trials);
  if (!(o.log_step > 0.0 && o.log_step < 1.0)) refuse("log_step", "in (0, 1)", o.log_step);
  if (!(o.linear_step > 0.0 && o.linear_step < 1.0))
    refuse("linear_step", "in (0, 1)", o.linear_step);
  if (!(o.bracket_step > 0.0)) refuse("bracket_step", "> 0", o.bracket_step);
  if (!(o.bracket_tolerance > 0.0)) refuse("bracket_tolerance", "> 0", o.bracket_tolerance);
}

}  // namespace identify
}  // namespace flagella
