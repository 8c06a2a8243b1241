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
  std::size_t held_bytes() const {  // capacity of the three arrays
    return row_start.capacity() * sizeof(int) + column.capacity() * sizeof(int) + value.capacity() * sizeof(double);
  }
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

// Assembles a CsrMatrix row by row, rows in parallel, without knowing the row lengths in
// advance: start() takes an upper bound of every row's length, each row is written into its
// own padded slot by a RowWriter (one thread per row), finish() packs the slots into the
// matrix (prefix sum of the actual lengths, then a parallel copy). All storage is reused: once
// the sizes have been seen, assembling allocates nothing.
//   assembler.start(rows, [&](int row) { return bound; });
//   #pragma omp parallel for
//   for (int row ...) { auto writer = assembler.row(row); writer.add(column, value); ... writer.close(); }
//   assembler.finish(matrix, /*diagonal_first=*/true);
class CsrAssembler {
 public:
  class RowWriter {
   public:
    RowWriter(CsrAssembler& owner, int row)
        : owner_(owner), row_(row), begin_(owner.slot_start_[static_cast<std::size_t>(row)]), end_(begin_) {}
    void add(int column, double value) {
      owner_.column_[static_cast<std::size_t>(end_)] = column;
      owner_.value_[static_cast<std::size_t>(end_)] = value;
      ++end_;
    }
    int size() const { return end_ - begin_; }
    double& value(int entry) { return owner_.value_[static_cast<std::size_t>(begin_ + entry)]; }  // entry < size()
    void close() { owner_.length_[static_cast<std::size_t>(row_)] = end_ - begin_; }

   private:
    CsrAssembler& owner_;
    int row_;
    int begin_, end_;
  };

  template <typename Bound>
  void start(int rows, Bound bound) {
    rows_ = rows;
    slot_start_.resize(static_cast<std::size_t>(rows) + 1);
    length_.resize(static_cast<std::size_t>(rows));
    slot_start_[0] = 0;
    for (int row = 0; row < rows; ++row) {
      slot_start_[static_cast<std::size_t>(row) + 1] = slot_start_[static_cast<std::size_t>(row)] + bound(row);
    }
    const auto capacity = static_cast<std::size_t>(slot_start_[static_cast<std::size_t>(rows)]);
    if (column_.size() < capacity) {
      column_.resize(capacity);
      value_.resize(capacity);
    }
  }
  RowWriter row(int row) { return RowWriter(*this, row); }
  void finish(CsrMatrix& matrix, bool diagonal_first);
  std::size_t held_bytes() const {  // the padded slots, bytes (capacities)
    return (slot_start_.capacity() + length_.capacity() + column_.capacity()) * sizeof(int) +
           value_.capacity() * sizeof(double);
  }

 private:
  int rows_ = 0;
  std::vector<int> slot_start_, length_, column_;
  std::vector<double> value_;
};

// Assembles a CsrMatrix row by row, rows in parallel, straight into the matrix's own arrays
// when the caller can count every row's entries beforehand (an upper bound that is exact but
// for rare entries the row drops: isph counts the unknowns among a particle's neighbours, and
// drops a pair only when its coefficient is exactly 0, two coincident particles). No padded
// copy of the matrix is kept beside it (CsrAssembler's slots: 12 bytes per bound entry).
//   assembler.start(matrix, rows);                  // matrix.row_start[r + 1] = 0
//   #pragma omp parallel for
//   for (int row ...) assembler.count(row, length); // the bound of row `row`
//   assembler.place(matrix);                        // prefix sums; sizes column and value
//   #pragma omp parallel for
//   for (int row ...) { auto writer = assembler.row(row); writer.add(column, value); ... writer.close(); }
//   assembler.finish(matrix, /*diagonal_first=*/true);
// A row longer than its count makes finish() throw std::logic_error (its entries past the
// count were not written; close() only records the length, as it runs inside the parallel
// loop, where an exception cannot leave); rows shorter than their count are closed up by finish() (sequentially, only
// in a step that has one). The entries and their order are those the writer received, as with CsrAssembler: the same
// matrix, bit for bit.
class CsrInPlaceAssembler {
 public:
  class RowWriter {
   public:
    RowWriter(CsrInPlaceAssembler& owner, int row)
        : owner_(owner),
          row_(row),
          begin_(owner.matrix_->row_start[static_cast<std::size_t>(row)]),
          end_(begin_),
          limit_(owner.matrix_->row_start[static_cast<std::size_t>(row) + 1]),
          column_(owner.matrix_->column.data()),
          value_(owner.matrix_->value.data()) {}
    void add(int column, double value) {
      if (end_ < limit_) {  // past the count: reported by finish()
        column_[end_] = column;
        value_[end_] = value;
      }
      ++end_;
    }
    int size() const { return end_ - begin_; }
    double& value(int entry) { return value_[begin_ + entry]; }  // entry < size()
    void close() { owner_.length_[static_cast<std::size_t>(row_)] = end_ - begin_; }

   private:
    CsrInPlaceAssembler& owner_;
    int row_;
    int begin_, end_, limit_;
    int* column_;
    double* value_;
  };

  void start(CsrMatrix& matrix, int rows);
  void count(int row, int length) { matrix_->row_start[static_cast<std::size_t>(row) + 1] = length; }
  void place(CsrMatrix& matrix);
  RowWriter row(int row) { return RowWriter(*this, row); }
  void finish(CsrMatrix& matrix, bool diagonal_first);
  std::size_t held_bytes() const { return length_.capacity() * sizeof(int); }

 private:
  CsrMatrix* matrix_ = nullptr;
  int rows_ = 0;
  std::vector<int> length_;  // entries written per row
};

// Deterministic parallel dot product: the sum is taken over fixed blocks of the index range
// whose partial sums are added in block order, so the result is the same, bit for bit, for
// any number of threads (the determinism tests compare 1 and 2 threads byte for byte).
double deterministic_dot(const double* a, const double* b, std::size_t n);

}  // namespace mps_lab
