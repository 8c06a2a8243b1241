#include "core/linalg/sparse_matrix.hpp"

#include <algorithm>
#include <stdexcept>

#include "core/base/memory_bytes.hpp"
#include "core/base/parallel.hpp"

namespace mps_lab {

void multiply(const CsrMatrix& matrix, const double* x, double* y) {
  const int rows = matrix.rows;
  const int* start = matrix.row_start.data();
  const int* column = matrix.column.data();
  const double* value = matrix.value.data();
#pragma omp parallel for schedule(static)
  for (int r = 0; r < rows; ++r) {
    double sum = 0.0;
    for (int k = start[r]; k < start[r + 1]; ++k) sum += value[k] * x[column[k]];
    y[r] = sum;
  }
}

void CsrAssembler::finish(CsrMatrix& matrix, bool diagonal_first) {
  matrix.rows = rows_;
  matrix.diagonal_first = diagonal_first;
  matrix.row_start.resize(static_cast<std::size_t>(rows_) + 1);
  matrix.row_start[0] = 0;
  for (int row = 0; row < rows_; ++row) {
    matrix.row_start[static_cast<std::size_t>(row) + 1] =
        matrix.row_start[static_cast<std::size_t>(row)] + length_[static_cast<std::size_t>(row)];
  }
  const auto entries = static_cast<std::size_t>(matrix.row_start[static_cast<std::size_t>(rows_)]);
  resize_with_headroom(matrix.column, entries);
  resize_with_headroom(matrix.value, entries);
  const int rows = rows_;
#pragma omp parallel for schedule(static)
  for (int row = 0; row < rows; ++row) {
    const auto from = static_cast<std::size_t>(slot_start_[static_cast<std::size_t>(row)]);
    const auto to = static_cast<std::size_t>(matrix.row_start[static_cast<std::size_t>(row)]);
    const auto length = static_cast<std::size_t>(length_[static_cast<std::size_t>(row)]);
    std::copy(column_.begin() + static_cast<std::ptrdiff_t>(from),
              column_.begin() + static_cast<std::ptrdiff_t>(from + length),
              matrix.column.begin() + static_cast<std::ptrdiff_t>(to));
    std::copy(value_.begin() + static_cast<std::ptrdiff_t>(from),
              value_.begin() + static_cast<std::ptrdiff_t>(from + length),
              matrix.value.begin() + static_cast<std::ptrdiff_t>(to));
  }
}

void CsrInPlaceAssembler::start(CsrMatrix& matrix, int rows) {
  matrix_ = &matrix;
  rows_ = rows;
  matrix.rows = rows;
  matrix.row_start.assign(static_cast<std::size_t>(rows) + 1, 0);
  length_.resize(static_cast<std::size_t>(rows));
}

void CsrInPlaceAssembler::place(CsrMatrix& matrix) {
  for (int row = 0; row < rows_; ++row) {
    matrix.row_start[static_cast<std::size_t>(row) + 1] += matrix.row_start[static_cast<std::size_t>(row)];
  }
  const auto entries = static_cast<std::size_t>(matrix.row_start[static_cast<std::size_t>(rows_)]);
  resize_with_headroom(matrix.column, entries);
  resize_with_headroom(matrix.value, entries);
}

void CsrInPlaceAssembler::finish(CsrMatrix& matrix, bool diagonal_first) {
  matrix.diagonal_first = diagonal_first;
  int first_short = rows_;
  for (int row = rows_ - 1; row >= 0; --row) {
    const auto r = static_cast<std::size_t>(row);
    const int counted = matrix.row_start[r + 1] - matrix.row_start[r];
    if (length_[r] > counted) throw std::logic_error("CsrInPlaceAssembler: a row has more entries than its count");
    if (length_[r] < counted) first_short = row;
  }
  if (first_short == rows_) return;  // every row as counted: nothing to move
  // Close up the gaps: every row moves towards the front (destination <= source), in order.
  int to = matrix.row_start[static_cast<std::size_t>(first_short)];
  for (int row = first_short; row < rows_; ++row) {
    const auto r = static_cast<std::size_t>(row);
    const int from = matrix.row_start[r];
    const int length = length_[r];
    std::copy_n(matrix.column.begin() + from, length, matrix.column.begin() + to);
    std::copy_n(matrix.value.begin() + from, length, matrix.value.begin() + to);
    matrix.row_start[r] = to;
    to += length;
  }
  matrix.row_start[static_cast<std::size_t>(rows_)] = to;
  matrix.column.resize(static_cast<std::size_t>(to));
  matrix.value.resize(static_cast<std::size_t>(to));
}

// The blocked sum of core/base/parallel.hpp (fixed blocks of kDeterministicBlock entries).
double deterministic_dot(const double* a, const double* b, std::size_t n) {
  return deterministic_sum(n, [a, b](std::size_t i) { return a[i] * b[i]; });
}

}  // namespace mps_lab
