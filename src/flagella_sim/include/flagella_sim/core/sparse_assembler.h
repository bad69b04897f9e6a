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
  /// Adds the n x n matrix m at rows/cols idx (m column-major). Fast path: the pattern verified
  /// at the block's first and last entry, then the values added (addRecorded).
  template <int N>
  void addDense(const int* idx, const Eigen::Matrix<double, N, N>& m) {
    const size_t end = cursor_ + N * N;
    if (!recording_ && end <= rows_.size() && rows_[cursor_] == idx[0] &&
        cols_[cursor_] == idx[0] && rows_[end - 1] == idx[N - 1] && cols_[end - 1] == idx[N - 1]) {
      addRecorded(m.data(), end);
      return;
    }
    for (int b = 0; b < N; ++b)
      for (int a = 0; a < N; ++a) add(idx[a], idx[b], m(a, b));
  }
  /// Adds a dense 3x3 block at (row, col); same fast path as addDense.
  void addBlock(int row, int col, const Mat3& block) { addBlockSigned<false>(row, col, block); }
  /// Subtracts a dense 3x3 block at (row, col) (the same sums as adding -block).
  void subtractBlock(int row, int col, const Mat3& block) { addBlockSigned<true>(row, col, block); }
  /// Ends a pass and returns the assembled matrix (its values are stale while redirected).
  SparseMatrix& finish();
  /// Later passes add the value of the matrix's k-th stored entry at storage[offsets[k]] (a
  /// solver's own storage, assembled in place) instead of into matrix(); begin() then leaves the
  /// zeroing of storage to the caller. Holds until a pass changes the pattern (finish() then
  /// assembles into matrix() again, patternChanged()) or stopRedirect().
  void redirect(double* storage, int storage_size, const std::vector<int>& offsets);
  void stopRedirect();
  bool redirected() const { return redirected_; }
  /// The matrix as last finished.
  const SparseMatrix& matrix() const { return matrix_; }
  /// True if the last finish() had to rebuild the pattern.
  bool patternChanged() const { return pattern_changed_; }
  int size() const { return size_; }

 private:
  void switchToRecording();
  void addSlow(int row, int col, double value);
  /// Adds the contributions cursor_ .. end - 1 (values in recorded order) and moves the cursor
  /// to end. Three contributions whose slots follow each other in the compressed storage (a
  /// node's three rows in one column) take one slot lookup.
  template <bool Subtract = false>
  void addRecorded(const double* values, size_t end) {
    const double* in = values - cursor_;
    size_t k = cursor_;
    while (k < end) {
      double* out = values_ptr_ + slot_[k];
      if (triple_[k] && k + 3 <= end) {
        out[0] += Subtract ? -in[k] : in[k];
        out[1] += Subtract ? -in[k + 1] : in[k + 1];
        out[2] += Subtract ? -in[k + 2] : in[k + 2];
        k += 3;
      } else {
        out[0] += Subtract ? -in[k] : in[k];
        ++k;
      }
    }
    cursor_ = end;
  }
  template <bool Subtract>
  void addBlockSigned(int row, int col, const Mat3& block) {
    const size_t end = cursor_ + 9;
    if (!recording_ && end <= rows_.size() && rows_[cursor_] == row && cols_[cursor_] == col &&
        rows_[end - 1] == row + 2 && cols_[end - 1] == col + 2) {
      addRecorded<Subtract>(block.data(), end);
      return;
    }
    for (int b = 0; b < 3; ++b)
      for (int a = 0; a < 3; ++a) add(row + a, col + b, Subtract ? -block(a, b) : block(a, b));
  }

  int size_ = 0;
  bool recorded_ = false;
  bool recording_ = true;
  bool pattern_changed_ = true;
  size_t cursor_ = 0;
  std::vector<int> rows_, cols_;
  std::vector<double> values_;
  std::vector<int> matrix_slot_;  // position in matrix_.valuePtr() of each contribution
  std::vector<int> slot_;         // where each contribution is added: matrix or redirect storage
  std::vector<char> triple_;      // slots of contributions k + 1, k + 2 follow slot_[k]
  void setSlots(double* values, int values_size, std::vector<int> slots);
  bool redirected_ = false;
  int values_size_ = 0;  // entries behind values_ptr_
  SparseMatrix matrix_;
  double* values_ptr_ = nullptr;
};

}  // namespace flagella
