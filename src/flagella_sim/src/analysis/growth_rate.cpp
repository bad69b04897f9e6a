#include "flagella_sim/analysis/growth_rate.h"

#include <algorithm>
#include <boost/math/tools/toms748_solve.hpp>
#include <cmath>
#include <stdexcept>

namespace flagella {

namespace {

// Integral from time[0] to t of the piecewise-linear interpolant of `values`, at every t.
class RunningIntegral {
 public:
  RunningIntegral(const std::vector<double>& time, const std::vector<Vec3>& values)
      : time_(time), values_(values), cumulative_(time.size(), Vec3::Zero()) {
    for (size_t k = 1; k < time.size(); ++k)
      cumulative_[k] =
          cumulative_[k - 1] + 0.5 * (time[k] - time[k - 1]) * (values[k] + values[k - 1]);
  }
  Vec3 at(double t) const {
    const size_t k = std::min<size_t>(
        std::upper_bound(time_.begin(), time_.end(), t) - time_.begin() - 1, time_.size() - 2);
    const double h = time_[k + 1] - time_[k], s = t - time_[k];
    const Vec3 v = values_[k] + (s / h) * (values_[k + 1] - values_[k]);
    return cumulative_[k] + 0.5 * s * (values_[k] + v);
  }

 private:
  const std::vector<double>& time_;
  const std::vector<Vec3>& values_;
  std::vector<Vec3> cumulative_;
};

// The zero of the line through (a, sa) and (b, sb), sa < 0 < sb, with its one-sigma error from
// the errors ea, eb of sa, sb.
std::pair<double, double> interpolatedZero(double a, double sa, double ea, double b, double sb,
                                           double eb) {
  const double d = sb - sa;
  const double zero = a - sa * (b - a) / d;
  const double error = (b - a) / (d * d) * std::hypot(sb * ea, sa * eb);
  return {zero, error};
}

struct FailedRun {
  std::string error;
};

}  // namespace

AmplitudeSeries slowTiltAmplitude(const std::vector<double>& time,
                                  const std::vector<Vec3>& tilt_vectors, double period) {
  if (time.size() != tilt_vectors.size())
    throw std::invalid_argument("slowTiltAmplitude: times and vectors differ in number");
  if (!(period > 0.0)) throw std::invalid_argument("slowTiltAmplitude: period must be > 0");
  AmplitudeSeries out;
  if (time.size() < 2) return out;
  const RunningIntegral integral(time, tilt_vectors);
  for (double t : time) {
    if (t - period < time.front() || t + period > time.back()) continue;
    const Vec3 before = integral.at(t - period), at = integral.at(t),
               after = integral.at(t + period);
    const double half = 0.5 * period;
    out.time.push_back(t);
    out.mean.push_back((integral.at(t + half) - integral.at(t - half)) / period);
    out.amplitude.push_back(out.mean.back().norm());
    out.change.push_back(((after - at) - (at - before)).norm() / period);  // docs/model.md 8.4.4
  }
  return out;
}

LogSlopeFit fitLogSlope(const AmplitudeSeries& series, double t_from, double t_to) {
  LogSlopeFit fit;
  std::vector<double> t, y;
  for (size_t k = 0; k < series.time.size(); ++k)
    if (series.time[k] >= t_from && series.time[k] <= t_to && series.change[k] > 0.0) {
      t.push_back(series.time[k]);
      y.push_back(std::log(series.change[k]));
    }
  fit.samples = static_cast<int>(t.size());
  if (t.size() < 4) {
    fit.message = "fewer than 4 samples in the fit window";
    return fit;
  }
  fit.t_from = t.front();
  fit.t_to = t.back();
  const double n = static_cast<double>(t.size());
  double tm = 0.0, ym = 0.0;
  for (size_t k = 0; k < t.size(); ++k) tm += t[k] / n, ym += y[k] / n;
  double stt = 0.0, sty = 0.0;
  for (size_t k = 0; k < t.size(); ++k) {
    stt += (t[k] - tm) * (t[k] - tm);
    sty += (t[k] - tm) * (y[k] - ym);
  }
  fit.slope = sty / stt;
  std::vector<double> r(t.size());
  double rss = 0.0;
  for (size_t k = 0; k < t.size(); ++k) {
    r[k] = y[k] - ym - fit.slope * (t[k] - tm);
    rss += r[k] * r[k];
  }
  double lag = 0.0;
  for (size_t k = 1; k < r.size(); ++k) lag += r[k] * r[k - 1];
  const double rho = rss > 0.0 ? std::clamp(lag / rss, 0.0, 0.99) : 0.0;
  fit.error = std::sqrt(rss / (n - 2.0) / stt) * std::sqrt((1.0 + rho) / (1.0 - rho));
  fit.ok = true;
  return fit;
}

GrowthReading readGrowth(const AmplitudeSeries& slow, double settle, double min_window,
                         double small_limit, double decay_limit, double decayed_before) {
  GrowthReading r;
  if (slow.time.size() < 2) {
    r.message = "the run is shorter than two turns of the flagellum";
    return r;
  }
  double floor = 0.0;                 // set at the window's start
  size_t k = 0, start = 0, peak = 0;  // peak: largest change before the window
  for (; k < slow.time.size(); ++k) {
    const double t = slow.time[k], c = slow.change[k];
    const bool early = t < settle + min_window;
    if (slow.amplitude[k] > small_limit) {
      r.grew_early = early;
      break;
    }
    if (t < settle && c > slow.change[peak]) peak = k;
    if (t >= settle && floor == 0.0) {
      floor = decay_limit * c, start = k;
      if (c < decayed_before * slow.change[peak]) {  // gone before the window
        r.decayed_early = true;
        start = peak;
        break;
      }
    }
    if (c < floor) {
      r.decayed_early = early;
      break;
    }
  }
  const size_t last = std::min(k, slow.time.size() - 1);
  r.to = slow.time[last];
  if (r.grew_early || r.decayed_early) {  // the sign is certain, the slope a bound
    if (r.grew_early) start = 0;          // from the first sample: the window may not have begun
    r.from = slow.time[start];
    const double c0 = slow.change[start], c_end = slow.change[last];
    r.sigma =
        r.to > r.from && c0 > 0.0 && c_end > 0.0 ? std::log(c_end / c0) / (r.to - r.from) : 0.0;
    if (r.grew_early) r.sigma = std::max(r.sigma, 1e-12);
    if (r.decayed_early) r.sigma = std::min(r.sigma, -1e-12);
    return r;
  }
  const LogSlopeFit fit = fitLogSlope(slow, settle, r.to);
  if (!fit.ok) {
    r.message = fit.message;
    return r;
  }
  r.sigma = fit.slope;
  r.error = fit.error;
  r.from = fit.t_from;
  r.to = fit.t_to;
  return r;
}

void validate(const GrowthThresholdOptions& o) {
  auto require = [](bool ok, const std::string& what) {
    if (!ok) throw std::invalid_argument(what);
  };
  require(o.low > 0.0 && std::isfinite(o.low), "--low must be > 0 rpm");
  require(o.high > o.low && std::isfinite(o.high), "--high must be > --low");
  require(o.min_rate > 0.0 && o.min_rate <= o.low, "--min-rpm must be in (0, --low]");
  require(o.max_rate >= o.high, "--max-rpm must be >= --high");
  require(o.tolerance > 0.0 && o.tolerance < 0.5, "--tolerance must be in (0, 0.5) (relative)");
  require(o.max_runs >= 2 && o.max_runs <= 200, "--max-runs must be in [2, 200]");
}

GrowthThreshold findGrowthThreshold(const std::function<GrowthProbe(double)>& probe,
                                    const GrowthThresholdOptions& o,
                                    const std::function<void(const GrowthProbe&)>& progress) {
  validate(o);
  GrowthThreshold result;
  auto sigmaAt = [&](double rate) {
    for (const GrowthProbe& made : result.runs)  // TOMS 748 may ask for a rate twice
      if (std::abs(made.rate - rate) <= 1e-9 * rate) return made.sigma;
    if (static_cast<int>(result.runs.size()) >= o.max_runs)
      throw FailedRun{"no threshold within " + std::to_string(o.max_runs) + " runs"};
    GrowthProbe p = probe(rate);
    p.rate = rate;
    result.runs.push_back(p);
    if (progress) progress(p);
    if (p.failed) throw FailedRun{"run at " + std::to_string(rate) + " rpm failed: " + p.error};
    return p.sigma;
  };
  try {
    double a = o.low, b = o.high;
    double sa = sigmaAt(a);
    while (sa > 0.0) {  // unstable already: halve the lower guess
      if (a / 2.0 < o.min_rate) throw FailedRun{"growing already at the lowest rate tried"};
      b = a;
      a /= 2.0;
      sa = sigmaAt(a);
    }
    double sb = sigmaAt(b);
    while (sb < 0.0) {  // stable still: double the upper guess
      if (b * 2.0 > o.max_rate) throw FailedRun{"decaying still at the highest rate tried"};
      a = b, sa = sb;
      b *= 2.0;
      sb = sigmaAt(b);
    }
    boost::uintmax_t iterations = static_cast<boost::uintmax_t>(o.max_runs);
    const double tolerance = o.tolerance;
    boost::math::tools::toms748_solve(
        sigmaAt, a, b, sa, sb,
        [tolerance](double lo, double hi) { return hi - lo <= tolerance * lo; }, iterations);
  } catch (const FailedRun& f) {
    result.message = f.error;
    return result;
  }
  // The last run on each side of the zero (the narrowest bracket the runs give).
  const GrowthProbe* below = nullptr;
  const GrowthProbe* above = nullptr;
  for (const GrowthProbe& p : result.runs) {
    if (p.sigma <= 0.0 && (!below || p.rate > below->rate)) below = &p;
    if (p.sigma > 0.0 && (!above || p.rate < above->rate)) above = &p;
  }
  if (!below || !above || below->rate >= above->rate) {
    result.message = "sigma does not change sign once between the rates tried (not monotone)";
    return result;
  }
  const auto [zero, error] = interpolatedZero(below->rate, below->sigma, below->sigma_error,
                                              above->rate, above->sigma, above->sigma_error);
  result.found = true;
  result.threshold = zero;
  result.uncertainty = error;
  result.low = below->rate;
  result.high = above->rate;
  return result;
}

}  // namespace flagella
