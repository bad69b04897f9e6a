// Assembles a sparse matrix from a repeated, deterministic sequence of (row, col, value)
// contributions. The first pass records the pattern; later passes write straight into the
// compressed storage, so the sparsity pattern (and a solver's symbolic analysis) is reused
// across Newton iterations and steps. A pass whose sequence differs from the recorded one
// rebuilds the pattern and reports it through patternChanged().
#pragma once

#include <vector>

#include "flagella_sim/core/types.h"

namespace flagella {

class SparseAssembler {
 public:
  explicit SparseAssembler(int size = 0) : size_(size) {}

  void resize(int size);
  /// Starts a pass: zeroes the values, rewinds the cursor.
  void begin();
  /// Adds value at (row, col). Contributions arrive in the recorded order (callers guarantee a
  /// value-independent sequence); the row/column check falls back to re-recording.
  void add(int row, int col, double value) {
    if (!recording_ && cursor_ < rows_.size() && rows_[cursor_] == row && cols_[cursor_] == col) {
      values_ptr_[slot_[cursor_++]] += value;
      return;
    }
    addSlow(row, col, value);
  }
  /// Adds the n x n matrix m at rows/cols idx (m column-major). Fast path: one slot lookup per
  /// entry, pattern verified at the block's first and last entry.
  template <int N>
  void addDense(const int* idx, const Eigen::Matrix<double, N, N>& m) {
    const size_t end = cursor_ + N * N;
    if (!recording_ && end <= rows_.size() && rows_[cursor_] == idx[0] &&
        cols_[cursor_] == idx[0] && rows_[end - 1] == idx[N - 1] && cols_[end - 1] == idx[N - 1]) {
      const int* slot = slot_.data() + cursor_;
      const double* value = m.data();
      for (int k = 0; k < N * N; ++k) values_ptr_[slot[k]] += value[k];
      cursor_ = end;
      return;
    }
    for (int b = 0; b < N; ++b)
      for (int a = 0; a < N; ++a) add(idx[a], idx[b], m(a, b));
  }
  /// Adds a dense 3x3 block at (row, col); same fast path as addDense.
  void addBlock(int row, int col, const Mat3& block) {
    const size_t end = cursor_ + 9;
    if (!recording_ && end <= rows_.size() && rows_[cursor_] == row && cols_[cursor_] == col &&
        rows_[end - 1] == row + 2 && cols_[end - 1] == col + 2) {
      const int* slot = slot_.data() + cursor_;
      for (int b = 0; b < 3; ++b)
        for (int a = 0; a < 3; ++a) values_ptr_[*slot++] += block(a, b);
      cursor_ = end;
      return;
    }
    for (int b = 0; b < 3; ++b)
      for (int a = 0; a < 3; ++a) add(row + a, col + b, block(a, b));
  }
  /// Ends a pass and returns the assembled matrix.
  SparseMatrix& finish();
  /// The matrix as last finished.
  const SparseMatrix& matrix() const { return matrix_; }
  /// True if the last finish() had to rebuild the pattern.
  bool patternChanged() const { return pattern_changed_; }
  int size() const { return size_; }

 private:
  void switchToRecording();
  void addSlow(int row, int col, double value);

  int size_ = 0;
  bool recorded_ = false;
  bool recording_ = true;
  bool pattern_changed_ = true;
  size_t cursor_ = 0;
  std::vector<int> rows_, cols_;
  std::vector<double> values_;
  std::vector<int> slot_;  // position in matrix_.valuePtr() of each contribution
  SparseMatrix matrix_;
  double* values_ptr_ = nullptr;
};

}  // namespace flagella
