// Files a run leaves behind: CSV time series (columns documented in the README), node
// positions, and plain text (the JSON summary is written by flagella_run: tools/summary_json.h).
#pragma once

#include <string>
#include <vector>

#include "flagella_sim/outputs/trajectory.h"

namespace flagella {

/// Columns: see trajectoryCsvHeader().
void writeTrajectoryCsv(const std::string& path, const std::vector<TrajectorySample>& samples);
std::string trajectoryCsvHeader();
/// Long format: time,node,x,y,z for every sample that carries node positions.
void writeNodesCsv(const std::string& path, const std::vector<TrajectorySample>& samples);
void writeText(const std::string& path, const std::string& text);

}  // namespace flagella
