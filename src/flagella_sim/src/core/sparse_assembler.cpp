#include "flagella_sim/core/sparse_assembler.h"

#include <algorithm>
#include <stdexcept>

namespace flagella {

void SparseAssembler::resize(int size) {
  size_ = size;
  recorded_ = false;
}

void SparseAssembler::begin() {
  cursor_ = 0;
  recording_ = !recorded_;
  if (recording_) {
    rows_.clear();
    cols_.clear();
    values_.clear();
  } else if (!redirected_) {
    std::fill(matrix_.valuePtr(), matrix_.valuePtr() + matrix_.nonZeros(), 0.0);
  }
}

void SparseAssembler::switchToRecording() {
  // The sequence diverged from the recorded pattern: replay what was added so far.
  recording_ = true;
  rows_.resize(cursor_);
  cols_.resize(cursor_);
  values_.assign(cursor_, 0.0);
  for (size_t k = 0; k < cursor_; ++k) values_[k] = values_ptr_[slot_[k]];
  // Values of shared slots were summed; keep the sum on the first contribution only.
  std::vector<bool> seen(values_size_, false);
  for (size_t k = 0; k < cursor_; ++k) {
    if (seen[slot_[k]]) values_[k] = 0.0;
    seen[slot_[k]] = true;
  }
}

void SparseAssembler::addSlow(int row, int col, double value) {
  if (!recording_) switchToRecording();
  rows_.push_back(row);
  cols_.push_back(col);
  values_.push_back(value);
  ++cursor_;
}

SparseMatrix& SparseAssembler::finish() {
  if (!recording_ && cursor_ == rows_.size()) {
    pattern_changed_ = false;
    return matrix_;
  }
  if (!recording_) switchToRecording();
  rows_.resize(cursor_);
  cols_.resize(cursor_);
  values_.resize(cursor_);
  // Build the pattern: every diagonal is present so fixed-DOF rows can be pinned.
  TripletList triplets;
  triplets.reserve(rows_.size() + size_);
  for (int i = 0; i < size_; ++i) triplets.emplace_back(i, i, 0.0);
  for (size_t k = 0; k < rows_.size(); ++k) triplets.emplace_back(rows_[k], cols_[k], values_[k]);
  matrix_.resize(size_, size_);
  matrix_.setFromTriplets(triplets.begin(), triplets.end());
  matrix_.makeCompressed();
  // Locate each contribution's slot in the compressed storage.
  matrix_slot_.resize(rows_.size());
  for (size_t k = 0; k < rows_.size(); ++k) {
    const int col = cols_[k];
    const int* begin = matrix_.innerIndexPtr() + matrix_.outerIndexPtr()[col];
    const int* end = matrix_.innerIndexPtr() + matrix_.outerIndexPtr()[col + 1];
    matrix_slot_[k] =
        static_cast<int>(std::lower_bound(begin, end, rows_[k]) - matrix_.innerIndexPtr());
  }
  redirected_ = false;
  setSlots(matrix_.valuePtr(), static_cast<int>(matrix_.nonZeros()), matrix_slot_);
  recorded_ = true;
  pattern_changed_ = true;
  return matrix_;
}

void SparseAssembler::setSlots(double* values, int values_size, std::vector<int> slots) {
  slot_ = std::move(slots);
  triple_.assign(slot_.size(), 0);
  for (size_t k = 0; k + 2 < slot_.size(); ++k)
    triple_[k] = slot_[k + 1] == slot_[k] + 1 && slot_[k + 2] == slot_[k] + 2;
  values_ptr_ = values;
  values_size_ = values_size;
}

void SparseAssembler::redirect(double* storage, int storage_size, const std::vector<int>& offsets) {
  if (!recorded_ || offsets.size() != static_cast<size_t>(matrix_.nonZeros()))
    throw std::logic_error("SparseAssembler::redirect: offsets do not match the recorded pattern");
  std::vector<int> slots(matrix_slot_.size());
  for (size_t k = 0; k < slots.size(); ++k) slots[k] = offsets[matrix_slot_[k]];
  setSlots(storage, storage_size, std::move(slots));
  redirected_ = true;
}

void SparseAssembler::stopRedirect() {
  if (!redirected_) return;
  setSlots(matrix_.valuePtr(), static_cast<int>(matrix_.nonZeros()), matrix_slot_);
  redirected_ = false;
}

}  // namespace flagella
