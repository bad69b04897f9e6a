#include "series_features.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <vector>

#include "interpolate.h"

namespace flagella {
namespace identify {

namespace {

/// Least-squares slope of y(t), and 1 / sqrt(sum (t - mean t)^2): the slope's standard error
/// per unit noise of y.
std::pair<double, double> slopeOf(const std::vector<double>& t, const std::vector<double>& y) {
  const size_t n = t.size();
  double tm = 0.0, ym = 0.0;
  for (size_t i = 0; i < n; ++i) {
    tm += t[i] / n;
    ym += y[i] / n;
  }
  double stt = 0.0, sty = 0.0;
  for (size_t i = 0; i < n; ++i) {
    stt += (t[i] - tm) * (t[i] - tm);
    sty += (t[i] - tm) * (y[i] - ym);
  }
  return {sty / stt, 1.0 / std::sqrt(stt)};
}

/// Angles made continuous (no 2 pi jumps between neighbours).
void unwrap(std::vector<double>& angle) {
  for (size_t i = 1; i < angle.size(); ++i)
    angle[i] -= 2.0 * M_PI * std::round((angle[i] - angle[i - 1]) / (2.0 * M_PI));
}

/// Sample index ranges [first, last) of constant command within [t0, t1), their transient
/// share removed, at least kFeatureMinStretch long.
std::vector<std::pair<size_t, size_t>> stretches(const TimeSeries& s, double t0, double t1) {
  std::vector<std::pair<size_t, size_t>> out;
  size_t i = 0;
  while (i < s.t.size()) {
    if (s.t[i] < t0 || s.t[i] >= t1) {
      ++i;
      continue;
    }
    size_t j = i;
    while (j < s.t.size() && s.t[j] < t1 && s.omega_cmd[j] == s.omega_cmd[i]) ++j;
    const double start = s.t[i] + kFeatureSettleShare * (s.t[j - 1] - s.t[i]);
    size_t a = i;
    while (a < j && s.t[a] < start) ++a;
    if (j - a >= 3 && s.t[j - 1] - s.t[a] >= kFeatureMinStretch) out.emplace_back(a, j);
    i = j;
  }
  return out;
}

// The horizontal plane (e1, e2) normal to the world vertical (docs/model.md 7.6).
struct HorizontalPlane {
  Vec3 e1, e2;
  explicit HorizontalPlane(const Vec3& up) {
    const Vec3 u = up.normalized();
    e1 = (std::abs(u.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(u).normalized();
    e2 = u.cross(e1);
  }
  // Components of v in the plane.
  Eigen::Vector2d of(const Vec3& v) const { return Eigen::Vector2d(v.dot(e1), v.dot(e2)); }
};

// Simulated head position at time t (linear interpolation of the trace).
Vec3 modelPosition(const SeriesTrace& trace, double t) {
  return interpolateAt(trace.t, t, [&](size_t k) { return trace.position[k]; });
}

// Residual fields shared by every feature of the stretch starting at sample a.
ResidualPoint stretchBase(const TimeSeries& s, int source, size_t a) {
  ResidualPoint base;
  base.from_series = true;
  base.source = source;
  base.row = static_cast<int>(a);
  base.omega_T = s.omega_cmd[a];
  base.session_time = s.session_time + s.t[a];
  base.run_time = s.t[a];
  return base;
}

// Appends one residual point: `base` with the output name, data, model and sigma set.
void pushResidual(Evaluation& out, const ResidualPoint& base, const char* output, double data,
                  double model, double sigma) {
  ResidualPoint p = base;
  p.output = output;
  p.data = data;
  p.model = model;
  p.sigma = sigma;
  out.points.push_back(p);
}

// Windows of >= kFeatureWindow: midpoints, data and model speeds and headings, data chord sum.
struct FeatureWindows {
  std::vector<double> mid, speed_data, speed_model, heading_data, heading_model;
  double mean_chord = 0.0;
};

// The feature windows of samples [a, b).
FeatureWindows featureWindows(const TimeSeries& s, const SeriesTrace& trace,
                              const HorizontalPlane& plane, size_t a, size_t b) {
  FeatureWindows w;
  for (size_t i = a, j = a; i < b; i = j) {
    while (j < b && s.t[j] - s.t[i] < kFeatureWindow) ++j;
    if (j >= b) break;
    const double dt = s.t[j] - s.t[i];
    const Eigen::Vector2d d = plane.of(s.position[j] - s.position[i]);
    const Eigen::Vector2d m = plane.of(modelPosition(trace, s.t[j]) - modelPosition(trace, s.t[i]));
    w.mid.push_back(0.5 * (s.t[i] + s.t[j]));
    w.speed_data.push_back(d.norm() / dt);
    w.speed_model.push_back(m.norm() / dt);
    w.heading_data.push_back(std::atan2(d.y(), d.x()));
    w.heading_model.push_back(std::atan2(m.y(), m.x()));
    w.mean_chord += d.norm();
  }
  return w;
}

// The "speed" residual of stretch [a, b) from >= 2 windows (w.mean_chord: sum -> mean).
void pushSpeed(const TimeSeries& s, size_t a, size_t b, FeatureWindows& w,
               const ResidualPoint& base, Evaluation& out) {
  const size_t windows = w.mid.size();
  if (windows >= 2) {
    w.mean_chord /= windows;
    double vd = 0.0, vm = 0.0, dt = 0.0;
    for (size_t k = 0; k < windows; ++k) {
      vd += w.speed_data[k] / windows;
      vm += w.speed_model[k] / windows;
    }
    dt = (s.t[b - 1] - s.t[a]) / windows;
    // the windows' chord noise sqrt(2) sigma_p, averaged; at least 2 % (its bias from noise)
    pushResidual(out, base, "speed", vd, vm,
                 std::max(std::sqrt(2.0) * s.position_noise / dt / std::sqrt(windows), 0.02 * vd));
  }
}

// The "yaw_rate" residual: slope of the head axis's heading if measured, else the windows'.
void pushYawRate(const TimeSeries& s, const SeriesTrace& trace, const HorizontalPlane& plane,
                 size_t a, size_t b, const FeatureWindows& w, const ResidualPoint& base,
                 Evaluation& out) {
  const size_t windows = w.mid.size();
  std::vector<double> times, yaw_data, yaw_model;
  double heading_noise = 0.0;
  if (!s.orientation.empty()) {
    for (size_t i = a; i < b; ++i) {
      const Eigen::Vector2d d = plane.of(s.orientation[i] * Vec3::UnitZ());
      const Eigen::Vector2d m =
          plane.of(interpolateAt(trace.t, s.t[i], [&](size_t k) { return trace.axis[k]; }));
      if (d.norm() < 0.5 || m.norm() < 0.5) continue;  // axis far from horizontal
      times.push_back(s.t[i]);
      yaw_data.push_back(std::atan2(d.y(), d.x()));
      yaw_model.push_back(std::atan2(m.y(), m.x()));
    }
    heading_noise = s.orientation_noise;
  } else if (windows >= 3 && w.mean_chord > 0.0) {
    times = w.mid;
    yaw_data = w.heading_data;
    yaw_model = w.heading_model;
    heading_noise = std::sqrt(2.0) * s.position_noise / w.mean_chord;
  }
  if (times.size() >= 3) {
    unwrap(yaw_data);
    unwrap(yaw_model);
    const auto [rate_data, per_noise] = slopeOf(times, yaw_data);
    pushResidual(out, base, "yaw_rate", rate_data, slopeOf(times, yaw_model).first,
                 heading_noise * per_noise);
  }
}

// The "head_rate" and "tail_rate" residuals from counted turns, where counted.
void pushTurnRates(const TimeSeries& s, const SeriesTrace& trace, size_t a, size_t b,
                   const ResidualPoint& base, Evaluation& out) {
  const std::vector<double>* counted[2] = {&s.head_turns, &s.tail_turns};
  const std::vector<double>* simulated[2] = {&trace.head_turns, &trace.tail_turns};
  static const char* kNames[2] = {"head_rate", "tail_rate"};
  for (int k = 0; k < 2; ++k) {
    if (counted[k]->empty()) continue;
    std::vector<double> t, d, m;
    for (size_t i = a; i < b; ++i) {
      t.push_back(s.t[i]);
      d.push_back((*counted[k])[i]);
      m.push_back(interpolateAt(trace.t, s.t[i], [&](size_t j) { return (*simulated[k])[j]; }));
    }
    const auto [rate_data, per_noise] = slopeOf(t, d);
    pushResidual(out, base, kNames[k], rate_data, slopeOf(t, m).first, s.turns_noise * per_noise);
  }
}

}  // namespace

void appendFeatureResiduals(const TimeSeries& s, int source, double t0, double t1,
                            const SeriesTrace& trace, const Vec3& up, Evaluation& out) {
  // docs/model.md 7.6: the horizontal plane (e1, e2) normal to the world vertical
  const HorizontalPlane plane(up);
  for (const auto& [a, b] : stretches(s, t0, t1)) {
    const ResidualPoint base = stretchBase(s, source, a);
    // Windows of at least kFeatureWindow: displacement of data and model.
    FeatureWindows windows = featureWindows(s, trace, plane, a, b);
    pushSpeed(s, a, b, windows, base, out);
    // Yaw rate: the heading of the head axis if measured, else of the window displacements.
    pushYawRate(s, trace, plane, a, b, windows, base, out);
    // Turn rates from counted turns.
    pushTurnRates(s, trace, a, b, base, out);
  }
}

}  // namespace identify
}  // namespace flagella
