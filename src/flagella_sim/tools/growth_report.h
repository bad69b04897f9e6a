// The growth-rate threshold of flagella_buckling as text (docs/model.md 8.4.4): its progress
// lines, its JSON, its CSV of sigma against the rate, and its exact encoding between MPI ranks.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "flagella_sim/analysis/buckling_probe.h"

namespace flagella::cli {

/// A finite value as a JSON number, NaN or infinity as null (the tool's JSON for a missing value).
nlohmann::ordered_json finiteOrNull(double x);
/// The definition printed and stored with the threshold.
std::string growthDefinition(const GrowthProbeOptions& o);
/// One run as a progress line ("  4.000 rpm: sigma +0.0131 +- 0.0005 1/s -> growing ...").
std::string growthRunLine(const GrowthProbe& p);
/// The threshold and every run, for --json.
nlohmann::ordered_json growthJson(const GrowthThreshold& g, const GrowthProbeOptions& o);
/// sigma against the rate, one run a row, for the plot.
void writeGrowthCsv(const std::string& path, const GrowthThreshold& g);
/// Exact round trip (doubles to the bit) for the ranks of an MPI sweep.
nlohmann::json encodeGrowth(const GrowthThreshold& g);
GrowthThreshold decodeGrowth(const nlohmann::json& j);

}  // namespace flagella::cli
