#include "growth_report.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <stdexcept>

#include "flagella_sim/runtime/exact_json.h"

namespace flagella::cli {

namespace {

// The run length after which a run's sign is trusted (|sigma| >= 2 error), if its window's error
// falls as window^-3/2 (a straight-line slope): window * (2 error / |sigma|)^(2/3).
double trustedAfter(const GrowthProbe& p) {
  if (p.saturated || p.decayed || p.failed || p.sigma == 0.0) return p.window_to;
  const double window = p.window_to - p.window_from;
  return p.window_from + window * std::pow(2.0 * p.sigma_error / std::abs(p.sigma), 2.0 / 3.0);
}

}  // namespace

nlohmann::ordered_json finiteOrNull(double x) {
  return std::isfinite(x) ? nlohmann::ordered_json(x) : nlohmann::ordered_json(nullptr);
}

std::string growthDefinition(const GrowthProbeOptions& o) {
  char text[512];
  std::snprintf(text, sizeof text,
                "the motor rate where the growth rate sigma of the flagellum's slow tilt changes "
                "sign; sigma is the log-slope of the tilt vector averaged over one turn of the "
                "flagellum, fitted from %.4g turns of the flagellum until it passes %.4g deg, in "
                "runs of %.4g turns from the straight helix",
                o.settle_turns, o.small_tilt_deg, o.observe_turns);
  return text;
}

std::string growthRunLine(const GrowthProbe& p) {
  char line[320];
  if (p.failed)
    std::snprintf(line, sizeof line, "%8.3f rpm: FAILED (%s)", p.rate, p.error.c_str());
  else if (p.decayed)
    std::snprintf(line, sizeof line,
                  "%8.3f rpm: sigma <= %+.4f 1/s (slow tilt down to a quarter by %.1f s) -> "
                  "decaying; max tilt %.1f deg (%.1f s)",
                  p.rate, p.sigma, p.window_to, p.max_tilt_deg, p.wall_seconds);
  else if (p.saturated)
    std::snprintf(line, sizeof line,
                  "%8.3f rpm: sigma >= %+.4f 1/s (slow tilt past the small-tilt limit at %.1f s) "
                  "-> growing; max tilt %.1f deg (%.1f s)",
                  p.rate, p.sigma, p.window_to, p.max_tilt_deg, p.wall_seconds);
  else
    std::snprintf(line, sizeof line,
                  "%8.3f rpm: sigma %+.4f +- %.4f 1/s over %.0f-%.0f s -> %s%s; max tilt %.1f deg "
                  "(%.1f s)",
                  p.rate, p.sigma, p.sigma_error, p.window_from, p.window_to,
                  p.sigma > 0.0 ? "growing" : "decaying",
                  p.trusted() ? "" : " (NOT trusted: |sigma| < 2 error, observe longer)",
                  p.max_tilt_deg, p.wall_seconds);
  return line;
}

nlohmann::ordered_json growthJson(const GrowthThreshold& g, const GrowthProbeOptions& o) {
  nlohmann::ordered_json j;
  j["found"] = g.found;
  j["buckling_threshold_rpm"] = finiteOrNull(g.threshold);
  j["uncertainty_rpm"] = finiteOrNull(g.uncertainty);
  j["bracket_rpm"] = g.found ? nlohmann::ordered_json({g.low, g.high}) : nullptr;
  if (!g.found) j["message"] = g.message;
  nlohmann::ordered_json rule;
  rule["definition"] = growthDefinition(o);
  rule["observe_turns"] = o.observe_turns;
  rule["settle_turns"] = o.settle_turns;
  rule["small_tilt_deg"] = o.small_tilt_deg;
  j["criterion"] = rule;
  nlohmann::ordered_json runs = nlohmann::ordered_json::array();
  for (const GrowthProbe& p : g.runs) {
    nlohmann::ordered_json r;
    r["omega_rpm"] = p.rate;
    r["sigma_per_s"] = finiteOrNull(p.sigma);
    r["sigma_error_per_s"] = finiteOrNull(p.sigma_error);
    r["window_s"] = {p.window_from, p.window_to};
    r["turn_period_s"] = p.period;
    r["saturated"] = p.saturated;
    r["decayed"] = p.decayed;
    r["trusted"] = p.trusted();
    r["trusted_after_s"] = finiteOrNull(trustedAfter(p));
    r["max_tilt_deg"] = p.max_tilt_deg;
    r["wall_s"] = p.wall_seconds;
    r["failed"] = p.failed;
    r["error"] = p.error;
    runs.push_back(r);
  }
  j["runs"] = runs;
  return j;
}

void writeGrowthCsv(const std::string& path, const GrowthThreshold& g) {
  std::ofstream csv(path);
  csv << "omega_rpm,sigma_per_s,sigma_error_per_s,saturated,decayed,trusted,threshold_rpm,"
         "threshold_error_rpm\n";
  for (const GrowthProbe& p : g.runs) {
    if (p.failed) continue;
    csv << p.rate << "," << p.sigma << "," << p.sigma_error << "," << p.saturated << ","
        << p.decayed << "," << p.trusted() << "," << (g.found ? std::to_string(g.threshold) : "")
        << "," << (g.found ? std::to_string(g.uncertainty) : "") << "\n";
  }
  if (!csv) throw std::runtime_error("cannot write " + path);
}

nlohmann::json encodeGrowth(const GrowthThreshold& g) {
  nlohmann::json runs = nlohmann::json::array();
  for (const GrowthProbe& p : g.runs)
    runs.push_back({exactJson(p.rate), exactJson(p.sigma), exactJson(p.sigma_error),
                    exactJson(p.window_from), exactJson(p.window_to), exactJson(p.period),
                    exactJson(p.max_tilt_deg), p.saturated, exactJson(p.wall_seconds), p.failed,
                    p.error, p.decayed});
  return {{"found", g.found},
          {"threshold", exactJson(g.threshold)},
          {"uncertainty", exactJson(g.uncertainty)},
          {"low", exactJson(g.low)},
          {"high", exactJson(g.high)},
          {"runs", runs},
          {"message", g.message}};
}

GrowthThreshold decodeGrowth(const nlohmann::json& j) {
  GrowthThreshold g;
  g.found = j.at("found").get<bool>();
  g.threshold = exactNumber(j.at("threshold"));
  g.uncertainty = exactNumber(j.at("uncertainty"));
  g.low = exactNumber(j.at("low"));
  g.high = exactNumber(j.at("high"));
  g.message = j.at("message").get<std::string>();
  for (const nlohmann::json& r : j.at("runs")) {
    GrowthProbe p;
    p.rate = exactNumber(r[0]);
    p.sigma = exactNumber(r[1]);
    p.sigma_error = exactNumber(r[2]);
    p.window_from = exactNumber(r[3]);
    p.window_to = exactNumber(r[4]);
    p.period = exactNumber(r[5]);
    p.max_tilt_deg = exactNumber(r[6]);
    p.saturated = r[7].get<bool>();
    p.wall_seconds = exactNumber(r[8]);
    p.failed = r[9].get<bool>();
    p.error = r[10].get<std::string>();
    p.decayed = r[11].get<bool>();
    g.runs.push_back(p);
  }
  return g;
}

}  // namespace flagella::cli
