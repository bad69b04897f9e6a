// What a config implies before anything is built: nodes, unknowns, the dense blocks of the
// regularized Stokeslet model, their memory and the time of one Newton update (docs/model.md
// 4.4). A helix given in metres where millimetres were meant builds thousands of nodes, and the
// dense model would need gigabytes and minutes per step: such configs are refused while loading.
#pragma once

#include <string>

namespace flagella {

struct SimulationConfig;

struct ProblemSize {
  int nodes = 0;                    ///< N (0: not estimated, the robot has no dense block)
  int dofs = 0;                     ///< 4N - 1
  int dense_unknowns = 0;           ///< 3 x the nodes the Stokeslet segments act on (0 without rss)
  double memory_bytes = 0.0;        ///< dense matrices: RSS matrix, its LU, Newton system, LU
  double seconds_per_update = 0.0;  ///< LU of both at kDenseFlopsPerSecond
};

/// Dense LU rate assumed for the time estimate (measured on a 2-core machine: the 88-node
/// helical robot factorizes its 351-unknown Newton system in 1.8-1.9 ms).
constexpr double kDenseFlopsPerSecond = 1.5e10;

ProblemSize estimateProblemSize(const SimulationConfig& config);

/// "88 nodes, dense block 255 + 351 unknowns: about 3.0 MB and 2.9 ms per factorisation".
std::string describeProblemSize(const ProblemSize& size);

/// Throws ConfigError with the figures when the dense blocks need more than half of this
/// machine's memory or more than kMaxSecondsPerUpdate per factorisation, unless the config
/// sets solver.size_check: false.
void requireRunnableSize(const SimulationConfig& config);

constexpr double kMaxSecondsPerUpdate = 10.0;

}  // namespace flagella
