// Files a run leaves behind: CSV time series (columns documented in the README), node
// positions, and a JSON summary.
#pragma once

#include <string>
#include <vector>

#include "flagella_sim/outputs/trajectory.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace flagella {

/// Columns: see trajectoryCsvHeader().
void writeTrajectoryCsv(const std::string& path, const std::vector<TrajectorySample>& samples);
std::string trajectoryCsvHeader();
/// Long format: time,node,x,y,z for every sample that carries node positions.
void writeNodesCsv(const std::string& path, const std::vector<TrajectorySample>& samples);
/// Summary metrics (SI and rpm) plus the run's key inputs.
std::string summaryJson(const SimulationConfig& config, const SummaryMetrics& m,
                        double wall_seconds);
void writeText(const std::string& path, const std::string& text);

}  // namespace flagella
