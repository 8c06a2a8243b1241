#pragma once
// A square sparse matrix in compressed-row storage (CSR), the common currency of the pressure
// solvers (methods/mps, methods/isph) and their preconditioners (core/). Plain data: the
// methods assemble it straight from the neighbour lists, reusing the storage from step to
// step (resize never shrinks the capacity, so after the first steps nothing is allocated).
//
// Invariants: row_start.size() == rows + 1, row_start[0] == 0, row_start is non-decreasing;
// the columns of row r are column[row_start[r] .. row_start[r+1]), each in [0, rows), each at
// most once; value[k] is the entry at (r, column[k]). Whether the diagonal comes first in its
// row is a property of the assembler (diagonal_first says so; the preconditioners use it).
#include <cstddef>
#include <vector>

namespace mps_lab {

struct CsrMatrix {
  int rows = 0;
  std::vector<int> row_start;  // rows + 1
  std::vector<int> column;
  std::vector<double> value;
  bool diagonal_first = false;  // every row stores its diagonal entry first

  std::size_t nonzeros() const { return column.size(); }
  void clear_rows(int row_count) {  // keeps capacity
    rows = row_count;
    row_start.assign(static_cast<std::size_t>(row_count) + 1, 0);
    column.clear();
    value.clear();
  }
};

// y = A x (parallel over rows; every y[r] is summed in row order, so the result does not depend
// on the thread count).
void multiply(const CsrMatrix& matrix, const double* x, double* y);

// Deterministic parallel dot product: the sum is taken over fixed blocks of the index range
// whose partial sums are added in block order, so the result is the same, bit for bit, for
// any number of threads (the determinism tests compare 1 and 2 threads byte for byte).
double deterministic_dot(const double* a, const double* b, std::size_t n);

}  // namespace mps_lab
