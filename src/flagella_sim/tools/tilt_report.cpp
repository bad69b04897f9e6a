#include "tilt_report.h"

#include <sstream>

#include "flagella_sim/runtime/exact_json.h"
#include "growth_report.h"

namespace flagella::cli {

namespace {

// A search as text, for the ranks of an MPI sweep (distributed_for.h); doubles exactly
// (exact_json.h).
nlohmann::json probesText(const std::vector<ThresholdProbe>& runs) {
  nlohmann::json out = nlohmann::json::array();
  for (const ThresholdProbe& p : runs)
    out.push_back({flagella::exactJson(p.rate), p.above, flagella::exactJson(p.indicator),
                   flagella::exactJson(p.wall_seconds), p.failed, p.error});
  return out;
}

std::vector<ThresholdProbe> probesFrom(const nlohmann::json& j) {
  std::vector<ThresholdProbe> runs;
  for (const nlohmann::json& r : j)
    runs.push_back({flagella::exactNumber(r[0]), r[1].get<bool>(), flagella::exactNumber(r[2]),
                    flagella::exactNumber(r[3]), r[4].get<bool>(), r[5].get<std::string>()});
  return runs;
}

nlohmann::ordered_json runsJson(const std::vector<ThresholdProbe>& probes) {
  nlohmann::ordered_json runs = nlohmann::ordered_json::array();
  for (const ThresholdProbe& p : probes) {
    nlohmann::ordered_json run;
    run["omega_rpm"] = p.rate;
    run["max_tilt_deg"] = p.indicator;
    run["buckled"] = p.above;
    run["wall_s"] = p.wall_seconds;
    run["failed"] = p.failed;
    run["error"] = p.error;
    runs.push_back(run);
  }
  return runs;
}

}  // namespace

std::string encodeSearch(const Search& s) {
  const ThresholdResult& b = s.bisection;
  return nlohmann::json{{"found", b.found},
                        {"threshold", flagella::exactJson(b.threshold)},
                        {"low", flagella::exactJson(b.low)},
                        {"high", flagella::exactJson(b.high)},
                        {"runs", probesText(b.runs)},
                        {"message", b.message},
                        {"refined_threshold", flagella::exactJson(s.refined.threshold)},
                        {"refined_runs", probesText(s.refined.runs)},
                        {"refined_message", s.refined.message},
                        {"growth", encodeGrowth(s.growth)}}
      .dump();
}

Search decodeSearch(const std::string& text) {
  const nlohmann::json j = nlohmann::json::parse(text);
  Search s;
  s.bisection.found = j.at("found").get<bool>();
  s.bisection.threshold = flagella::exactNumber(j.at("threshold"));
  s.bisection.low = flagella::exactNumber(j.at("low"));
  s.bisection.high = flagella::exactNumber(j.at("high"));
  s.bisection.runs = probesFrom(j.at("runs"));
  s.bisection.message = j.at("message").get<std::string>();
  s.refined.threshold = flagella::exactNumber(j.at("refined_threshold"));
  s.refined.runs = probesFrom(j.at("refined_runs"));
  s.refined.message = j.at("refined_message").get<std::string>();
  s.growth = decodeGrowth(j.at("growth"));
  return s;
}

std::string criterion(const SimulationConfig& c) {
  std::ostringstream s;
  s << "buckled when the largest angle between the head axis and the helix's principal axis over "
       "the last "
    << c.steady_fraction * 100.0 << " % of a " << c.duration << " s run exceeds "
    << c.buckling_tilt_deg << " deg (simulation.buckling_tilt_deg)";
  return s.str();
}

nlohmann::ordered_json resultJson(const SimulationConfig& c, const Search& s, int refine) {
  const ThresholdResult& r = s.bisection;
  nlohmann::ordered_json j;
  j["config"] = c.source;
  j["found"] = r.found;
  j["buckling_threshold_rpm"] = r.found ? nlohmann::ordered_json(r.threshold) : nullptr;
  j["bracket_rpm"] = r.found ? nlohmann::ordered_json({r.low, r.high}) : nullptr;
  if (!r.found) j["message"] = r.message;
  nlohmann::ordered_json rule;
  rule["definition"] = criterion(c);
  rule["buckling_tilt_deg"] = c.buckling_tilt_deg;
  rule["duration_s"] = c.duration;
  rule["steady_fraction"] = c.steady_fraction;
  j["criterion"] = rule;
  j["runs"] = runsJson(r.runs);
  if (refine > 0) {
    nlohmann::ordered_json refined;
    refined["smoothed_threshold_rpm"] = finiteOrNull(s.refined.threshold);
    refined["definition"] =
        "lowest rate where the largest tilt, averaged over three neighbouring rates of the grid "
        "1.02^k rpm and interpolated in log rate, reaches the criterion; runs at the " +
        std::to_string(2 * refine + 1) +
        " grid rates nearest the bisection threshold (the calibration's threshold)";
    if (!s.refined.message.empty()) refined["message"] = s.refined.message;
    refined["runs"] = runsJson(s.refined.runs);
    j["refined"] = refined;
  }
  return j;
}

}  // namespace flagella::cli
