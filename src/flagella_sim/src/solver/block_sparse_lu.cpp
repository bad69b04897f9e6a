#include "flagella_sim/solver/block_sparse_lu.h"

#include <suitesparse/amd.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <string>

namespace flagella {

namespace {

// Storage index of each block (row, col) of the factor pattern, created on first use.
class BlockSlots {
 public:
  int at(int row, int col) {
    const auto [it, inserted] = slots_.try_emplace({row, col}, static_cast<int>(slots_.size()));
    return it->second;
  }
  int size() const { return static_cast<int>(slots_.size()); }

 private:
  std::map<std::pair<int, int>, int> slots_;
};

// Inverts a 4x4 block by LU with partial pivoting (Golub & Van Loan, Alg. 3.4.1) unrolled at
// fixed size (Eigen's PartialPivLU::inverse() goes through its dynamic-size triangular solver);
// widens [smallest, largest] by the pivots' magnitudes, except those of the padding slots (bit s
// of `padding`: a unit row and column, which stay in place as pivot s). False on a zero pivot.
bool invertBlock(const BlockSparseLu::Block& D, unsigned padding, BlockSparseLu::Block& inverse,
                 double& smallest, double& largest) {
  BlockSparseLu::Block lu = D;
  int row_of[4] = {0, 1, 2, 3};  // lu's row k holds D's row row_of[k]
  double inverse_pivot[4];
  for (int k = 0; k < 4; ++k) {
    int p = k;
    for (int i = k + 1; i < 4; ++i)
      if (std::abs(lu(i, k)) > std::abs(lu(p, k))) p = i;
    if (p != k) {
      lu.row(k).swap(lu.row(p));
      std::swap(row_of[k], row_of[p]);
    }
    const double pivot = lu(k, k);
    if (pivot == 0.0) return false;
    inverse_pivot[k] = 1.0 / pivot;     // divisions once per pivot, products below
    if (padding & (1u << k)) continue;  // nothing below a padding pivot to eliminate
    smallest = std::min(smallest, std::abs(pivot));
    largest = std::max(largest, std::abs(pivot));
    for (int i = k + 1; i < 4; ++i) {
      lu(i, k) *= inverse_pivot[k];
      for (int j = k + 1; j < 4; ++j) lu(i, j) -= lu(i, k) * lu(k, j);
    }
  }
  for (int c = 0; c < 4; ++c) {  // column c of D^-1 solves L U x = P e_c
    double x[4];
    for (int i = 0; i < 4; ++i) {
      x[i] = row_of[i] == c ? 1.0 : 0.0;
      for (int j = 0; j < i; ++j) x[i] -= lu(i, j) * x[j];
    }
    for (int i = 3; i >= 0; --i) {
      for (int j = i + 1; j < 4; ++j) x[i] -= lu(i, j) * x[j];
      x[i] *= inverse_pivot[i];
    }
    for (int i = 0; i < 4; ++i) inverse(i, c) = x[i];
  }
  return true;
}

// Block and slot of each DOF; throws if a DOF is out of range, in two groups or in none.
void assignDofSlots(const std::vector<BlockSparseLu::DofGroup>& groups, int ndof,
                    std::vector<int>& block_of, std::vector<int>& slot_of) {
  const int nb = static_cast<int>(groups.size());
  for (int b = 0; b < nb; ++b)
    for (int s = 0; s < 4; ++s) {
      const int dof = groups[b][s];
      if (dof < 0) continue;
      if (dof >= ndof || block_of[dof] >= 0)
        throw std::invalid_argument("BlockSparseLu: DOF " + std::to_string(dof) +
                                    " out of range or in two groups");
      block_of[dof] = b;
      slot_of[dof] = s;
    }
  if (std::count(block_of.begin(), block_of.end(), -1) > 0)
    throw std::invalid_argument("BlockSparseLu: a DOF is in no group");
}

// Block graph of A + A^T (off-diagonal blocks only).
std::vector<std::set<int>> blockGraph(const SparseMatrix& A, const std::vector<int>& block_of,
                                      int nb) {
  std::vector<std::set<int>> adjacent(nb);
  for (int col = 0; col < A.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(A, col); it; ++it) {
      const int I = block_of[it.row()], J = block_of[col];
      if (I == J) continue;
      adjacent[I].insert(J);
      adjacent[J].insert(I);
    }
  return adjacent;
}

// Approximate-minimum-degree elimination order of the block graph (SuiteSparse AMD) into `order`.
void amdBlockOrder(const std::vector<std::set<int>>& adjacent, std::vector<int>& order) {
  const int nb = static_cast<int>(adjacent.size());
  std::vector<int> Ap(nb + 1, 0), Ai;
  for (int b = 0; b < nb; ++b) {
    Ai.insert(Ai.end(), adjacent[b].begin(), adjacent[b].end());
    Ap[b + 1] = static_cast<int>(Ai.size());
  }
  Ai.push_back(0);  // AMD refuses a null index array (a graph without edges); not referenced
  order.assign(nb, 0);
  if (nb > 0 && amd_order(nb, Ap.data(), Ai.data(), order.data(), nullptr, nullptr) < AMD_OK)
    throw std::runtime_error("BlockSparseLu: AMD ordering failed");
}

// The stored entry of each value of A, in A's storage order; marks each in `from_matrix`.
void mapMatrixValues(const SparseMatrix& A, BlockSlots& slots, const std::vector<int>& block_of,
                     const std::vector<int>& slot_of, std::vector<int>& value_offset,
                     std::vector<char>& from_matrix) {
  int n = 0;
  for (int col = 0; col < A.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(A, col); it; ++it, ++n) {
      const int offset = 16 * slots.at(block_of[it.row()], block_of[col]) + 4 * slot_of[col] +
                         slot_of[it.row()];  // Eigen blocks are column-major
      value_offset[n] = offset;
      from_matrix[offset] = 1;
    }
}

// The padding DOFs' unit diagonals and each block's padding bits; marks them in `from_matrix`.
void mapPadding(const std::vector<BlockSparseLu::DofGroup>& groups,
                const std::vector<int>& diagonal, std::vector<int>& unit_offsets,
                std::vector<unsigned>& padding, std::vector<char>& from_matrix) {
  const int nb = static_cast<int>(groups.size());
  for (int b = 0; b < nb; ++b)
    for (int s = 0; s < 4; ++s)
      if (groups[b][s] < 0) {
        unit_offsets.push_back(16 * diagonal[b] + 5 * s);
        from_matrix[unit_offsets.back()] = 1;
        padding[b] |= 1u << s;
      }
}

}  // namespace

void BlockSparseLu::analyze(const SparseMatrix& A, const std::vector<DofGroup>& groups) {
  ndof_ = static_cast<int>(A.rows());
  groups_ = groups;
  const int nb = static_cast<int>(groups.size());
  std::vector<int> block_of(ndof_, -1), slot_of(ndof_, -1);
  assignDofSlots(groups, ndof_, block_of, slot_of);

  std::vector<std::set<int>> adjacent = blockGraph(A, block_of, nb);
  amdBlockOrder(adjacent, order_);
  std::vector<int> position(nb);
  for (int k = 0; k < nb; ++k) position[order_[k]] = k;

  // Symbolic right-looking elimination: step k removes block v = order_[k]; its neighbours still
  // to come get L_iv = A_iv D_v^-1, and every pair of them the update A_ij -= L_iv A_vj.
  BlockSlots slots;
  diagonal_.assign(nb, 0);
  for (int b = 0; b < nb; ++b) diagonal_[b] = slots.at(b, b);
  lower_.clear();
  upper_.clear();
  updates_.clear();
  lower_begin_.assign(nb + 1, 0);
  upper_begin_.assign(nb + 1, 0);
  update_begin_.assign(nb + 1, 0);
  fill_blocks_ = 0;
  for (int k = 0; k < nb; ++k) {
    const int v = order_[k];
    std::vector<int> later;
    for (int u : adjacent[v])
      if (position[u] > k) later.push_back(u);
    lower_begin_[k] = static_cast<int>(lower_.size());
    upper_begin_[k] = static_cast<int>(upper_.size());
    update_begin_[k] = static_cast<int>(updates_.size());
    for (int i : later) {
      lower_.push_back({i, slots.at(i, v)});
      upper_.push_back({i, slots.at(v, i)});
    }
    for (int i : later)
      for (int j : later) {
        if (i != j && adjacent[i].insert(j).second) ++fill_blocks_;
        updates_.push_back({slots.at(i, j), slots.at(i, v), slots.at(v, j)});
      }
  }
  lower_begin_[nb] = static_cast<int>(lower_.size());
  upper_begin_[nb] = static_cast<int>(upper_.size());
  update_begin_[nb] = static_cast<int>(updates_.size());

  // Every stored entry is one value of A (each at its own place), a padding DOF's unit diagonal
  // or zero before elimination: a factorisation scatters A's values and rewrites the constants.
  nonzeros_ = static_cast<int>(A.nonZeros());
  const size_t entries = 16 * static_cast<size_t>(slots.size());
  std::vector<char> from_matrix(entries, 0);
  value_offset_.assign(nonzeros_, 0);
  mapMatrixValues(A, slots, block_of, slot_of, value_offset_, from_matrix);
  padding_.assign(nb, 0u);
  unit_offsets_.clear();
  mapPadding(groups, diagonal_, unit_offsets_, padding_, from_matrix);
  zero_offsets_.clear();
  for (size_t offset = 0; offset < entries; ++offset)
    if (!from_matrix[offset]) zero_offsets_.push_back(static_cast<int>(offset));
  blocks_.assign(slots.size(), Block::Zero());
  inverse_diagonal_.assign(nb, Block::Zero());
  work_.assign(nb, Eigen::Vector4d::Zero());
}

bool BlockSparseLu::factorize(const SparseMatrix& A, double min_pivot_ratio) {
  if (A.nonZeros() != nonzeros_)
    throw std::logic_error("BlockSparseLu::factorize: pattern differs from the analysed one");
  double* stored = storage();
  const double* values = A.valuePtr();
  for (int n = 0; n < nonzeros_; ++n) stored[value_offset_[n]] = values[n];
  for (int offset : zero_offsets_) stored[offset] = 0.0;
  for (int offset : unit_offsets_) stored[offset] = 1.0;
  return factorizeInPlace(min_pivot_ratio);
}

void BlockSparseLu::clearStorage() {
  for (Block& block : blocks_) block.setZero();
  double* stored = storage();
  for (int offset : unit_offsets_) stored[offset] = 1.0;
}

bool BlockSparseLu::factorizeInPlace(double min_pivot_ratio) {
  double smallest = std::numeric_limits<double>::infinity(), largest = 0.0;
  const int nb = numBlocks();
  for (int k = 0; k < nb; ++k) {
    if (!invertBlock(blocks_[diagonal_[order_[k]]], padding_[order_[k]], inverse_diagonal_[k],
                     smallest, largest) ||
        !std::isfinite(largest))
      return false;
    for (int n = lower_begin_[k]; n < lower_begin_[k + 1]; ++n) {
      Block& L = blocks_[lower_[n][1]];
      L = (L * inverse_diagonal_[k]).eval();
    }
    for (int n = update_begin_[k]; n < update_begin_[k + 1]; ++n) {
      const Update& u = updates_[n];
      blocks_[u.target].noalias() -= blocks_[u.lower] * blocks_[u.upper];
    }
  }
  return smallest >= min_pivot_ratio * largest;
}

VecX BlockSparseLu::solve(const VecX& b) {
  VecX x;
  solve(b, x);
  return x;
}

void BlockSparseLu::solve(const VecX& b, VecX& x) {
  const int nb = numBlocks();
  for (int k = 0; k < nb; ++k)
    for (int s = 0; s < 4; ++s) work_[k](s) = groups_[k][s] >= 0 ? b(groups_[k][s]) : 0.0;
  for (int k = 0; k < nb; ++k) {  // L y = b
    const Eigen::Vector4d& yv = work_[order_[k]];
    for (int n = lower_begin_[k]; n < lower_begin_[k + 1]; ++n)
      work_[lower_[n][0]].noalias() -= blocks_[lower_[n][1]] * yv;
  }
  for (int k = nb - 1; k >= 0; --k) {  // U x = y
    Eigen::Vector4d r = work_[order_[k]];
    for (int n = upper_begin_[k]; n < upper_begin_[k + 1]; ++n)
      r.noalias() -= blocks_[upper_[n][1]] * work_[upper_[n][0]];
    work_[order_[k]].noalias() = inverse_diagonal_[k] * r;
  }
  x.resize(ndof_);
  for (int k = 0; k < nb; ++k)
    for (int s = 0; s < 4; ++s)
      if (groups_[k][s] >= 0) x(groups_[k][s]) = work_[k](s);
}

}  // namespace flagella
