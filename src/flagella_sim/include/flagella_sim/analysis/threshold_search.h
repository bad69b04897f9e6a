// Bracketing + bisection for the motor rate at which a monotone yes/no property of a run switches
// (the flagellum's buckling threshold, docs/model.md 8.4.4). Pure logic: the runs are a callback.
#pragma once

#include <functional>
#include <limits>
#include <string>
#include <vector>

namespace flagella {

/// One run of the search: the rate tried and what it showed.
struct ThresholdProbe {
  double rate = 0.0;       ///< motor rate magnitude tried [rpm]
  bool above = false;      ///< the property holds (e.g. buckled)
  double indicator = 0.0;  ///< the measured quantity behind `above` (e.g. max tilt [deg])
  double wall_seconds = 0.0;
  bool failed = false;  ///< the run could not be completed (then `error` says why)
  std::string error;
};

struct ThresholdSearchOptions {
  double low = 10.0;         ///< first lower guess [rpm], > 0
  double high = 100.0;       ///< first upper guess [rpm], > low
  double min_rate = 0.1;     ///< the lower guess is halved down to this before giving up
  double max_rate = 2000.0;  ///< the upper guess is doubled up to this before giving up
  double tolerance = 1.0;    ///< stop when the bracket is narrower than this [rpm]
  int max_runs = 40;
};

struct ThresholdResult {
  bool found = false;
  double threshold = 0.0;            ///< bracket midpoint [rpm]
  double low = 0.0;                  ///< highest rate seen below the threshold [rpm]
  double high = 0.0;                 ///< lowest rate seen above it [rpm]
  std::vector<ThresholdProbe> runs;  ///< in the order made
  std::string message;               ///< why the search stopped without a threshold
};

/// Throws std::invalid_argument naming the option and its allowed range.
void validate(const ThresholdSearchOptions& options);

/// Finds the rate where `probe(rate).above` switches from false to true: the lower guess is
/// halved while it is above, the upper guess doubled while it is below, then the bracket is
/// bisected until narrower than the tolerance. A failed run stops the search (found = false).
/// `progress` (optional) sees every run as it completes.
ThresholdResult findThreshold(const std::function<ThresholdProbe(double)>& probe,
                              const ThresholdSearchOptions& options,
                              const std::function<void(const ThresholdProbe&)>& progress = {});

/// The lowest rate where the indicator, averaged over three neighbouring rates and interpolated
/// linearly in log rate between them, reaches `level` from below. `probes` are runs at
/// consecutive rates of a geometric grid, in rate order. The average takes out most of a wobble
/// with the rate (docs/model.md 8.4.5); the crossing depends only on the runs around it. NaN if
/// fewer than three probes, a failed one, or no crossing inside (the averaged indicator already at
/// `level` at the second rate, or below it up to the last but one).
double smoothedCrossing(const std::vector<ThresholdProbe>& probes, double level);

/// A threshold from runs on the global rate grid grid_ratio^k rpm (k integer): the 2 half_width
/// + 1 grid rates nearest `center`, and their smoothedCrossing at `level`. When the crossing lies
/// below or above them, the window moves that way by 2 half_width - 2 rates (the runs it shares
/// are reused), at most `max_moves` times. Since the grid does not move with `center`, every
/// window that holds the crossing gives the same threshold, and it moves continuously with the
/// model. The runs stop at the first failed one.
struct WindowThreshold {
  double threshold = std::numeric_limits<double>::quiet_NaN();  ///< [rpm], NaN if not found
  std::vector<ThresholdProbe> runs;                             ///< in the order made
  std::string message;               ///< why there is no threshold
};
WindowThreshold windowThreshold(const std::function<ThresholdProbe(double)>& probe, double center,
                                double grid_ratio, int half_width, double level, int max_moves = 8,
                                const std::function<void(const ThresholdProbe&)>& progress = {});
/// The same with the runs of a window made by one call (they may run in parallel).
using ProbeBatch = std::function<std::vector<ThresholdProbe>(const std::vector<double>& rates)>;
WindowThreshold windowThreshold(const ProbeBatch& probes, double center, double grid_ratio,
                                int half_width, double level, int max_moves = 8,
                                const std::function<void(const ThresholdProbe&)>& progress = {});

}  // namespace flagella
