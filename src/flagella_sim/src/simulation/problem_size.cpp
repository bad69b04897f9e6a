#include "flagella_sim/simulation/problem_size.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>

#include "flagella_sim/core/parameter_set.h"
#include "flagella_sim/core/text_lists.h"
#include "flagella_sim/effects/rss_hydrodynamics.h"
#include "flagella_sim/simulation/simulation_config.h"

namespace flagella {

namespace {

// Nodes x_0 .. x_3 (head, shaft, plate rim) before the helix (docs/model.md 8.4.1).
constexpr int kHelicalHeadNodes = 4;
// Stokeslet segments act on x_3 .. x_{N-1} (docs/model.md 4).
constexpr int kFirstStokesletNode = 3;

double physicalMemoryBytes() {
  const long pages = sysconf(_SC_PHYS_PAGES), page = sysconf(_SC_PAGE_SIZE);
  return pages > 0 && page > 0 ? static_cast<double>(pages) * static_cast<double>(page) : 0.0;
}

std::string bytesText(double bytes) {
  char text[32];
  if (bytes >= 1e9)
    std::snprintf(text, sizeof(text), "%.1f GB", bytes / 1e9);
  else
    std::snprintf(text, sizeof(text), "%.1f MB", bytes / 1e6);
  return text;
}

std::string secondsText(double seconds) {
  char text[32];
  if (seconds >= 1.0)
    std::snprintf(text, sizeof(text), "%.3g s", seconds);
  else
    std::snprintf(text, sizeof(text), "%.2g ms", seconds * 1e3);
  return text;
}

}  // namespace

ProblemSize estimateProblemSize(const SimulationConfig& c) {
  ProblemSize size;
  const HelicalGeometry* helix = c.findRobotGeometry<HelicalGeometry>();
  if (!helix || !c.effect(RssHydrodynamics::kName)) return size;
  // Before rounding, as validateEdgeCount: no int overflow for absurd sizes.
  const double helix_nodes = helix->arcLength() / helix->edge_length + 1.0;
  const double nodes = kHelicalHeadNodes + helix_nodes;
  const double dofs = 4.0 * nodes - 1.0;
  const double dense = 3.0 * (nodes - kFirstStokesletNode);
  size.nodes = static_cast<int>(std::min(nodes, 2e9));
  size.dofs = static_cast<int>(std::min(dofs, 2e9));
  size.dense_unknowns = static_cast<int>(std::min(dense, 2e9));
  // Two copies of each dense matrix (the matrix and its LU), 8 bytes an entry.
  size.memory_bytes = 16.0 * (dense * dense + dofs * dofs);
  // LU: 2/3 n^3 flops each.
  size.seconds_per_update =
      (2.0 / 3.0) * (dense * dense * dense + dofs * dofs * dofs) / kDenseFlopsPerSecond;
  return size;
}

std::string describeProblemSize(const ProblemSize& s) {
  if (s.nodes == 0) return "";
  return std::to_string(s.nodes) + " nodes, dense blocks " + std::to_string(s.dense_unknowns) +
         " + " + std::to_string(s.dofs) + " unknowns: about " + bytesText(s.memory_bytes) +
         " and " + secondsText(s.seconds_per_update) + " per factorisation";
}

void requireRunnableSize(const SimulationConfig& c) {
  if (!c.size_check) return;
  const ProblemSize s = estimateProblemSize(c);
  if (s.nodes == 0) return;
  const double memory_limit = 0.5 * physicalMemoryBytes();
  const bool too_big = memory_limit > 0.0 && s.memory_bytes > memory_limit;
  const bool too_slow = s.seconds_per_update > kMaxSecondsPerUpdate;
  if (!too_big && !too_slow) return;
  std::string why =
      too_big ? "more than half of this machine's " + bytesText(2.0 * memory_limit) + " of memory"
              : "more than " + secondsText(kMaxSecondsPerUpdate) + " per factorisation";
  const HelicalGeometry& helix = c.robotGeometry<HelicalGeometry>();
  throw ConfigError("robot: the helix (L_arc = " + formatNumber(helix.arcLength()) +
                    " m, robot.edge_length = " + formatNumber(helix.edge_length) + " m) gives " +
                    describeProblemSize(s) + ", " + why +
                    " (lengths are in metres: robot.helix_radius, robot.pitch); "
                    "--set solver.size_check=false runs it anyway");
}

}  // namespace flagella
