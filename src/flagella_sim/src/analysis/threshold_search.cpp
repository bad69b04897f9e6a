#include "flagella_sim/analysis/threshold_search.h"

#include <cmath>
#include <limits>
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
  require(o.grid_ratio == 0.0 || (std::isfinite(o.grid_ratio) && o.grid_ratio > 1.0), "grid_ratio",
          o.grid_ratio, "0 (no grid) or > 1");
}

ThresholdResult findThreshold(const std::function<ThresholdProbe(double)>& probe,
                              const ThresholdSearchOptions& o,
                              const std::function<void(const ThresholdProbe&)>& progress) {
  validate(o);
  ThresholdResult r;
  const bool gridded = o.grid_ratio > 1.0;
  // A rate on the grid low * grid_ratio^k (the rate itself without a grid).
  auto snap = [&](double rate) {
    if (!gridded) return rate;
    return o.low *
           std::pow(o.grid_ratio, std::round(std::log(rate / o.low) / std::log(o.grid_ratio)));
  };
  // Runs `rate` (snapped); false if the search must stop (failed run or out of runs).
  auto run = [&](double rate, bool& above) {
    rate = snap(rate);
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
  low = snap(low);
  high = snap(high);
  auto open = [&] {
    return gridded ? high / low > o.grid_ratio * (1.0 + 1e-9) : high - low > o.tolerance;
  };
  while (open()) {  // bisection (geometric on the grid)
    const double mid = gridded ? snap(std::sqrt(low * high)) : 0.5 * (low + high);
    if (!run(mid, above)) return r;
    (above ? high : low) = mid;
  }
  r.found = true;
  r.low = low;
  r.high = high;
  r.threshold = 0.5 * (low + high);
  return r;
}

double interpolatedThreshold(const ThresholdResult& result, double level) {
  if (!result.found) return std::numeric_limits<double>::quiet_NaN();
  const ThresholdProbe* below = nullptr;
  const ThresholdProbe* above = nullptr;
  for (const ThresholdProbe& p : result.runs) {
    if (p.failed) continue;
    if (p.rate == result.low && !p.above) below = &p;
    if (p.rate == result.high && p.above) above = &p;
  }
  if (!below || !above || !(below->indicator < level && above->indicator >= level))
    return result.threshold;
  const double w = (level - below->indicator) / (above->indicator - below->indicator);
  return below->rate + w * (above->rate - below->rate);
}

}  // namespace flagella
