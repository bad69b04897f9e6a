#include "flagella_sim/analysis/threshold_search.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
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

double smoothedCrossing(const std::vector<ThresholdProbe>& probes, double level) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  if (probes.size() < 3) return nan;
  for (const ThresholdProbe& p : probes)
    if (p.failed) return nan;
  std::vector<double> averaged;  // at probes[1 .. n-2]
  for (size_t i = 1; i + 1 < probes.size(); ++i)
    averaged.push_back((probes[i - 1].indicator + probes[i].indicator + probes[i + 1].indicator) /
                       3.0);
  if (averaged.front() >= level) return nan;  // the crossing lies below these rates
  for (size_t i = 0; i + 1 < averaged.size(); ++i) {
    if (averaged[i + 1] < level) continue;
    const double w = (level - averaged[i]) / (averaged[i + 1] - averaged[i]);
    const double low = probes[i + 1].rate, high = probes[i + 2].rate;
    return low * std::pow(high / low, w);
  }
  return nan;
}

WindowThreshold windowThreshold(const std::function<ThresholdProbe(double)>& probe, double center,
                                double grid_ratio, int half_width, double level, int max_moves,
                                const std::function<void(const ThresholdProbe&)>& progress) {
  // One run after the other, stopping at a failed one.
  auto one_by_one = [&](const std::vector<double>& rates) {
    std::vector<ThresholdProbe> made;
    for (double rate : rates) {
      made.push_back(probe(rate));
      if (made.back().failed) break;
    }
    return made;
  };
  return windowThreshold(ProbeBatch(one_by_one), center, grid_ratio, half_width, level, max_moves,
                         progress);
}

WindowThreshold windowThreshold(const ProbeBatch& probes, double center, double grid_ratio,
                                int half_width, double level, int max_moves,
                                const std::function<void(const ThresholdProbe&)>& progress) {
  require(std::isfinite(center) && center > 0.0, "center", center, "> 0");
  require(std::isfinite(grid_ratio) && grid_ratio > 1.0, "grid_ratio", grid_ratio, "> 1");
  require(half_width >= 2, "half_width", half_width, ">= 2");
  require(max_moves >= 0, "max_moves", max_moves, ">= 0");
  WindowThreshold w;
  std::map<long, ThresholdProbe> by_k;  // every run made, by grid index
  long low = std::lround(std::log(center) / std::log(grid_ratio)) - half_width;
  for (int move = 0;; ++move) {
    std::vector<long> missing;
    std::vector<double> rates;
    for (long k = low; k <= low + 2 * half_width; ++k)
      if (!by_k.count(k)) {
        missing.push_back(k);
        rates.push_back(std::pow(grid_ratio, static_cast<double>(k)));
      }
    const std::vector<ThresholdProbe> made =
        rates.empty() ? std::vector<ThresholdProbe>{} : probes(rates);
    for (size_t i = 0; i < made.size() && i < rates.size(); ++i) {
      ThresholdProbe p = made[i];
      p.rate = rates[i];
      w.runs.push_back(p);
      if (progress) progress(p);
      if (p.failed) {
        w.message = "run at " + number(p.rate) + " rpm failed: " + p.error;
        return w;
      }
      by_k.emplace(missing[i], p);
    }
    if (made.size() < rates.size()) throw std::logic_error("windowThreshold: runs missing");
    std::vector<ThresholdProbe> window;
    for (long k = low; k <= low + 2 * half_width; ++k) window.push_back(by_k.at(k));
    w.threshold = smoothedCrossing(window, level);
    if (std::isfinite(w.threshold)) return w;
    // Averaged indicator already at the level at the window's second rate: the crossing is below.
    const bool below =
        (window[0].indicator + window[1].indicator + window[2].indicator) / 3.0 >= level;
    if (move == max_moves) {
      w.message = "the indicator averaged over neighbouring rates does not cross " + number(level) +
                  " between " + number(window[1].rate) + " and " +
                  number(window[window.size() - 2].rate) + " rpm (" + std::to_string(move) +
                  " window moves)";
      return w;
    }
    low += (below ? -1 : 1) * (2 * half_width - 2);
  }
}

}  // namespace flagella
