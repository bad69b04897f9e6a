// Seeded Gaussian matrices and vectors for linear-algebra tests.
#pragma once

#include <random>

#include "flagella_sim/core/types.h"

namespace flagella::testing {

/// n x n entries drawn from N(0, 1) with this seed.
inline MatX randomMatrix(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  return MatX::NullaryExpr(n, n, [&] { return g(rng); });
}

/// n entries drawn from N(0, 1) with this seed.
inline VecX randomVector(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> g;
  return VecX::NullaryExpr(n, [&] { return g(rng); });
}

}  // namespace flagella::testing
