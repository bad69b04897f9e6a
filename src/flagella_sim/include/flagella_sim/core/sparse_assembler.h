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
  /// Adds a dense 3x3 block at (row, col).
  void addBlock(int row, int col, const Mat3& block);
  /// Ends a pass and returns the assembled matrix.
  SparseMatrix& finish();
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
