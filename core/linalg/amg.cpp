#include "core/linalg/amg.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>

#include <omp.h>

#include "core/base/memory_bytes.hpp"
#include "core/io/checkpoint.hpp"

namespace mps_lab {

namespace {

// A coarsest level that stopped coarsening above this many rows is not factorised (dense LU
// is O(rows^3): 1500 rows = 2e9 flops); a few smoother applications stand in for the solve.
constexpr int kMaxDenseRows = 1500;
constexpr int kCoarsestFallbackSmoothings = 4;
// Levels with fewer rows run their loops on one thread. The V-cycle's loops share one parallel
// region, where a split costs a barrier (~0.25 us here) and splits pay from a few hundred rows:
// mps at 4.9e3 unknowns, whose second level has ~400 rows, solved 4-8 % faster with that level
// split than with the 4096 rows a loop needed when each had a region of its own (~0.6 us).
constexpr int kParallelRows = 256;
// Levels with fewer rows fuse the degree-1 pre-smoothing step with the residual
// (presmooth_with_residual), whose rows gather D^-1 rhs of their neighbours themselves: a barrier
// saved where the gathered vectors are in cache; above it the two plain loops (at 1e6 rows
// the fused loop's solve took 527-548 against 520 ms per step, two rounds; at 4.9e3 rows equal on
// one thread, 2.33-2.35 ms both). 2^16 rows: the level's vectors stay in a core's L2 (512 KB each).
constexpr int kFusedPresmoothMaxRows = 1 << 16;

// Aggregate markers during aggregation.
constexpr int kUnassigned = -2;
constexpr int kNoAggregate = -1;  // no strong neighbour: not on the coarse level

void resize_csr(CsrMatrix& matrix, int rows, std::size_t nonzeros) {
  matrix.rows = rows;
  resize_with_headroom(matrix.row_start, static_cast<std::size_t>(rows) + 1);
  resize_with_headroom(matrix.column, nonzeros);
  resize_with_headroom(matrix.value, nonzeros);
  matrix.diagonal_first = false;
}

// row_start[r + 1] holds the count of row r on entry; prefix sums on exit. Returns the total.
std::size_t prefix_sum_counts(std::vector<int>& row_start) {
  row_start[0] = 0;
  for (std::size_t r = 1; r < row_start.size(); ++r) row_start[r] += row_start[r - 1];
  return static_cast<std::size_t>(row_start.back());
}

double diagonal_of_row(const CsrMatrix& matrix, int row) {
  const int begin = matrix.row_start[row];
  const int end = matrix.row_start[row + 1];
  if (matrix.diagonal_first) return begin < end && matrix.column[begin] == row ? matrix.value[begin] : 0.0;
  for (int k = begin; k < end; ++k)
    if (matrix.column[k] == row) return matrix.value[k];
  return 0.0;
}

// Where a thread builds its contiguous range of rows of a result: thread 0's rows begin at entry
// 0 of the result, so it writes them there directly; every other thread into its scratch, copied
// into place once the row lengths are known. No copy of the thread-0 part is held (with two
// threads, half a result less in scratch).
struct RowBuffer {
  std::vector<int>& column;
  std::vector<double>& value;
  std::size_t growth_divisor;  // grow by size / this: the vectors are kept at their largest
  void ensure(std::size_t size) {
    if (column.size() >= size) return;
    resize_with_headroom(column, size + size / growth_divisor, growth_divisor);
    resize_with_headroom(value, size + size / growth_divisor, growth_divisor);
  }
};

// The result grows by 1/16 (its capacity is held with the hierarchy), a scratch by 1/4.
RowBuffer row_buffer(int thread, AmgThreadScratch& own, CsrMatrix& result) {
  return thread == 0 ? RowBuffer{result.column, result.value, 16} : RowBuffer{own.column, own.value, 4};
}

// After the barrier that follows the rows: the result sized (prefix sums of the counts in
// row_start[r + 1]), then every thread but 0 copies its rows [first_row, end_row) into place.
void place_thread_rows(int thread, int first_row, int end_row, const RowBuffer& buffer, CsrMatrix& result) {
#pragma omp single
  {
    const std::size_t nonzeros = prefix_sum_counts(result.row_start);
    result.column.resize(nonzeros);  // keeps thread 0's rows at the front
    result.value.resize(nonzeros);
  }  // implicit barrier
  if (thread == 0 || first_row >= end_row) return;
  const int destination = result.row_start[first_row];
  const int count = result.row_start[end_row] - destination;
  std::copy_n(buffer.column.data(), count, result.column.data() + destination);
  std::copy_n(buffer.value.data(), count, result.value.data() + destination);
}

// product = left * right. Rows are split into one contiguous range per thread; each thread
// computes its rows into its own buffer (one pass: no symbolic phase), then, after the row
// lengths are known, copies them into place. Every entry is summed in the order of left's row
// then right's rows, so the bits do not depend on the thread count. Columns appear in a row in
// the order they are first reached.
void multiply_sparse(const CsrMatrix& left, const CsrMatrix& right, int right_columns, CsrMatrix& product,
                     std::vector<AmgThreadScratch>& scratch) {
  const int rows = left.rows;
  product.rows = rows;
  product.diagonal_first = false;
  resize_with_headroom(product.row_start, static_cast<std::size_t>(rows) + 1);
  product.row_start[0] = 0;
#pragma omp parallel if (rows >= kParallelRows)
  {
    const int threads = omp_get_num_threads();
    const int thread = omp_get_thread_num();
    AmgThreadScratch& own = scratch[static_cast<std::size_t>(thread)];
    RowBuffer buffer = row_buffer(thread, own, product);
    const auto first_row = static_cast<int>(static_cast<long long>(rows) * thread / threads);
    const auto end_row = static_cast<int>(static_cast<long long>(rows) * (thread + 1) / threads);
    // position[c]: where column c sits in the buffer; before the current row's start: stale.
    own.position.assign(static_cast<std::size_t>(right_columns), -1);
    std::size_t used = 0;  // entries of the buffer in use (its vectors only grow)
    for (int r = first_row; r < end_row; ++r) {
      // At most the sum of the right rows' lengths: make room first, then write by index.
      std::size_t bound = 0;
      for (int k = left.row_start[r]; k < left.row_start[r + 1]; ++k)
        bound += static_cast<std::size_t>(right.row_start[left.column[k] + 1] - right.row_start[left.column[k]]);
      buffer.ensure(used + bound);
      int* columns = buffer.column.data();
      double* values = buffer.value.data();
      int* position = own.position.data();
      const auto row_begin = static_cast<int>(used);
      auto next = row_begin;
      for (int k = left.row_start[r]; k < left.row_start[r + 1]; ++k) {
        const int middle = left.column[k];
        const double left_value = left.value[k];
        for (int l = right.row_start[middle]; l < right.row_start[middle + 1]; ++l) {
          const int c = right.column[l];
          const double term = left_value * right.value[l];
          if (position[c] < row_begin) {
            position[c] = next;
            columns[next] = c;
            values[next] = term;
            ++next;
          } else {
            values[position[c]] += term;
          }
        }
      }
      used = static_cast<std::size_t>(next);
      product.row_start[static_cast<std::size_t>(r) + 1] = next - row_begin;
    }
#pragma omp barrier
    place_thread_rows(thread, first_row, end_row, buffer, product);
  }
}

// transpose = matrix^T (matrix has `columns` columns); sequential counting sort, O(nonzeros).
void transpose_sparse(const CsrMatrix& matrix, int columns, CsrMatrix& transpose) {
  resize_csr(transpose, columns, matrix.nonzeros());
  std::fill(transpose.row_start.begin(), transpose.row_start.end(), 0);
  for (const int c : matrix.column) ++transpose.row_start[static_cast<std::size_t>(c) + 1];
  prefix_sum_counts(transpose.row_start);
  // Fill, using row_start[c] as the running insertion point, then shift back.
  for (int r = 0; r < matrix.rows; ++r) {
    for (int k = matrix.row_start[r]; k < matrix.row_start[r + 1]; ++k) {
      const int destination = transpose.row_start[matrix.column[k]]++;
      transpose.column[destination] = r;
      transpose.value[destination] = matrix.value[k];
    }
  }
  for (int c = columns; c > 0; --c) transpose.row_start[c] = transpose.row_start[c - 1];
  transpose.row_start[0] = 0;
}

}  // namespace

AmgPreconditioner::AmgPreconditioner(const AmgOptions& options) : options_(options) {
  if (!(options_.strength_threshold >= 0.0)) throw std::invalid_argument("AMG: strength_threshold must be >= 0");
  if (options_.smoother_sweeps < 1) throw std::invalid_argument("AMG: smoother_sweeps must be >= 1");
  if (!(options_.chebyshev_ratio > 1.0)) throw std::invalid_argument("AMG: chebyshev_ratio must be > 1");
  if (options_.coarsest_size < 1) throw std::invalid_argument("AMG: coarsest_size must be >= 1");
  if (options_.max_levels < 1) throw std::invalid_argument("AMG: max_levels must be >= 1");
  if (!(options_.coarse_correction_scaling > 0.0))
    throw std::invalid_argument("AMG: coarse_correction_scaling must be > 0");
}

const CsrMatrix& AmgPreconditioner::level_matrix(std::size_t level) const {
  return level == 0 ? *fine_matrix_ : levels_[level].matrix;
}

// The smoother's data of `level` for its matrix `a`: the inverse diagonal and the Gershgorin
// bound of rho(D^-1 A) (max is exact: deterministic), and the work vectors. The residual has one
// entry more than the rows, held at 0: a transfer of a refreshed hierarchy reads it for a base
// row without a current one (refresh()).
void AmgPreconditioner::prepare_smoother(std::size_t level, const CsrMatrix& a) {
  Level& current = levels_[level];
  const int rows = a.rows;
  resize_with_headroom(current.inverse_diagonal, static_cast<std::size_t>(rows));
  double bound = 0.0;
#pragma omp parallel for schedule(static) reduction(max : bound) if (rows >= kParallelRows)
  for (int r = 0; r < rows; ++r) {
    const double diagonal = diagonal_of_row(a, r);
    double absolute_sum = 0.0;
    for (int k = a.row_start[r]; k < a.row_start[r + 1]; ++k) absolute_sum += std::abs(a.value[k]);
    current.inverse_diagonal[r] = diagonal != 0.0 ? 1.0 / diagonal : 0.0;
    if (diagonal != 0.0) bound = std::max(bound, absolute_sum / std::abs(diagonal));
  }
  current.spectral_bound = bound > 0.0 ? bound : 1.0;
  size_work_vectors(level, static_cast<std::size_t>(rows));
}

// The cycle's work vectors of `level` for `rows` rows. The finest level's right-hand side and
// solution are the caller's (apply): none kept; a coarse level of the W-cycle keeps its second
// cycle's two vectors (repeat_cycle).
void AmgPreconditioner::size_work_vectors(std::size_t level, std::size_t rows) {
  Level& current = levels_[level];
  resize_with_headroom(current.rhs, level == 0 ? 0 : rows);
  resize_with_headroom(current.solution, level == 0 ? 0 : rows);
  assign_with_headroom(current.residual, rows + 1, 0.0);
  resize_with_headroom(current.direction, rows);
  const bool repeated =
      level > 0 && options_.coarse_cycles > 1 && rows >= static_cast<std::size_t>(options_.coarse_cycle_min_rows);
  resize_with_headroom(current.second_rhs, repeated ? rows : 0);
  resize_with_headroom(current.second_solution, repeated ? rows : 0);
}

void AmgPreconditioner::setup(const CsrMatrix& matrix) {
  fine_matrix_ = &matrix;
  refreshed_ = false;
  const auto threads = static_cast<std::size_t>(std::max(1, omp_get_max_threads()));
  if (thread_scratch_.size() < threads) thread_scratch_.resize(threads);
  level_count_ = 0;
  for (std::size_t level = 0;; ++level) {
    if (levels_.size() < level + 2) levels_.resize(level + 2);  // this level and the next
    const CsrMatrix& a = level_matrix(level);
    const int rows = a.rows;
    prepare_smoother(level, a);
    level_count_ = level + 1;
    if (rows <= options_.coarsest_size || static_cast<int>(level) + 1 >= options_.max_levels) break;
    build_level(level);
    if (levels_[level + 1].matrix.rows == 0 || levels_[level + 1].matrix.rows >= rows) break;
  }
  factorise_coarsest();
  base_rows_ = matrix.rows;
}

void AmgPreconditioner::refresh(const CsrMatrix& matrix, std::vector<int>& base_row_of_row) {
  if (level_count_ == 0) throw std::logic_error("AmgPreconditioner::refresh before setup");
  if (base_row_of_row.size() != static_cast<std::size_t>(matrix.rows))
    throw std::logic_error("AmgPreconditioner::refresh: one base row per row expected");
  fine_matrix_ = &matrix;
  if (level_count_ == 1) {  // a single level: the direct solve must be of this matrix
    setup(matrix);
    return;
  }
  refreshed_ = true;
  prepare_smoother(0, matrix);
  base_row_of_row_.swap(base_row_of_row);
  const int rows = matrix.rows;
  row_of_base_row_.assign(static_cast<std::size_t>(base_rows_), rows);  // rows: the residual's 0 entry
  for (int r = 0; r < rows; ++r) {
    const int base = base_row_of_row_[static_cast<std::size_t>(r)];
    if (base >= 0 && base < base_rows_) row_of_base_row_[static_cast<std::size_t>(base)] = r;
  }
}

namespace {

// Step 1 of a level: strength of connection (Vaněk, Mandel & Brezina 1996): a_rc is strong
// when |a_rc| >= theta sqrt(|a_rr a_cc|); strong[k] per entry, 0 on the diagonal. Also the
// filtered diagonal d_F = a_rr + (sum of weak a_rc) and returns the Gershgorin bound of
// D_F^-1 A_F for the prolongator smoothing.
double mark_strong_connections(const CsrMatrix& a, const std::vector<double>& inverse_diagonal, double theta,
                               std::vector<char>& strong, std::vector<double>& filtered_diagonal) {
  const int rows = a.rows;
  const double theta_squared = theta * theta;
  resize_with_headroom(strong, a.nonzeros());
  double filtered_bound = 0.0;
#pragma omp parallel for schedule(static) reduction(max : filtered_bound) if (rows >= kParallelRows)
  for (int r = 0; r < rows; ++r) {
    const double inverse_r = inverse_diagonal[r];
    const double diagonal_r = inverse_r != 0.0 ? 1.0 / inverse_r : 0.0;
    double weak_sum = 0.0, strong_absolute_sum = 0.0;
    for (int k = a.row_start[r]; k < a.row_start[r + 1]; ++k) {
      const int c = a.column[k];
      if (c == r) {
        strong[k] = 0;
        continue;
      }
      // |a_rc| >= theta sqrt(|a_rr a_cc|)  <=>  a_rc^2 |a_rr^-1 a_cc^-1| >= theta^2 (branch-free:
      // irregular particle patterns defeat the branch predictor)
      const double value = a.value[k];
      const double normalised = value * value * std::abs(inverse_r * inverse_diagonal[c]);
      const bool is_strong = normalised >= theta_squared && value != 0.0;
      strong[k] = static_cast<char>(is_strong);
      const double strong_part = is_strong ? 1.0 : 0.0;
      strong_absolute_sum += strong_part * std::abs(value);
      weak_sum += (1.0 - strong_part) * value;
    }
    double filtered = diagonal_r + weak_sum;
    if (!(filtered * diagonal_r > 0.0)) filtered = diagonal_r;  // lumping must not flip the sign
    filtered_diagonal[r] = filtered;
    if (filtered != 0.0) filtered_bound = std::max(filtered_bound, 1.0 + strong_absolute_sum / std::abs(filtered));
  }
  return filtered_bound;
}

// Roots are visited in breadth-first order over the strong connections (restarting at the
// first unvisited row): aggregates then grow as a front, regular on a lattice, whatever the
// order of the unknowns (particles are not sorted); coarse rows inherit that locality.
void strong_breadth_first_order(const CsrMatrix& a, const std::vector<char>& strong, std::vector<int>& order,
                                std::vector<char>& visited) {
  const int rows = a.rows;
  order.resize(static_cast<std::size_t>(rows));
  visited.assign(static_cast<std::size_t>(rows), 0);
  std::size_t head = 0, tail = 0;
  for (int seed = 0; seed < rows; ++seed) {
    if (visited[seed]) continue;
    visited[seed] = 1;
    order[tail++] = seed;
    while (head < tail) {
      const int r = order[head++];
      for (int k = a.row_start[r]; k < a.row_start[r + 1]; ++k) {
        const int c = a.column[k];
        if (strong[k] && !visited[c]) {
          visited[c] = 1;
          order[tail++] = c;
        }
      }
    }
  }
}

// A new aggregate `id` of row r and its unassigned strong neighbours.
void form_aggregate(const CsrMatrix& a, const std::vector<char>& strong, int r, int id, std::vector<int>& aggregate) {
  aggregate[r] = id;
  for (int k = a.row_start[r]; k < a.row_start[r + 1]; ++k)
    if (strong[k] && aggregate[a.column[k]] == kUnassigned) aggregate[a.column[k]] = id;
}

// Pass 2: a leftover joins the pass-1 aggregate it is most strongly connected to (recorded
// as -3 - aggregate, so that only pass-1 aggregates are joined).
void join_strongest_aggregates(const CsrMatrix& a, const std::vector<char>& strong, std::vector<int>& aggregate) {
  for (int r = 0; r < a.rows; ++r) {
    if (aggregate[r] != kUnassigned) continue;
    double strongest = 0.0;
    int chosen = kUnassigned;
    for (int k = a.row_start[r]; k < a.row_start[r + 1]; ++k) {
      const int c = a.column[k];
      if (strong[k] && aggregate[c] >= 0 && std::abs(a.value[k]) > strongest) {
        strongest = std::abs(a.value[k]);
        chosen = aggregate[c];
      }
    }
    if (chosen >= 0) aggregate[r] = -3 - chosen;
  }
}

// Step 2: greedy aggregation (sequential, O(rows)): Vaněk, Mandel & Brezina 1996, section 5.
// aggregate[r] is r's coarse row, or kNoAggregate for a row without strong connections.
// Returns the number of aggregates.
int aggregate_rows(const CsrMatrix& a, const std::vector<char>& strong, std::vector<int>& aggregate,
                   std::vector<int>& order, std::vector<char>& visited) {
  const int rows = a.rows;
  aggregate.assign(static_cast<std::size_t>(rows), kUnassigned);
  for (int r = 0; r < rows; ++r) {
    bool any_strong = false;
    for (int k = a.row_start[r]; k < a.row_start[r + 1] && !any_strong; ++k) any_strong = strong[k] != 0;
    if (!any_strong) aggregate[r] = kNoAggregate;
  }
  int aggregates = 0;
  strong_breadth_first_order(a, strong, order, visited);
  // Pass 1: a root whose strong neighbours are all free takes them all.
  for (const int r : order) {
    if (aggregate[r] != kUnassigned) continue;
    bool all_free = true;
    for (int k = a.row_start[r]; k < a.row_start[r + 1] && all_free; ++k)
      if (strong[k] && aggregate[a.column[k]] >= 0) all_free = false;
    if (!all_free) continue;
    form_aggregate(a, strong, r, aggregates++, aggregate);
  }
  join_strongest_aggregates(a, strong, aggregate);
  // Pass 3: the rest form aggregates with their free strong neighbours.
  for (const int r : order) {
    if (aggregate[r] != kUnassigned) continue;
    form_aggregate(a, strong, r, aggregates++, aggregate);
  }
  for (int r = 0; r < rows; ++r)
    if (aggregate[r] <= -3) aggregate[r] = -3 - aggregate[r];
  return aggregates;
}

// Step 3: row r of P = (I - omega D_F^-1 A_F) P0 (or P0 when not smooth), at most (row length +
// 1) entries, written at `columns` / `values`; returns its length.
int prolongator_row(const CsrMatrix& a, const std::vector<char>& strong, const std::vector<int>& aggregate,
                    const std::vector<double>& filtered_diagonal, bool smooth, double omega, int r, int* columns,
                    double* values) {
  int count = 0;
  const int own = aggregate[r];
  if (own >= 0) {
    columns[0] = own;
    values[0] = 1.0 - omega;  // (I - omega D_F^-1 A_F) on the diagonal entry, d_F / d_F = 1
    count = 1;
    if (smooth) {
      const double factor = -omega / filtered_diagonal[r];
      for (int k = a.row_start[r]; k < a.row_start[r + 1]; ++k) {
        if (!strong[k]) continue;
        const int target = aggregate[a.column[k]];
        if (target < 0) continue;
        const double term = factor * a.value[k];
        int slot = 0;
        while (slot < count && columns[slot] != target) ++slot;
        if (slot == count) {
          columns[count] = target;
          values[count] = term;
          ++count;
        } else {
          values[slot] += term;
        }
      }
    }
  }
  return count;
}

// Steps 3-4: the prolongator's rows, one contiguous range of rows per thread computed into the
// thread's scratch (as multiply_sparse: no padded copy of P is kept), then copied into place.
void build_prolongator(const CsrMatrix& a, const std::vector<char>& strong, const std::vector<int>& aggregate,
                       const std::vector<double>& filtered_diagonal, bool smooth, double omega, CsrMatrix& prolongator,
                       std::vector<AmgThreadScratch>& scratch) {
  const int rows = a.rows;
  prolongator.rows = rows;
  prolongator.diagonal_first = false;
  resize_with_headroom(prolongator.row_start, static_cast<std::size_t>(rows) + 1);
  prolongator.row_start[0] = 0;
#pragma omp parallel if (rows >= kParallelRows)
  {
    const int threads = omp_get_num_threads();
    const int thread = omp_get_thread_num();
    RowBuffer buffer = row_buffer(thread, scratch[static_cast<std::size_t>(thread)], prolongator);
    const auto first_row = static_cast<int>(static_cast<long long>(rows) * thread / threads);
    const auto end_row = static_cast<int>(static_cast<long long>(rows) * (thread + 1) / threads);
    std::size_t used = 0;
    for (int r = first_row; r < end_row; ++r) {
      buffer.ensure(used + static_cast<std::size_t>(a.row_start[r + 1] - a.row_start[r]) + 1);
      const int count = prolongator_row(a, strong, aggregate, filtered_diagonal, smooth, omega, r,
                                        buffer.column.data() + used, buffer.value.data() + used);
      used += static_cast<std::size_t>(count);
      prolongator.row_start[static_cast<std::size_t>(r) + 1] = count;
    }
#pragma omp barrier
    place_thread_rows(thread, first_row, end_row, buffer, prolongator);
  }
}

}  // namespace

void AmgPreconditioner::build_level(std::size_t level) {
  Level& current = levels_[level];
  Level& next = levels_[level + 1];
  const CsrMatrix& a = level_matrix(level);
  const int rows = a.rows;

  // 1. Strength of connection, the filtered diagonal and its Gershgorin bound.
  const double theta = options_.strength_threshold * std::pow(0.5, static_cast<double>(level));
  std::vector<double>& filtered_diagonal = current.residual;  // scratch until apply
  const double filtered_bound = mark_strong_connections(a, current.inverse_diagonal, theta, strong_, filtered_diagonal);

  // 2. Greedy aggregation.
  const int coarse_rows = aggregate_rows(a, strong_, aggregate_, visit_order_, visited_);
  if (coarse_rows == 0 || coarse_rows >= rows) {  // nothing to coarsen: this level is the coarsest
    next.matrix.clear_rows(0);
    return;
  }

  // 3-4. Prolongator P = (I - omega D_F^-1 A_F) P0 (or P0), each thread's rows in its scratch,
  // then copied into place.
  CsrMatrix& prolongator = current.prolongator;
  const bool smooth = options_.smooth_prolongator;
  const double omega = smooth ? (4.0 / 3.0) / std::max(filtered_bound, 1.0) : 0.0;
  build_prolongator(a, strong_, aggregate_, filtered_diagonal, smooth, omega, prolongator, thread_scratch_);

  // 5. R = P^T and the Galerkin product A_c = R (A P).
  transpose_sparse(prolongator, coarse_rows, current.restriction);
  multiply_sparse(a, prolongator, coarse_rows, product_, thread_scratch_);
  multiply_sparse(current.restriction, product_, coarse_rows, next.matrix, thread_scratch_);
}

void AmgPreconditioner::factorise_coarsest() {
  const CsrMatrix& a = level_matrix(level_count_ - 1);
  const int n = a.rows;
  if (n > kMaxDenseRows) {
    coarsest_factors_.clear();
    return;
  }
  const auto size = static_cast<std::size_t>(n);
  coarsest_factors_.assign(size * size, 0.0);
  coarsest_work_.resize(size);
  double* lu = coarsest_factors_.data();
  double largest_diagonal = 0.0;
  for (int r = 0; r < n; ++r)
    for (int k = a.row_start[r]; k < a.row_start[r + 1]; ++k) {
      lu[static_cast<std::size_t>(r) * size + static_cast<std::size_t>(a.column[k])] += a.value[k];
      if (a.column[k] == r) largest_diagonal = std::max(largest_diagonal, std::abs(a.value[k]));
    }
  // LU without pivoting (Doolittle, in place). A pivot below 1e-12 of the largest diagonal
  // (a singular block) is set to 0 and its column is not eliminated; the solve zeroes it.
  const double tiny = 1e-12 * largest_diagonal;
  for (std::size_t p = 0; p < size; ++p) {
    double& pivot = lu[p * size + p];
    if (!(std::abs(pivot) > tiny)) {
      pivot = 0.0;
      for (std::size_t i = p + 1; i < size; ++i) lu[i * size + p] = 0.0;
      continue;
    }
    for (std::size_t i = p + 1; i < size; ++i) {
      const double multiplier = lu[i * size + p] / pivot;
      lu[i * size + p] = multiplier;
      if (multiplier == 0.0) continue;
      for (std::size_t j = p + 1; j < size; ++j) lu[i * size + j] -= multiplier * lu[p * size + j];
    }
  }
}

// The V-cycle runs in the team of the caller's parallel region (apply_in_team: every thread
// calls it; the Krylov iterations run in one region) or in one region of its own (apply). Each
// loop of a level of kParallelRows rows or more is an orphaned worksharing construct split among
// the threads, with its barrier at the end. The levels below that size are cycled by one thread
// of the team inside a single `single` (Sharing::serial below it: plain loops), so they cost the
// team one barrier per cycle together, where a `single` per loop cost one per loop (six per
// level). The rows' results do not depend on the split, so the bits do not depend on the thread
// count.
namespace {

template <typename Body>
void for_rows(int rows, AmgPreconditioner::Sharing sharing, Body&& body) {
  if (sharing == AmgPreconditioner::Sharing::serial) {
    for (int r = 0; r < rows; ++r) body(r);
  } else if (rows >= kParallelRows) {
#pragma omp for schedule(static)
    for (int r = 0; r < rows; ++r) body(r);
  } else {
#pragma omp single
    for (int r = 0; r < rows; ++r) body(r);
  }
}

}  // namespace

void AmgPreconditioner::solve_coarsest(const double* rhs, double* solution, Sharing sharing) const {
  const std::size_t level = level_count_ - 1;
  const CsrMatrix& a = level_matrix(level);
  const auto size = static_cast<std::size_t>(a.rows);
  if (coarsest_factors_.size() != size * size) {  // too large to factorise: smoothing only
    smooth(level, rhs, solution, true, sharing);
    for (int i = 1; i < kCoarsestFallbackSmoothings; ++i) smooth(level, rhs, solution, false, sharing);
    return;
  }
  if (sharing == Sharing::serial) {
    substitute_coarsest(rhs, solution);
    return;
  }
#pragma omp single
  substitute_coarsest(rhs, solution);
}

// The dense LU factors' forward and back substitution, by the calling thread.
void AmgPreconditioner::substitute_coarsest(const double* rhs, double* solution) const {
  const auto size = static_cast<std::size_t>(level_matrix(level_count_ - 1).rows);
  const double* lu = coarsest_factors_.data();
  for (std::size_t i = 0; i < size; ++i) {
    double sum = rhs[i];
    for (std::size_t j = 0; j < i; ++j) sum -= lu[i * size + j] * solution[j];
    solution[i] = sum;
  }
  for (std::size_t i = size; i-- > 0;) {
    const double pivot = lu[i * size + i];
    if (pivot == 0.0) {
      solution[i] = 0.0;
      continue;
    }
    double sum = solution[i];
    for (std::size_t j = i + 1; j < size; ++j) sum -= lu[i * size + j] * solution[j];
    solution[i] = sum / pivot;
  }
}

namespace {

// rhs[r] - (A solution)_r.
inline double residual_row(const CsrMatrix& a, const double* rhs, const double* solution, int r) {
  double product = 0.0;
  for (int k = a.row_start[r]; k < a.row_start[r + 1]; ++k) product += a.value[k] * solution[a.column[k]];
  return rhs[r] - product;
}

}  // namespace

// 1/theta: the first Chebyshev step's scale, theta the centre of [rho / ratio, rho].
double AmgPreconditioner::chebyshev_inverse_centre(const Level& current) const {
  const double upper = current.spectral_bound;
  const double lower = upper / options_.chebyshev_ratio;
  return 1.0 / (0.5 * (upper + lower));
}

// The degree-1 Chebyshev smoother (the default) is one step x += D^-1 (rhs - A x) / theta, which
// the cycle fuses with the loop next to it (presmooth_with_residual, postsmooth_from).
bool AmgPreconditioner::single_step_smoother() const {
  return options_.smoother == AmgSmoother::chebyshev && options_.smoother_sweeps == 1;
}

// Smoother for A x = rhs on `level`: a Chebyshev polynomial in D^-1 A on [rho / ratio, rho]
// (the three-term recurrence of Saad, Iterative Methods for Sparse Linear Systems, 2nd ed.,
// algorithm 12.1, preconditioned by D), or damped Jacobi. zero_initial: solution starts at 0
// (its content is ignored and the first product with A is skipped). Called by the team.
void AmgPreconditioner::smooth(std::size_t level, const double* rhs, double* solution, bool zero_initial,
                               Sharing sharing) const {
  const Level& current = levels_[level];
  const CsrMatrix& a = level_matrix(level);
  const int rows = a.rows;
  const double* inverse_diagonal = current.inverse_diagonal.data();
  double* scaled_residual = current.residual.data();
  double* direction = current.direction.data();
  const double upper = current.spectral_bound;
  const int steps = options_.smoother_sweeps;

  if (options_.smoother == AmgSmoother::damped_jacobi) {
    const double weight = (4.0 / 3.0) / upper;
    for (int step = 0; step < steps; ++step) {
      if (zero_initial && step == 0) {  // x = w D^-1 rhs
        for_rows(rows, sharing, [&](int r) { solution[r] = weight * (inverse_diagonal[r] * rhs[r]); });
        continue;
      }
      // scaled_residual = D^-1 (rhs - A x) for every row first (x is read by the neighbours' rows).
      for_rows(rows, sharing,
               [&](int r) { scaled_residual[r] = inverse_diagonal[r] * residual_row(a, rhs, solution, r); });
      for_rows(rows, sharing, [&](int r) { solution[r] += weight * scaled_residual[r]; });
    }
    return;
  }

  const double lower = upper / options_.chebyshev_ratio;
  const double half_width = 0.5 * (upper - lower);  // delta
  const double sigma = 0.5 * (upper + lower) / half_width;
  double rho_old = 1.0 / sigma;
  const double inverse_centre = chebyshev_inverse_centre(current);
  if (zero_initial) {  // d = D^-1 rhs / theta, x = d: one pass
    for_rows(rows, sharing, [&](int r) {
      direction[r] = inverse_centre * (inverse_diagonal[r] * rhs[r]);
      solution[r] = direction[r];
    });
  } else {
    for_rows(rows, sharing,
             [&](int r) { scaled_residual[r] = inverse_diagonal[r] * residual_row(a, rhs, solution, r); });
    for_rows(rows, sharing, [&](int r) {
      direction[r] = inverse_centre * scaled_residual[r];
      solution[r] += direction[r];
    });
  }
  for (int step = 1; step < steps; ++step) {
    const double rho_new = 1.0 / (2.0 * sigma - rho_old);
    const double keep = rho_new * rho_old;
    const double push = 2.0 * rho_new / half_width;
    for_rows(rows, sharing,
             [&](int r) { scaled_residual[r] = inverse_diagonal[r] * residual_row(a, rhs, solution, r); });
    for_rows(rows, sharing, [&](int r) {
      direction[r] = keep * direction[r] + push * scaled_residual[r];
      solution[r] += direction[r];
    });
    rho_old = rho_new;
  }
}

// coarse_rhs = R residual. `mapped` (a refreshed finest level): R's columns are the base rows,
// each read from its current row (row_of_base_row_; a base row without one reads the residual's
// zero entry past its rows). The work is R's nonzeros, about one per fine row: split as the fine
// level is (a coarse count of ~400 at 4e3 fine rows ran on one thread while the other waited).
void AmgPreconditioner::restrict_residual(const Level& current, const double* residual, bool mapped, int fine_rows,
                                          double* coarse_rhs, Sharing sharing) const {
  const CsrMatrix& restriction = current.restriction;
  const int coarse_rows = restriction.rows;
  const int* row_of_base = row_of_base_row_.data();
  const auto restrict_row = [&](int c) {
    double sum = 0.0;
    if (mapped) {
      for (int k = restriction.row_start[c]; k < restriction.row_start[c + 1]; ++k)
        sum += restriction.value[k] * residual[row_of_base[restriction.column[k]]];
    } else {
      for (int k = restriction.row_start[c]; k < restriction.row_start[c + 1]; ++k)
        sum += restriction.value[k] * residual[restriction.column[k]];
    }
    coarse_rhs[c] = sum;
  };
  if (sharing == Sharing::team && fine_rows >= kParallelRows) {
#pragma omp for schedule(static)
    for (int c = 0; c < coarse_rows; ++c) restrict_row(c);
  } else {
    for_rows(coarse_rows, sharing, restrict_row);
  }
}

// prolonged = solution + scaling P coarse. `mapped`: row r takes P's row of its base row
// (base_row_of_row_), none when it has none (a row new since the setup is left to the smoother).
// `prolonged` may be `solution` (in place).
void AmgPreconditioner::prolong_correction(const Level& current, const double* coarse, bool mapped, int rows,
                                           const double* solution, double* prolonged, Sharing sharing) const {
  const CsrMatrix& p = current.prolongator;
  const double scaling = options_.coarse_correction_scaling;
  const int* base_of = base_row_of_row_.data();
  for_rows(rows, sharing, [&](int r) {
    const int source = mapped ? base_of[r] : r;
    if (source < 0) {
      prolonged[r] = solution[r];
      return;
    }
    double correction = 0.0;
    for (int k = p.row_start[source]; k < p.row_start[source + 1]; ++k) correction += p.value[k] * coarse[p.column[k]];
    prolonged[r] = solution[r] + scaling * correction;
  });
}

// The degree-1 pre-smoothing step from zero, x = D^-1 rhs / theta, and the residual rhs - A x
// in one loop: each row computes its neighbours' x itself (the same product, so the same bits as
// a loop for x and one for the residual, without the barrier between them).
void AmgPreconditioner::presmooth_with_residual(std::size_t level, const double* rhs, double* solution,
                                                double* residual, Sharing sharing) const {
  const Level& current = levels_[level];
  const CsrMatrix& a = level_matrix(level);
  const double* inverse_diagonal = current.inverse_diagonal.data();
  const double inverse_centre = chebyshev_inverse_centre(current);
  for_rows(a.rows, sharing, [&](int r) {
    solution[r] = inverse_centre * (inverse_diagonal[r] * rhs[r]);
    double product = 0.0;
    for (int k = a.row_start[r]; k < a.row_start[r + 1]; ++k) {
      const int c = a.column[k];
      product += a.value[k] * (inverse_centre * (inverse_diagonal[c] * rhs[c]));
    }
    residual[r] = rhs[r] - product;
  });
}

// The degree-1 post-smoothing step x = y + D^-1 (rhs - A y) / theta from the prolonged y, kept
// apart from x so that each row reads its neighbours' y while the others write x: one loop where
// smoothing in place needs two (the scaled residual of every row, then the update).
void AmgPreconditioner::postsmooth_from(std::size_t level, const double* rhs, const double* prolonged, double* solution,
                                        Sharing sharing) const {
  const Level& current = levels_[level];
  const CsrMatrix& a = level_matrix(level);
  const double* inverse_diagonal = current.inverse_diagonal.data();
  const double inverse_centre = chebyshev_inverse_centre(current);
  for_rows(a.rows, sharing, [&](int r) {
    solution[r] = prolonged[r] + inverse_centre * (inverse_diagonal[r] * residual_row(a, rhs, prolonged, r));
  });
}

// One V-cycle from `level` down. With the single-step smoother (the default) a level costs the
// team four loops: the pre-smoothing step with the residual (two loops from
// kFusedPresmoothMaxRows rows on), the restriction, the prolongation into the level's
// `direction`, and the post-smoothing step from it; otherwise six. A level
// below kParallelRows rows and all beneath it are cycled by one thread (one `single`).
void AmgPreconditioner::cycle(std::size_t level, const double* rhs, double* solution, Sharing sharing) const {
  if (level + 1 == level_count_) {
    solve_coarsest(rhs, solution, sharing);
    return;
  }
  const Level& current = levels_[level];
  const CsrMatrix& a = level_matrix(level);
  const int rows = a.rows;
  if (sharing == Sharing::team && rows < kParallelRows) {
#pragma omp single
    cycle(level, rhs, solution, Sharing::serial);
    return;
  }
  const Level& next = levels_[level + 1];
  const int next_rows = level_matrix(level + 1).rows;
  const bool mapped = level == 0 && refreshed_;
  double* residual = current.residual.data();
  const bool fused = single_step_smoother();
  if (fused && rows < kFusedPresmoothMaxRows) {
    presmooth_with_residual(level, rhs, solution, residual, sharing);
  } else {
    smooth(level, rhs, solution, true, sharing);
    for_rows(rows, sharing, [&](int r) { residual[r] = residual_row(a, rhs, solution, r); });
  }
  restrict_residual(current, residual, mapped, rows, next.rhs.data(), sharing);
  cycle(level + 1, next.rhs.data(), next.solution.data(), sharing);
  if (options_.coarse_cycles > 1 && level + 2 < level_count_ && next_rows >= options_.coarse_cycle_min_rows)
    repeat_cycle(level + 1, sharing);
  if (fused) {
    double* prolonged = current.direction.data();
    prolong_correction(current, next.solution.data(), mapped, rows, solution, prolonged, sharing);
    postsmooth_from(level, rhs, prolonged, solution, sharing);
  } else {
    prolong_correction(current, next.solution.data(), mapped, rows, solution, solution, sharing);
    smooth(level, rhs, solution, false, sharing);
  }
}

// The W-cycle's second cycle of a coarse `level` (coarse_cycles 2), after its first one left its
// solution in levels_[level].solution: the residual rhs - A solution is cycled and the
// correction added.
void AmgPreconditioner::repeat_cycle(std::size_t level, Sharing sharing) const {
  const Level& current = levels_[level];
  const CsrMatrix& a = level_matrix(level);
  const double* rhs = current.rhs.data();
  double* solution = current.solution.data();
  double* residual = current.second_rhs.data();
  double* correction = current.second_solution.data();
  for_rows(a.rows, sharing, [&](int r) { residual[r] = residual_row(a, rhs, solution, r); });
  cycle(level, residual, correction, sharing);
  for_rows(a.rows, sharing, [&](int r) { solution[r] += correction[r]; });
}

void AmgPreconditioner::apply_in_team(const double* residual, double* result) const {
  if (fine_matrix_ == nullptr) throw std::logic_error("AmgPreconditioner::apply before setup");
  if (fine_matrix_->rows == 0) return;
  cycle(0, residual, result, Sharing::team);
}

void AmgPreconditioner::apply(const double* residual, double* result) const {
  if (fine_matrix_ == nullptr) throw std::logic_error("AmgPreconditioner::apply before setup");
  if (fine_matrix_->rows == 0) return;
    // One region for the whole cycle (its loops' barriers instead of a region per loop); a level
    // below kParallelRows rows is done by one thread of it.
#pragma omp parallel if (fine_matrix_->rows >= kParallelRows)
  cycle(0, residual, result, Sharing::team);
}

namespace {

std::vector<std::uint32_t> as_u32s(const std::vector<int>& values) {
  return std::vector<std::uint32_t>(values.begin(), values.end());
}

std::vector<int> as_ints(const std::vector<std::uint32_t>& values) {
  return std::vector<int>(values.begin(), values.end());
}

void write_csr(CheckpointWriter& out, const CsrMatrix& matrix) {
  out.write_int(matrix.rows);
  out.write_bool(matrix.diagonal_first);
  out.write_u32s(as_u32s(matrix.row_start));
  out.write_u32s(as_u32s(matrix.column));
  out.write_doubles(matrix.value);
}

void read_csr(CheckpointReader& in, CsrMatrix& matrix) {
  matrix.rows = static_cast<int>(in.read_int());
  matrix.diagonal_first = in.read_bool();
  matrix.row_start = as_ints(in.read_u32s());
  matrix.column = as_ints(in.read_u32s());
  matrix.value = in.read_doubles();
  if (matrix.row_start.size() != static_cast<std::size_t>(matrix.rows) + 1 ||
      matrix.column.size() != matrix.value.size() ||
      static_cast<std::size_t>(matrix.row_start.back()) != matrix.column.size()) {
    in.fail("an AMG level's matrix is inconsistent");
  }
}

}  // namespace

void AmgPreconditioner::save_state(CheckpointWriter& out) const {
  out.write_size(level_count_);
  out.write_int(base_rows_);
  for (std::size_t level = 0; level < level_count_; ++level) {
    const Level& l = levels_[level];
    const bool coarsest = level + 1 == level_count_;
    if (level > 0) {
      write_csr(out, l.matrix);
      out.write_doubles(l.inverse_diagonal);
      out.write_double(l.spectral_bound);
    }
    if (!coarsest) {
      write_csr(out, l.prolongator);
      write_csr(out, l.restriction);
    }
  }
  out.write_doubles(coarsest_factors_);
}

void AmgPreconditioner::restore_state(CheckpointReader& in) {
  level_count_ = in.read_size();
  base_rows_ = static_cast<int>(in.read_int());
  if (level_count_ > static_cast<std::size_t>(options_.max_levels)) in.fail("too many AMG levels");
  if (levels_.size() < level_count_ + 1) levels_.resize(level_count_ + 1);
  for (std::size_t level = 0; level < level_count_; ++level) {
    Level& l = levels_[level];
    const bool coarsest = level + 1 == level_count_;
    if (level > 0) {
      read_csr(in, l.matrix);
      l.inverse_diagonal = in.read_doubles();
      l.spectral_bound = in.read_double();
      size_work_vectors(level, static_cast<std::size_t>(l.matrix.rows));
    }
    if (!coarsest) {
      read_csr(in, l.prolongator);
      read_csr(in, l.restriction);
    }
  }
  coarsest_factors_ = in.read_doubles();
  const std::size_t coarsest_rows =
      level_count_ > 1 ? static_cast<std::size_t>(levels_[level_count_ - 1].matrix.rows) : 0;
  coarsest_work_.resize(coarsest_rows);
  const auto threads = static_cast<std::size_t>(std::max(1, omp_get_max_threads()));
  if (thread_scratch_.size() < threads) thread_scratch_.resize(threads);
  fine_matrix_ = nullptr;  // set by the next setup() or refresh()
  refreshed_ = false;
}

std::vector<AmgLevelInfo> AmgPreconditioner::levels() const {
  std::vector<AmgLevelInfo> info;
  for (std::size_t level = 0; level < level_count_; ++level) {
    const CsrMatrix& a = level_matrix(level);
    const bool coarsest = level + 1 == level_count_;
    info.push_back({a.rows, a.nonzeros(), coarsest ? std::size_t{0} : levels_[level].prolongator.nonzeros()});
  }
  return info;
}

MemoryBreakdown AmgPreconditioner::memory_breakdown() const {
  // Level 0 structure by structure (its matrix is the caller's), the coarser levels together.
  MemoryBreakdown out;
  std::size_t coarse = 0;
  for (std::size_t level = 0; level < levels_.size(); ++level) {
    const Level& l = levels_[level];
    const std::size_t transfer = l.prolongator.held_bytes() + l.restriction.held_bytes();
    const std::size_t vectors = held_bytes(l.inverse_diagonal, l.rhs, l.solution, l.residual, l.direction) +
                                held_bytes(l.second_rhs, l.second_solution);
    if (level > 0) {
      coarse += l.matrix.held_bytes() + transfer + vectors;
      continue;
    }
    out.emplace_back("level0.prolongator_restriction", transfer);
    out.emplace_back("level0.vectors", vectors);
  }
  out.emplace_back("coarse_levels", coarse);
  out.emplace_back("galerkin_scratch", product_.held_bytes());  // A P of the finest level, kept for the next setup
  out.emplace_back("aggregation_scratch", held_bytes(aggregate_, strong_, visit_order_, visited_));
  out.emplace_back("reuse_rows", held_bytes(base_row_of_row_, row_of_base_row_));  // refresh()
  std::size_t scratch = 0;
  for (const auto& own : thread_scratch_) scratch += held_bytes(own.column, own.position, own.value);
  out.emplace_back("product_thread_scratch", scratch);
  out.emplace_back("coarsest_factors", held_bytes(coarsest_factors_, coarsest_work_));
  return out;
}

double AmgPreconditioner::operator_complexity() const {
  if (level_count_ == 0 || level_matrix(0).nonzeros() == 0) return 1.0;
  double total = 0.0;
  for (std::size_t level = 0; level < level_count_; ++level) {
    const CsrMatrix& a = level_matrix(level);
    const bool dense = level + 1 == level_count_ && level > 0 && !coarsest_factors_.empty();
    total += dense ? static_cast<double>(a.rows) * static_cast<double>(a.rows) : static_cast<double>(a.nonzeros());
  }
  return total / static_cast<double>(level_matrix(0).nonzeros());
}

}  // namespace mps_lab
