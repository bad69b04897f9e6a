#include "flagella_identify/diagnosis.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <cstdio>
#include <map>

#include "flagella_sim/core/units.h"
#include "text_format.h"

namespace flagella {
namespace identify {

namespace {

double mean(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / v.size();
}

/// Pearson correlation and its t statistic.
double correlationT(const std::vector<double>& x, const std::vector<double>& y) {
  const size_t n = x.size();
  if (n < 4) return 0.0;
  const double mx = mean(x), my = mean(y);
  double sxy = 0, sxx = 0, syy = 0;
  for (size_t i = 0; i < n; ++i) {
    sxy += (x[i] - mx) * (y[i] - my);
    sxx += (x[i] - mx) * (x[i] - mx);
    syy += (y[i] - my) * (y[i] - my);
  }
  if (sxx <= 0 || syy <= 0) return 0.0;
  const double r = std::clamp(sxy / std::sqrt(sxx * syy), -0.999999, 0.999999);
  return r * std::sqrt((n - 2.0) / (1.0 - r * r));
}

/// y minus its least-squares line in x (to hold x fixed in a correlation).
std::vector<double> residualize(const std::vector<double>& y, const std::vector<double>& x) {
  const double mx = mean(x), my = mean(y);
  double sxx = 0, sxy = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    sxx += (x[i] - mx) * (x[i] - mx);
    sxy += (x[i] - mx) * (y[i] - my);
  }
  const double b = sxx > 0 ? sxy / sxx : 0.0;
  std::vector<double> r(y.size());
  for (size_t i = 0; i < y.size(); ++i) r[i] = y[i] - my - b * (x[i] - mx);
  return r;
}

GroupStats group(const std::string& name, const std::vector<const ResidualPoint*>& pts) {
  GroupStats g;
  g.group = name;
  g.count = static_cast<int>(pts.size());
  double s2 = 0, s1 = 0;
  for (const ResidualPoint* p : pts) {
    s2 += p->z() * p->z();
    s1 += p->z();
  }
  if (g.count > 0) {
    g.rms_z = std::sqrt(s2 / g.count);
    g.mean_z = s1 / g.count;
  }
  return g;
}

/// Largest periodogram peak of a detrended, evenly indexed signal relative to the median power;
/// returns the period in the units of t.
std::pair<double, double> dominantPeriod(const std::vector<double>& t, std::vector<double> y) {
  const size_t n = y.size();
  if (n < 16) return {0.0, 0.0};
  // remove the best line (a drift is reported separately)
  const double mt = mean(t), my = mean(y);
  double stt = 0, sty = 0;
  for (size_t i = 0; i < n; ++i) {
    stt += (t[i] - mt) * (t[i] - mt);
    sty += (t[i] - mt) * (y[i] - my);
  }
  const double slope = stt > 0 ? sty / stt : 0.0;
  for (size_t i = 0; i < n; ++i) y[i] -= my + slope * (t[i] - mt);
  const double span = t.back() - t.front();
  std::vector<double> power;
  std::vector<double> periods;
  for (size_t k = 2; k <= n / 2; ++k) {  // at least two cycles in the window
    const double f = k / span;
    std::complex<double> sum = 0.0;
    for (size_t i = 0; i < n; ++i)
      sum += y[i] * std::polar(1.0, -2.0 * M_PI * f * (t[i] - t.front()));
    power.push_back(std::norm(sum));
    periods.push_back(1.0 / f);
  }
  if (power.empty()) return {0.0, 0.0};
  std::vector<double> sorted = power;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double median = sorted[sorted.size() / 2];
  const size_t best = std::max_element(power.begin(), power.end()) - power.begin();
  return {periods[best], median > 0 ? power[best] / median : 0.0};
}

}  // namespace

std::pair<std::string, double> displayUnit(const std::string& output) {
  if (output == "v") return {"mm/s", 1e3};
  if (output == "omega_h" || output == "omega_t" || output == "buckling_threshold")
    return {"rpm", units::kRpmPerRadPerSec};
  if (output == "omega_yr") return {"rad/s", 1.0};
  if (output == "tilt") return {"deg", units::radToDeg(1.0)};
  if (output == "R_yr" || output == "x" || output == "y" || output == "z") return {"mm", 1e3};
  if (output.rfind("axis_", 0) == 0) return {"", 1.0};
  if (output.find("turns") != std::string::npos) return {"turns", 1.0};
  return {"", 1.0};
}

double noiseZScore(double chi_square, int n) {
  if (n <= 0) return 0.0;
  const double k = static_cast<double>(n);
  const double a = 2.0 / (9.0 * k);
  return (std::cbrt(chi_square / k) - (1.0 - a)) / std::sqrt(a);
}

namespace {

/// The residual points of each output, outputs in order of first appearance.
using OutputPoints = std::pair<std::string, std::vector<const ResidualPoint*>>;

std::vector<OutputPoints> pointsByOutput(const Evaluation& evaluation) {
  std::map<std::string, std::vector<const ResidualPoint*>> by_output;
  std::vector<std::string> order;
  for (const ResidualPoint& p : evaluation.points) {
    if (!by_output.count(p.output)) order.push_back(p.output);
    by_output[p.output].push_back(&p);
  }
  std::vector<OutputPoints> out;
  for (const std::string& name : order) out.emplace_back(name, by_output[name]);
  return out;
}

/// Size of the residual of one output, in z and in display units.
OutputStats outputStats(const std::string& name, const std::vector<const ResidualPoint*>& pts) {
  OutputStats o;
  o.output = name;
  const auto [unit, factor] = displayUnit(name);
  o.unit = unit;
  o.count = static_cast<int>(pts.size());
  double chi = 0, s1 = 0, e2 = 0, e1 = 0;
  for (const ResidualPoint* p : pts) {
    chi += p->z() * p->z();
    s1 += p->z();
    const double e = (p->model - p->data) * factor;
    e2 += e * e;
    e1 += e;
  }
  o.rms_z = std::sqrt(chi / o.count);
  o.mean_z = s1 / o.count;
  o.rms_error = std::sqrt(e2 / o.count);
  o.mean_error = e1 / o.count;
  o.noise_z = noiseZScore(chi, o.count);
  return o;
}

/// bias: the mean error of the output differs from zero.
void diagnoseBias(const OutputStats& o, std::vector<Signature>& signatures) {
  const double bias_z = o.mean_z * std::sqrt(static_cast<double>(o.count));
  if (std::abs(bias_z) > kSignificanceZ)
    signatures.push_back(
        {"bias", o.output, std::abs(bias_z),
         "the model " + std::string(o.mean_z > 0 ? "over" : "under") + "-predicts " + o.output +
             formatted(" by %.3g ", std::abs(o.mean_error)) + o.unit + " on average"});
}

/// asymmetry: the error depends on the sign of rotation.
void diagnoseAsymmetry(const std::string& name, const std::vector<const ResidualPoint*>& pts,
                       std::vector<Signature>& signatures) {
  std::vector<double> zp, zn;
  for (const ResidualPoint* p : pts) (p->omega_T >= 0 ? zp : zn).push_back(p->z());
  if (zp.size() >= 2 && zn.size() >= 2) {
    const double t = (mean(zp) - mean(zn)) / std::sqrt(1.0 / zp.size() + 1.0 / zn.size());
    if (std::abs(t) > kSignificanceZ)
      signatures.push_back({"asymmetry", name, std::abs(t),
                            formatted("the error in " + name +
                                          " depends on the sign of rotation: mean z %+.2f for "
                                          "omega_T > 0, %+.2f for omega_T < 0",
                                      mean(zp), mean(zn))});
  }
}

/// threshold (tables): data at rest where the model moves, only below some speed.
void diagnoseThreshold(const std::string& name, const std::vector<const ResidualPoint*>& pts,
                       std::vector<Signature>& signatures) {
  double max_still = -1.0, min_moving = 1e300;
  int still = 0;
  for (const ResidualPoint* p : pts) {
    if (std::abs(p->data) < 2.0 * p->sigma && std::abs(p->model) > 5.0 * p->sigma) {
      ++still;
      max_still = std::max(max_still, std::abs(p->omega_T));
    } else if (std::abs(p->data) > 5.0 * p->sigma) {
      min_moving = std::min(min_moving, std::abs(p->omega_T));
    }
  }
  if (still >= 2 && max_still < min_moving)
    signatures.push_back(
        {"threshold", name, static_cast<double>(still),
         formatted("%.0f experiments show no " + name +
                       " at |omega_T| <= %.0f rpm where the model predicts motion; it "
                       "resumes from %.0f rpm",
                   still, max_still * units::kRpmPerRadPerSec,
                   min_moving * units::kRpmPerRadPerSec)});
}

/// saturation (tables): the error grows with the motor speed.
void diagnoseSaturation(const std::string& name, const std::vector<double>& speed,
                        const std::vector<double>& z, std::vector<Signature>& signatures) {
  const double t = correlationT(speed, z);
  if (std::abs(t) > kSignificanceZ)
    signatures.push_back({"saturation", name, std::abs(t),
                          "the " + std::string(t > 0 ? "over" : "under") + "-prediction of " +
                              name + " grows with |omega_T|" +
                              formatted(" (correlation t = %.1f)", t)});
}

/// drift and oscillation (series): the error against the run time.
void diagnoseRunTime(const std::string& name, const std::vector<double>& run,
                     const std::vector<double>& z, std::vector<Signature>& signatures) {
  const double t = correlationT(run, z);
  if (std::abs(t) > kSignificanceZ)
    signatures.push_back({"drift", name, std::abs(t),
                          formatted("the error in " + name +
                                        " grows steadily over the run (correlation with run "
                                        "time t = %.1f)",
                                    t)});
  const auto [period, ratio] = dominantPeriod(run, z);
  if (ratio > 30.0)
    signatures.push_back({"oscillation", name, ratio,
                          formatted("the error in " + name +
                                        " oscillates with a period of %.1f s (peak %.0fx the "
                                        "median spectral power)",
                                    period, ratio)});
}

/// drift (tables): the error against the session time, the motor speed held fixed.
void diagnoseSessionDrift(const std::string& name, const std::vector<double>& session,
                          const std::vector<double>& zs, const std::vector<double>& speed_s,
                          std::vector<Signature>& signatures) {
  // partial correlation: the motor speed held fixed (experiments run in random order)
  const double t = correlationT(residualize(session, speed_s), residualize(zs, speed_s));
  if (std::abs(t) > kSignificanceZ)
    signatures.push_back({"drift", name, std::abs(t),
                          formatted("the error in " + name +
                                        " changes with the session time of the experiment, "
                                        "at equal motor speed (partial correlation t = %.1f)",
                                    t)});
}

/// The signatures of one output whose residual exceeds the noise, in the order bias,
/// asymmetry, then threshold and saturation (tables) or drift and oscillation (series), then
/// session drift (tables).
void diagnoseOutput(const OutputStats& o, const std::vector<const ResidualPoint*>& pts,
                    std::vector<Signature>& signatures) {
  const std::string& name = o.output;
  diagnoseBias(o, signatures);
  diagnoseAsymmetry(name, pts, signatures);
  // trend with motor speed (tables): saturation or threshold
  std::vector<double> speed, z, session, run, zs, speed_s;
  for (const ResidualPoint* p : pts) {
    speed.push_back(std::abs(p->omega_T));
    z.push_back(p->z());
    if (std::isfinite(p->session_time)) {
      session.push_back(p->session_time);
      zs.push_back(p->z());
      speed_s.push_back(std::abs(p->omega_T));
    }
    run.push_back(p->run_time);
  }
  if (!pts.front()->from_series) {
    diagnoseThreshold(name, pts, signatures);
    diagnoseSaturation(name, speed, z, signatures);
  } else {
    diagnoseRunTime(name, run, z, signatures);
  }
  if (zs.size() >= 4 && !pts.front()->from_series)
    diagnoseSessionDrift(name, session, zs, speed_s, signatures);
}

/// intermittency in a series: stretches where the tracked head is still but the model moves.
void diagnoseIntermittency(const Evaluation& evaluation, const MeasuredData& data,
                           std::vector<Signature>& signatures) {
  for (size_t si = 0; si < data.series.size(); ++si) {
    const TimeSeries& s = data.series[si];
    std::map<int, std::pair<Vec3, Vec3>> samples;  // row -> (data, model) positions
    for (const ResidualPoint& p : evaluation.points) {
      if (!p.from_series || p.source != static_cast<int>(si)) continue;
      const int axis = p.output == "x" ? 0 : p.output == "y" ? 1 : p.output == "z" ? 2 : -1;
      if (axis < 0) continue;
      samples[p.row].first(axis) = p.data;
      samples[p.row].second(axis) = p.model;
    }
    if (samples.size() < 12) continue;
    std::vector<double> data_speed, model_speed;
    auto prev = samples.begin();
    for (auto it = std::next(samples.begin()); it != samples.end(); prev = it, ++it) {
      const double dt = s.t[it->first] - s.t[prev->first];
      data_speed.push_back((it->second.first - prev->second.first).norm() / dt);
      model_speed.push_back((it->second.second - prev->second.second).norm() / dt);
    }
    const double noise_speed = 2.0 * s.position_noise /
                               (s.t[samples.rbegin()->first] - s.t[samples.begin()->first]) *
                               samples.size();
    int stopped = 0, moving_model = 0;
    for (size_t i = 0; i < data_speed.size(); ++i) {
      if (model_speed[i] < 3.0 * noise_speed) continue;
      ++moving_model;
      if (data_speed[i] < 0.25 * model_speed[i]) ++stopped;
    }
    if (moving_model >= 10 && stopped >= 3 && stopped < moving_model * 0.8)
      signatures.push_back(
          {"intermittency", "position", static_cast<double>(stopped),
           formatted(
               "in %.0f of %.0f intervals the head nearly stops (speed below a quarter of the "
               "model's) and then moves on",
               stopped, moving_model)});
  }
}

/// where: the residual by motor-speed range, sign of rotation and part of the run (empty
/// groups left out).
std::vector<GroupStats> diagnoseWhere(const Evaluation& evaluation) {
  std::vector<GroupStats> where;
  std::vector<const ResidualPoint*> all;
  for (const ResidualPoint& p : evaluation.points) all.push_back(&p);
  if (all.empty()) return where;
  std::vector<double> speeds;
  for (const ResidualPoint* p : all) speeds.push_back(std::abs(p->omega_T));
  std::sort(speeds.begin(), speeds.end());
  const double lo = speeds[speeds.size() / 3], hi = speeds[2 * speeds.size() / 3];
  std::vector<const ResidualPoint*> g[3], sign[2], part[3];
  double t_max = 0;
  for (const ResidualPoint* p : all) t_max = std::max(t_max, p->run_time);
  for (const ResidualPoint* p : all) {
    const double w = std::abs(p->omega_T);
    g[w < lo ? 0 : w < hi ? 1 : 2].push_back(p);
    sign[p->omega_T >= 0 ? 0 : 1].push_back(p);
    if (p->from_series)
      part[std::min(2, static_cast<int>(3.0 * p->run_time / (t_max + 1e-9)))].push_back(p);
  }
  const double rpm = units::kRpmPerRadPerSec;
  where.push_back(group(formatted("|omega_T| < %.0f rpm", lo * rpm), g[0]));
  where.push_back(group(formatted("|omega_T| %.0f-%.0f rpm", lo * rpm, hi * rpm), g[1]));
  where.push_back(group(formatted("|omega_T| >= %.0f rpm", hi * rpm), g[2]));
  where.push_back(group("omega_T >= 0", sign[0]));
  where.push_back(group("omega_T < 0", sign[1]));
  for (int k = 0; k < 3; ++k)
    if (!part[k].empty())
      where.push_back(
          group(formatted("run time %.0f-%.0f s", k * t_max / 3, (k + 1) * t_max / 3), part[k]));
  where.erase(
      std::remove_if(where.begin(), where.end(), [](const GroupStats& s) { return s.count == 0; }),
      where.end());
  return where;
}

}  // namespace

Diagnosis diagnose(const Evaluation& evaluation, const MeasuredData& data) {
  Diagnosis d;
  d.count = static_cast<int>(evaluation.points.size());
  d.chi_square = chiSquare(evaluation);
  d.rms_z = d.count ? std::sqrt(d.chi_square / d.count) : 0.0;
  d.noise_z = noiseZScore(d.chi_square, d.count);
  d.significant = d.noise_z > kSignificanceZ;
  for (const auto& [name, pts] : pointsByOutput(evaluation)) {
    d.outputs.push_back(outputStats(name, pts));
    if (d.outputs.back().noise_z > kSignificanceZ)
      diagnoseOutput(d.outputs.back(), pts, d.signatures);
  }
  diagnoseIntermittency(evaluation, data, d.signatures);
  d.where = diagnoseWhere(evaluation);
  return d;
}

}  // namespace identify
}  // namespace flagella
