#include "flagella_sim/analysis/threshold_search.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace flagella {

namespace {

std::string number(double x) {
  std::ostringstream out;
  out << x;
  return out.str();
}

void require(bool ok, const std::string& field, double value, const std::string& range) {
  if (!ok) throw std::invalid_argument(field + " = " + number(value) + " must be " + range);
}

}  // namespace

void validate(const ThresholdSearchOptions& o) {
  require(std::isfinite(o.min_rate) && o.min_rate > 0.0, "min_rate", o.min_rate, "> 0");
  require(std::isfinite(o.low) && o.low >= o.min_rate, "low", o.low,
          ">= min_rate (" + number(o.min_rate) + ")");
  require(std::isfinite(o.high) && o.high > o.low, "high", o.high, "> low (" + number(o.low) + ")");
  require(std::isfinite(o.max_rate) && o.max_rate >= o.high, "max_rate", o.max_rate,
          ">= high (" + number(o.high) + ")");
  require(std::isfinite(o.tolerance) && o.tolerance > 0.0, "tolerance", o.tolerance, "> 0");
  require(o.max_runs >= 2, "max_runs", o.max_runs, ">= 2");
}

ThresholdResult findThreshold(const std::function<ThresholdProbe(double)>& probe,
                              const ThresholdSearchOptions& o,
                              const std::function<void(const ThresholdProbe&)>& progress) {
  validate(o);
  ThresholdResult r;
  // Runs `rate`; false if the search must stop (failed run or out of runs).
  auto run = [&](double rate, bool& above) {
    if (static_cast<int>(r.runs.size()) >= o.max_runs) {
      r.message = "no threshold within " + std::to_string(o.max_runs) + " runs";
      return false;
    }
    ThresholdProbe p = probe(rate);
    p.rate = rate;
    r.runs.push_back(p);
    if (progress) progress(p);
    if (p.failed) {
      r.message = "run at " + number(rate) + " rpm failed: " + p.error;
      return false;
    }
    above = p.above;
    return true;
  };
  double low = o.low, high = o.high;
  bool above = false, high_known = false;
  if (!run(low, above)) return r;
  while (above) {  // bracketing from below: halve until below the threshold
    high = low;
    high_known = true;
    low *= 0.5;
    if (low < o.min_rate) {
      r.message = "above the threshold even at " + number(high) + " rpm (min_rate " +
                  number(o.min_rate) + ")";
      return r;
    }
    if (!run(low, above)) return r;
  }
  if (!high_known) {
    if (!run(high, above)) return r;
    while (!above) {  // bracketing from above: double until above the threshold
      low = high;
      high *= 2.0;
      if (high > o.max_rate) {
        r.message = "below the threshold up to " + number(low) + " rpm (max_rate " +
                    number(o.max_rate) + ")";
        return r;
      }
      if (!run(high, above)) return r;
    }
  }
  while (high - low > o.tolerance) {  // bisection
    const double mid = 0.5 * (low + high);
    if (!run(mid, above)) return r;
    (above ? high : low) = mid;
  }
  r.found = true;
  r.low = low;
  r.high = high;
  r.threshold = 0.5 * (low + high);
  return r;
}

}  // namespace flagella
