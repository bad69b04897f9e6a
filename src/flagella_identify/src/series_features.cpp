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

}  // namespace

void appendFeatureResiduals(const TimeSeries& s, int source, double t0, double t1,
                            const SeriesTrace& trace, const Vec3& up, Evaluation& out) {
  // docs/model.md 7.6: the horizontal plane (e1, e2) normal to the world vertical
  const Vec3 u = up.normalized();
  const Vec3 e1 = (std::abs(u.x()) < 0.9 ? Vec3::UnitX() : Vec3::UnitY()).cross(u).normalized();
  const Vec3 e2 = u.cross(e1);
  const auto horizontal = [&](const Vec3& v) { return Eigen::Vector2d(v.dot(e1), v.dot(e2)); };
  const auto model_position = [&](double t) {
    return interpolateAt(trace.t, t, [&](size_t k) { return trace.position[k]; });
  };
  for (const auto& [a, b] : stretches(s, t0, t1)) {
    ResidualPoint base;
    base.from_series = true;
    base.source = source;
    base.row = static_cast<int>(a);
    base.omega_T = s.omega_cmd[a];
    base.session_time = s.session_time + s.t[a];
    base.run_time = s.t[a];
    const auto push = [&](const char* output, double data, double model, double sigma) {
      ResidualPoint p = base;
      p.output = output;
      p.data = data;
      p.model = model;
      p.sigma = sigma;
      out.points.push_back(p);
    };
    // Windows of at least kFeatureWindow: displacement of data and model.
    std::vector<double> mid, speed_data, speed_model, heading_data, heading_model;
    double mean_chord = 0.0;
    for (size_t i = a, j = a; i < b; i = j) {
      while (j < b && s.t[j] - s.t[i] < kFeatureWindow) ++j;
      if (j >= b) break;
      const double dt = s.t[j] - s.t[i];
      const Eigen::Vector2d d = horizontal(s.position[j] - s.position[i]);
      const Eigen::Vector2d m = horizontal(model_position(s.t[j]) - model_position(s.t[i]));
      mid.push_back(0.5 * (s.t[i] + s.t[j]));
      speed_data.push_back(d.norm() / dt);
      speed_model.push_back(m.norm() / dt);
      heading_data.push_back(std::atan2(d.y(), d.x()));
      heading_model.push_back(std::atan2(m.y(), m.x()));
      mean_chord += d.norm();
    }
    const size_t windows = mid.size();
    if (windows >= 2) {
      mean_chord /= windows;
      double vd = 0.0, vm = 0.0, dt = 0.0;
      for (size_t k = 0; k < windows; ++k) {
        vd += speed_data[k] / windows;
        vm += speed_model[k] / windows;
      }
      dt = (s.t[b - 1] - s.t[a]) / windows;
      // the windows' chord noise sqrt(2) sigma_p, averaged; at least 2 % (its bias from noise)
      push("speed", vd, vm,
           std::max(std::sqrt(2.0) * s.position_noise / dt / std::sqrt(windows), 0.02 * vd));
    }
    // Yaw rate: the heading of the head axis if measured, else of the window displacements.
    std::vector<double> times, yaw_data, yaw_model;
    double heading_noise = 0.0;
    if (!s.orientation.empty()) {
      for (size_t i = a; i < b; ++i) {
        const Eigen::Vector2d d = horizontal(s.orientation[i] * Vec3::UnitZ());
        const Eigen::Vector2d m =
            horizontal(interpolateAt(trace.t, s.t[i], [&](size_t k) { return trace.axis[k]; }));
        if (d.norm() < 0.5 || m.norm() < 0.5) continue;  // axis far from horizontal
        times.push_back(s.t[i]);
        yaw_data.push_back(std::atan2(d.y(), d.x()));
        yaw_model.push_back(std::atan2(m.y(), m.x()));
      }
      heading_noise = s.orientation_noise;
    } else if (windows >= 3 && mean_chord > 0.0) {
      times = mid;
      yaw_data = heading_data;
      yaw_model = heading_model;
      heading_noise = std::sqrt(2.0) * s.position_noise / mean_chord;
    }
    if (times.size() >= 3) {
      unwrap(yaw_data);
      unwrap(yaw_model);
      const auto [rate_data, per_noise] = slopeOf(times, yaw_data);
      push("yaw_rate", rate_data, slopeOf(times, yaw_model).first, heading_noise * per_noise);
    }
    // Turn rates from counted turns.
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
      push(kNames[k], rate_data, slopeOf(t, m).first, s.turns_noise * per_noise);
    }
  }
}

}  // namespace identify
}  // namespace flagella
