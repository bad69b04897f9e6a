// The buckling threshold as a loss of stability (docs/model.md 8.4.4): the growth rate sigma of
// the flagellum's slow tilt away from its straight helical state, measured from the log-slope
// of the tilt's envelope while it is still small, and the motor rate where sigma(omega) = 0.
// Pure logic: the runs are a callback.
#pragma once

#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "flagella_sim/core/types.h"

namespace flagella {

/// The slow part of a tilt-vector series. At every sample t whose two-turn window [t - P, t + P]
/// lies inside the series: `mean`, the vector's mean over [t - P/2, t + P/2] (trapezoid rule on
/// the linear interpolant), `amplitude` its norm, and `change` = |mean(t + P/2) - mean(t - P/2)|,
/// how much that mean moves in one turn. A lean that turns with the flagellum (the straight
/// state's own, period P) averages out of `mean`; a lean fixed in space or turning slowly (the
/// buckling mode) stays. `change` also removes a constant remainder (a few tenths of a degree
/// that do not average out exactly), so its log-slope is the mode's growth rate even when the
/// mode is small: for mean = c0 + c1 e^{(sigma + i w) t}, change = |c1| |e^{(sigma + i w) P} - 1|
/// e^{sigma t}. Times must increase, period > 0.
struct AmplitudeSeries {
  std::vector<double> time;
  std::vector<double> amplitude;  ///< |mean| (the slow tilt)
  std::vector<double> change;     ///< |mean(t + P/2) - mean(t - P/2)|
  std::vector<Vec3> mean;
};
AmplitudeSeries slowTiltAmplitude(const std::vector<double>& time,
                                  const std::vector<Vec3>& tilt_vectors, double period);

/// Least-squares slope of ln(change) against time over the samples in [t_from, t_to], with a
/// one-sigma error from the residuals, widened for their lag-one autocorrelation r by
/// sqrt((1 + r)/(1 - r)) (r >= 0 only).
struct LogSlopeFit {
  bool ok = false;
  double slope = 0.0;  ///< [1/s]
  double error = 0.0;  ///< one sigma [1/s]
  double t_from = 0.0, t_to = 0.0;
  int samples = 0;
  std::string message;  ///< why not ok
};
LogSlopeFit fitLogSlope(const AmplitudeSeries& series, double t_from, double t_to);

/// The growth rate a slow-tilt series shows (docs/model.md 8.4.4): the log-slope of `change`
/// from `settle` until the slow tilt (`amplitude`) passes `small_limit` (no longer small) or
/// `change` falls to `decay_limit` times its value at `settle` (numerical remainders would
/// flatten the slope), or the series ends. When either happens before `settle + min_window` the
/// sign is certain but the window too short for a fit: sigma is then the mean log-rate of
/// `change` up to that point, from the first sample (`grew_early`, a lower bound) or from
/// `settle` (`decayed_early`, an upper bound), with no error. Before `settle` the spin-up's fast
/// transients make `change` fall whatever the sign (by up to 3x near the gimbal's threshold), so
/// only a fall below `decayed_before` times its largest value before `settle` counts
/// (`decayed_early`, sigma from that peak): far below the threshold the mode is gone before the
/// window, and what is left is numerical remainder whose slope means nothing.
struct GrowthReading {
  double sigma = 0.0, error = 0.0;  ///< [1/s]
  double from = 0.0, to = 0.0;      ///< the window [s]
  bool grew_early = false, decayed_early = false;
  std::string message;  ///< non-empty: no reading (too few samples)
};
GrowthReading readGrowth(const AmplitudeSeries& slow, double settle, double min_window,
                         double small_limit, double decay_limit, double decayed_before);

/// One run of the threshold search: the rate tried and the growth rate it showed.
struct GrowthProbe {
  double rate = 0.0;         ///< motor rate magnitude [rpm]
  double sigma = 0.0;        ///< growth rate of the slow tilt [1/s]
  double sigma_error = 0.0;  ///< one sigma [1/s]
  double window_from = 0.0;  ///< fit window [s]
  double window_to = 0.0;
  double period = 0.0;        ///< averaging period [s]
  double max_tilt_deg = 0.0;  ///< largest tilt of the run [deg]
  /// The slow tilt passed the small-tilt limit before the fit window began: sigma > 0 for sure,
  /// its value from the rise to that limit (a lower bound).
  bool saturated = false;
  /// The slow tilt had already decayed to decay_limit of its start before the fit window could
  /// hold a turn: sigma < 0 for sure, its value from that fall (an upper bound).
  bool decayed = false;
  double wall_seconds = 0.0;
  bool failed = false;
  std::string error;
  /// |sigma| is at least twice its error: the run is long enough to trust its sign.
  bool trusted() const {
    return !failed && (saturated || decayed || std::abs(sigma) >= 2.0 * sigma_error);
  }
};

struct GrowthThresholdOptions {
  double low = 2.0;          ///< first lower guess [rpm], > 0
  double high = 20.0;        ///< first upper guess [rpm], > low
  double min_rate = 0.05;    ///< the lower guess is halved down to this before giving up
  double max_rate = 2000.0;  ///< the upper guess is doubled up to this before giving up
  double tolerance = 0.01;   ///< stop when the bracket is narrower than this fraction of it
  int max_runs = 14;
};

struct GrowthThreshold {
  bool found = false;
  double threshold = std::numeric_limits<double>::quiet_NaN();    ///< [rpm]
  double uncertainty = std::numeric_limits<double>::quiet_NaN();  ///< one sigma [rpm]
  double low = 0.0, high = 0.0;                                   ///< the final bracket [rpm]
  std::vector<GrowthProbe> runs;                                  ///< in the order made
  std::string message;                                            ///< why there is no threshold
};

/// Throws std::invalid_argument naming the option and its allowed range.
void validate(const GrowthThresholdOptions& options);

/// The rate where sigma changes sign from - to +: the lower guess halved while sigma > 0, the
/// upper doubled while sigma < 0, then the bracket narrowed by TOMS 748 (Boost.Math) on
/// sigma(rate) until narrower than the tolerance. The threshold is the zero of the straight line
/// through the last run on each side, its uncertainty propagated from their sigma errors. A
/// failed run stops the search.
GrowthThreshold findGrowthThreshold(const std::function<GrowthProbe(double)>& probe,
                                    const GrowthThresholdOptions& options,
                                    const std::function<void(const GrowthProbe&)>& progress = {});

}  // namespace flagella
