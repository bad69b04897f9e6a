// The tilt method's report of flagella_buckling (--method tilt, "visibly buckled within T s",
// docs/model.md 8.4.4): a search's result as JSON, and as exact text for the ranks of an MPI
// sweep (the growth method's pieces are in growth_report.h).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "flagella_sim/analysis/buckling_probe.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace flagella::cli {

/// A bisection's threshold and, with --refine, the straight-line crossing over runs around it.
struct Search {
  ThresholdResult bisection;
  flagella::WindowThreshold refined;
  flagella::GrowthThreshold growth;  ///< --method growth
};

/// A search as exact text (exact_json.h) and back, for the ranks of an MPI sweep.
std::string encodeSearch(const Search& s);
Search decodeSearch(const std::string& text);

/// The tilt criterion in words.
std::string criterion(const SimulationConfig& c);

/// The JSON of a tilt search: threshold, bracket, criterion, runs and, with `refine` > 0, the
/// smoothed threshold over the refinement grid.
nlohmann::ordered_json resultJson(const SimulationConfig& c, const Search& s, int refine);

}  // namespace flagella::cli
