#include "core/linalg/krylov.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "core/base/memory_bytes.hpp"

namespace mps_lab {

namespace {

// Rows per block of the fused loops: each block's partial sums are formed in row order and the
// blocks' partials are added in block order, whatever thread ran the block. The blocks are
// shared out statically, so small blocks balance the threads on small systems: mps's pressure
// system of 4,140 unknowns, 2 threads, set-up excluded: 1.2-1.3 ms with 256 rows per block
// against 2.2 ms with 1024 (5 blocks split 3 : 2; docs/performance.md, "A degree-1 smoother").
constexpr int kBlockRows = 256;

int block_count(int rows) { return (rows + kBlockRows - 1) / kBlockRows; }

struct BlockRange {
  int begin, end;
};
BlockRange block_range(int block, int rows) { return {block * kBlockRows, std::min(rows, (block + 1) * kBlockRows)}; }

double sum_in_order(const double* partial, int blocks) {
  double total = 0.0;
  for (int b = 0; b < blocks; ++b) total += partial[static_cast<std::size_t>(b)];
  return total;
}

void ensure_size(std::vector<double>& vector, int rows) {
  if (vector.size() < static_cast<std::size_t>(rows)) resize_with_headroom(vector, static_cast<std::size_t>(rows));
}

// sum_k value[k] x[column[k]] over [begin, end): two partial sums, which halves the chain of
// dependent additions (a row has ~13-25 entries; the product is bound by that latency).
inline double row_product(const double* value, const int* column, const double* x, int begin, int end) {
  double even = 0.0, odd = 0.0;
  int k = begin;
  for (; k + 1 < end; k += 2) {
    even += value[k] * x[column[k]];
    odd += value[k + 1] * x[column[k + 1]];
  }
  if (k < end) even += value[k] * x[column[k]];
  return even + odd;
}

// Two blocked sums at once: partial[b] and partial[blocks + b], each added in block order.
std::pair<double, double> sum_pairs_in_order(const double* partial, int blocks) {
  double first = 0.0, second = 0.0;
  for (int b = 0; b < blocks; ++b) {
    first += partial[static_cast<std::size_t>(b)];
    second += partial[static_cast<std::size_t>(blocks + b)];
  }
  return {first, second};
}

// The loops below come twice: "_in_team", an orphaned worksharing loop for the threads of the
// caller's region (the conjugate-gradient iterations run in one), which returns after its
// barrier with the block sums in `partial`; and a function with a region of its own that adds them.

// One pass over the rows of A x in fixed blocks: row_sum = (A x)_r is handed to
// visit(r, row_sum, first, second), which stores what it needs and adds the row's terms to
// two sums; the block sums go to partial[b] and partial[blocks + b] (partial holds 2 blocks
// entries) and are added in block order (the same bits for any thread count).
template <typename Visit>
void row_products_in_team(const CsrMatrix& matrix, const double* x, double* partial, Visit visit) {
  const int rows = matrix.rows;
  const int blocks = block_count(rows);
  const int* start = matrix.row_start.data();
  const int* column = matrix.column.data();
  const double* value = matrix.value.data();
#pragma omp for schedule(static)
  for (int b = 0; b < blocks; ++b) {
    const BlockRange range = block_range(b, rows);
    double first = 0.0, second = 0.0;
    for (int r = range.begin; r < range.end; ++r) {
      visit(r, row_product(value, column, x, start[r], start[r + 1]), first, second);
    }
    partial[b] = first;
    partial[blocks + b] = second;
  }
}

template <typename Visit>
std::pair<double, double> blocked_row_products(const CsrMatrix& matrix, const double* x, std::vector<double>& partial,
                                               Visit visit) {
#pragma omp parallel
  row_products_in_team(matrix, x, partial.data(), visit);
  return sum_pairs_in_order(partial.data(), block_count(matrix.rows));
}

// out = A x, shadow . out in partial's first blocks entries (both in one pass over the rows).
void multiply_dot_in_team(const CsrMatrix& matrix, const double* x, const double* shadow, double* out,
                          double* partial) {
  row_products_in_team(matrix, x, partial, [&](int r, double row_sum, double& sum, double&) {
    out[r] = row_sum;
    sum += shadow[r] * row_sum;
  });
}

// residual = rhs - A x, returns ||residual||^2.
double residual_norm2(const CsrMatrix& matrix, const double* rhs, const double* x, double* residual,
                      std::vector<double>& partial) {
  return blocked_row_products(matrix, x, partial,
                              [&](int r, double row_sum, double& sum, double&) {
                                const double difference = rhs[r] - row_sum;
                                residual[r] = difference;
                                sum += difference * difference;
                              })
      .first;
}

// a . b in partial's first blocks entries.
void dot_in_team(const double* a, const double* b, int rows, double* partial) {
  const int blocks = block_count(rows);
#pragma omp for schedule(static)
  for (int block = 0; block < blocks; ++block) {
    const BlockRange range = block_range(block, rows);
    double sum = 0.0;
    for (int r = range.begin; r < range.end; ++r) sum += a[r] * b[r];
    partial[block] = sum;
  }
}

double blocked_dot(const double* a, const double* b, int rows, std::vector<double>& partial) {
#pragma omp parallel
  dot_in_team(a, b, rows, partial.data());
  return sum_in_order(partial.data(), block_count(rows));
}

}  // namespace

// --- Jacobi ----------------------------------------------------------------------------------

void JacobiPreconditioner::setup(const CsrMatrix& matrix) {
  const int rows = matrix.rows;
  resize_with_headroom(inverse_diagonal_, static_cast<std::size_t>(rows));
#pragma omp parallel for schedule(static)
  for (int r = 0; r < rows; ++r) {
    double diagonal = 0.0;
    if (matrix.diagonal_first && matrix.row_start[r] < matrix.row_start[r + 1]) {
      if (matrix.column[matrix.row_start[r]] == r) diagonal = matrix.value[matrix.row_start[r]];
    } else {
      for (int k = matrix.row_start[r]; k < matrix.row_start[r + 1]; ++k) {
        if (matrix.column[k] == r) diagonal += matrix.value[k];
      }
    }
    inverse_diagonal_[static_cast<std::size_t>(r)] = diagonal != 0.0 ? 1.0 / diagonal : 1.0;
  }
}

void Preconditioner::apply_in_team(const double* residual, double* result) const {
#pragma omp single
  apply(residual, result);
}

void JacobiPreconditioner::apply(const double* residual, double* result) const {
#pragma omp parallel
  apply_in_team(residual, result);
}

void JacobiPreconditioner::apply_in_team(const double* residual, double* result) const {
  const auto rows = static_cast<int>(inverse_diagonal_.size());
  const double* inverse = inverse_diagonal_.data();
#pragma omp for schedule(static)
  for (int r = 0; r < rows; ++r) result[r] = inverse[r] * residual[r];
}

// --- block ILU(0) ----------------------------------------------------------------------------

namespace {

// The row starts of the block-local pattern of ILU(0): row r keeps the entries of A whose
// column lies in r's own block (block_start[b] <= column < block_start[b + 1]), plus a
// diagonal entry where A has none.
void count_block_pattern(const CsrMatrix& matrix, const std::vector<int>& block_start, std::vector<int>& row_start) {
  const int blocks = static_cast<int>(block_start.size()) - 1;
  row_start.resize(static_cast<std::size_t>(matrix.rows) + 1);
  row_start[0] = 0;
  for (int b = 0; b < blocks; ++b) {
    const int first = block_start[static_cast<std::size_t>(b)], last = block_start[static_cast<std::size_t>(b) + 1];
    for (int r = first; r < last; ++r) {
      int inside = 0;
      bool has_diagonal = false;
      for (int k = matrix.row_start[r]; k < matrix.row_start[r + 1]; ++k) {
        const int c = matrix.column[k];
        if (c >= first && c < last) ++inside;
        has_diagonal = has_diagonal || c == r;
      }
      row_start[static_cast<std::size_t>(r) + 1] =
          row_start[static_cast<std::size_t>(r)] + inside + (has_diagonal ? 0 : 1);
    }
  }
}

}  // namespace

void IncompleteLuPreconditioner::setup(const CsrMatrix& matrix) {
  rows_ = matrix.rows;
  const int blocks = std::min(block_count_, std::max(rows_, 1));
  block_start_.resize(static_cast<std::size_t>(blocks) + 1);
  for (int b = 0; b <= blocks; ++b) {
    block_start_[static_cast<std::size_t>(b)] =
        static_cast<int>(static_cast<long long>(rows_) * b / blocks);  // nearly equal consecutive ranges
  }
  // Pattern: the entries of A inside the row's own block, columns sorted. Counted per row first
  // so that the blocks can copy in parallel.
  count_block_pattern(matrix, block_start_, row_start_);
  const auto entries = static_cast<std::size_t>(row_start_[static_cast<std::size_t>(rows_)]);
  resize_with_headroom(column_, entries);
  resize_with_headroom(value_, entries);
  resize_with_headroom(diagonal_, static_cast<std::size_t>(rows_));
  resize_with_headroom(inverse_pivot_, static_cast<std::size_t>(rows_));
  position_.assign(static_cast<std::size_t>(rows_), -1);

#pragma omp parallel for schedule(static, 1)
  for (int b = 0; b < blocks; ++b) {
    const int first = block_start_[static_cast<std::size_t>(b)], last = block_start_[static_cast<std::size_t>(b) + 1];
    for (int r = first; r < last; ++r) {
      // Copy the row's in-block entries (and a zero diagonal if A has none), insertion-sorted.
      const int begin = row_start_[static_cast<std::size_t>(r)];
      int end = begin;
      bool has_diagonal = false;
      const auto insert = [&](int c, double v) {
        int k = end++;
        while (k > begin && column_[static_cast<std::size_t>(k) - 1] > c) {
          column_[static_cast<std::size_t>(k)] = column_[static_cast<std::size_t>(k) - 1];
          value_[static_cast<std::size_t>(k)] = value_[static_cast<std::size_t>(k) - 1];
          --k;
        }
        column_[static_cast<std::size_t>(k)] = c;
        value_[static_cast<std::size_t>(k)] = v;
      };
      for (int k = matrix.row_start[r]; k < matrix.row_start[r + 1]; ++k) {
        const int c = matrix.column[k];
        if (c < first || c >= last) continue;
        insert(c, matrix.value[k]);
        has_diagonal = has_diagonal || c == r;
      }
      if (!has_diagonal) insert(r, 0.0);
      // IKJ elimination restricted to the pattern (Saad algorithm 10.4): for each k < r in
      // row r, l_rk = a_rk / u_kk, then a_rj -= l_rk u_kj for the j > k present in row r.
      for (int k = begin; k < end; ++k) position_[static_cast<std::size_t>(column_[static_cast<std::size_t>(k)])] = k;
      int pivot = begin;
      for (int k = begin; k < end; ++k) {
        const int c = column_[static_cast<std::size_t>(k)];
        if (c >= r) {
          pivot = k;
          break;
        }
        const double factor = value_[static_cast<std::size_t>(k)] /
                              value_[static_cast<std::size_t>(diagonal_[static_cast<std::size_t>(c)])];
        value_[static_cast<std::size_t>(k)] = factor;
        for (int m = diagonal_[static_cast<std::size_t>(c)] + 1; m < row_start_[static_cast<std::size_t>(c) + 1]; ++m) {
          const int target = position_[static_cast<std::size_t>(column_[static_cast<std::size_t>(m)])];
          if (target >= 0) value_[static_cast<std::size_t>(target)] -= factor * value_[static_cast<std::size_t>(m)];
        }
      }
      if (value_[static_cast<std::size_t>(pivot)] == 0.0) value_[static_cast<std::size_t>(pivot)] = 1.0;
      diagonal_[static_cast<std::size_t>(r)] = pivot;
      inverse_pivot_[static_cast<std::size_t>(r)] = 1.0 / value_[static_cast<std::size_t>(pivot)];
      for (int k = begin; k < end; ++k) position_[static_cast<std::size_t>(column_[static_cast<std::size_t>(k)])] = -1;
    }
  }
}

void IncompleteLuPreconditioner::apply(const double* residual, double* result) const {
#pragma omp parallel
  apply_in_team(residual, result);
}

void IncompleteLuPreconditioner::apply_in_team(const double* residual, double* result) const {
  const auto blocks = static_cast<int>(block_start_.size()) - 1;
  const int* start = row_start_.data();
  const int* column = column_.data();
  const int* diagonal = diagonal_.data();
  const double* value = value_.data();
  const double* inverse_pivot = inverse_pivot_.data();
  // Two partial sums per row halve the chain of dependent additions (the sweeps are bound by
  // latency, not by memory).
#pragma omp for schedule(static, 1)
  for (int b = 0; b < blocks; ++b) {
    const int first = block_start_[static_cast<std::size_t>(b)], last = block_start_[static_cast<std::size_t>(b) + 1];
    for (int r = first; r < last; ++r) {  // L y = residual (unit lower triangle)
      double even = residual[r], odd = 0.0;
      int k = start[r];
      for (; k + 1 < diagonal[r]; k += 2) {
        even -= value[k] * result[column[k]];
        odd -= value[k + 1] * result[column[k + 1]];
      }
      if (k < diagonal[r]) even -= value[k] * result[column[k]];
      result[r] = even + odd;
    }
    for (int r = last - 1; r >= first; --r) {  // U z = y
      double even = result[r], odd = 0.0;
      int k = diagonal[r] + 1;
      for (; k + 1 < start[r + 1]; k += 2) {
        even -= value[k] * result[column[k]];
        odd -= value[k + 1] * result[column[k + 1]];
      }
      if (k < start[r + 1]) even -= value[k] * result[column[k]];
      result[r] = (even + odd) * inverse_pivot[r];
    }
  }
}

// --- conjugate gradients -----------------------------------------------------------------------

namespace {

// b = 0: x = 0 and nothing to iterate (as Eigen).
KrylovResult zero_solution(double* x, int rows) {
  std::fill(x, x + rows, 0.0);
  KrylovResult result;
  result.converged = true;
  return result;
}

// One CG update: x += alpha p, r -= alpha q, and with a Jacobi preconditioner (inverse_diagonal
// not null) z = D^-1 r, in one pass of the team. partial[b] = the block's ||r||^2 terms,
// partial[blocks + b] its r.z terms (0 without Jacobi).
void cg_update_in_team(double alpha, const double* p, const double* q, const double* inverse_diagonal, int rows,
                       double* x, double* r, double* z, double* partial) {
  const int blocks = block_count(rows);
#pragma omp for schedule(static)
  for (int b = 0; b < blocks; ++b) {
    const BlockRange range = block_range(b, rows);
    double rr_sum = 0.0, rz_sum = 0.0;
    if (inverse_diagonal != nullptr) {
      for (int i = range.begin; i < range.end; ++i) {
        x[i] += alpha * p[i];
        const double ri = r[i] - alpha * q[i];
        r[i] = ri;
        rr_sum += ri * ri;
        const double zi = inverse_diagonal[i] * ri;
        z[i] = zi;
        rz_sum += ri * zi;
      }
    } else {
      for (int i = range.begin; i < range.end; ++i) {
        x[i] += alpha * p[i];
        const double ri = r[i] - alpha * q[i];
        r[i] = ri;
        rr_sum += ri * ri;
      }
    }
    partial[b] = rr_sum;
    partial[blocks + b] = rz_sum;
  }
}

// The CG iterations from the residual r = b - A x held in the workspace (p = z = M^-1 r),
// until the recurrence residual is below `threshold` or the iteration budget is spent. They
// run in one parallel region (a barrier per loop, ~0.25 us, where a region per loop cost
// ~0.6 us: about 20 loops per iteration with AMG). Every thread adds the block sums itself, in
// block order, so all take the same branch; each reduction has its own third of the partial
// sums, so no thread overwrites sums another is still adding (a barrier lies between a
// reduction's reads and its next writes).
void cg_iterations(const CsrMatrix& matrix, double* x, const Preconditioner& preconditioner,
                   const double* inverse_diagonal, double threshold, long long max_iterations, KrylovWorkspace& work,
                   KrylovResult& result) {
  const int rows = matrix.rows;
  const int blocks = block_count(rows);
  double* r = work.residual.data();
  double* p = work.direction.data();
  double* q = work.product.data();
  double* z = work.preconditioned.data();
  double* pq_partial = work.partial.data();
  double* update_partial = pq_partial + 2 * blocks;
  double* rz_partial = update_partial + 2 * blocks;
  long long iterations_done = result.iterations;
#pragma omp parallel
  {
    long long iterations = iterations_done;
    preconditioner.apply_in_team(r, z);
    dot_in_team(r, z, rows, rz_partial);
    double rz = sum_in_order(rz_partial, blocks);
#pragma omp for schedule(static)
    for (int i = 0; i < rows; ++i) p[i] = z[i];
    while (iterations < max_iterations) {
      multiply_dot_in_team(matrix, p, p, q, pq_partial);  // q = A p
      const double alpha = rz / sum_in_order(pq_partial, blocks);
      ++iterations;
      cg_update_in_team(alpha, p, q, inverse_diagonal, rows, x, r, z, update_partial);
      const auto [recurrence_norm2, jacobi_rz] = sum_pairs_in_order(update_partial, blocks);
      if (!(recurrence_norm2 >= threshold)) break;  // below the tolerance (or NaN: stop, reported below)
      double rz_new = jacobi_rz;
      if (inverse_diagonal == nullptr) {
        preconditioner.apply_in_team(r, z);
        dot_in_team(r, z, rows, rz_partial);
        rz_new = sum_in_order(rz_partial, blocks);
      }
      const double beta = rz_new / rz;
      rz = rz_new;
#pragma omp for schedule(static)
      for (int i = 0; i < rows; ++i) p[i] = z[i] + beta * p[i];
    }
#pragma omp single nowait
    iterations_done = iterations;
  }
  result.iterations = iterations_done;
}

}  // namespace

KrylovResult conjugate_gradient(const CsrMatrix& matrix, const double* rhs, double* x,
                                const Preconditioner& preconditioner, const KrylovSettings& settings,
                                KrylovWorkspace& work) {
  KrylovResult result;
  const int rows = matrix.rows;
  const int blocks = block_count(rows);
  for (auto* vector : {&work.residual, &work.direction, &work.product, &work.preconditioned})
    ensure_size(*vector, rows);
  if (work.partial.size() < 6 * static_cast<std::size_t>(blocks))  // cg_iterations: three pairs
    work.partial.resize(6 * static_cast<std::size_t>(blocks));

  const double rhs_norm2 = blocked_dot(rhs, rhs, rows, work.partial);
  if (rhs_norm2 == 0.0) return zero_solution(x, rows);
  // Stop when ||r||^2 < tol^2 ||b||^2 (Eigen's threshold, never below the smallest normal).
  const double threshold =
      std::max(settings.tolerance * settings.tolerance * rhs_norm2, std::numeric_limits<double>::min());
  const auto* jacobi = dynamic_cast<const JacobiPreconditioner*>(&preconditioner);
  const double* inverse_diagonal = jacobi != nullptr ? jacobi->inverse_diagonal().data() : nullptr;

  double true_norm2 = residual_norm2(matrix, rhs, x, work.residual.data(), work.partial);
  while (true_norm2 >= threshold && result.iterations < settings.max_iterations) {
    // (Re)start from the true residual r = b - A x.
    cg_iterations(matrix, x, preconditioner, inverse_diagonal, threshold, settings.max_iterations, work, result);
    // The recurrence residual can drift from b - A x: check the true one (and restart if needed).
    true_norm2 = residual_norm2(matrix, rhs, x, work.residual.data(), work.partial);
    if (!std::isfinite(true_norm2)) break;
  }
  result.residual = std::sqrt(true_norm2 / rhs_norm2);
  result.converged = true_norm2 < threshold;
  return result;
}

// --- BiCGSTAB --------------------------------------------------------------------------------

namespace {

// The vectors of BiCGSTAB, in the workspace.
struct BicgstabVectors {
  double* r;   // residual
  double* r0;  // shadow residual
  double* p;
  double* v;  // A y
  double* s;  // r - alpha v, in r's storage (r is not read again before r = s - omega t)
  double* t;  // A z
  double* y;  // M^-1 p
  double* z;  // M^-1 s
};

BicgstabVectors bicgstab_vectors(KrylovWorkspace& work, int rows) {
  for (auto* vector : {&work.residual, &work.shadow, &work.direction, &work.product, &work.t, &work.y, &work.z}) {
    ensure_size(*vector, rows);
  }
  return {work.residual.data(), work.shadow.data(), work.direction.data(), work.product.data(),
          work.residual.data(), work.t.data(),      work.y.data(),         work.z.data()};
}

// x += alpha y + omega z, r = s - omega t, in one pass of the team; partial[b] = the block's
// ||r||^2 terms, partial[blocks + b] its r0 . r terms.
void bicgstab_update_in_team(double alpha, double omega, const BicgstabVectors& vec, int rows, double* x,
                             double* partial) {
  const int blocks = block_count(rows);
#pragma omp for schedule(static)
  for (int b = 0; b < blocks; ++b) {
    const BlockRange range = block_range(b, rows);
    double rr = 0.0, r0r = 0.0;
    for (int i = range.begin; i < range.end; ++i) {
      x[i] += alpha * vec.y[i] + omega * vec.z[i];
      const double ri = vec.s[i] - omega * vec.t[i];
      vec.r[i] = ri;
      rr += ri * ri;
      r0r += vec.r0[i] * ri;
    }
    partial[b] = rr;
    partial[blocks + b] = r0r;
  }
}

// Why a start of BiCGSTAB ended.
enum class BicgstabEnd { converged_or_budget, breakdown, not_finite };

// The iterations of one start of BiCGSTAB (r = b - A x, r0 = p = r, rho = r0 . r = norm2), in
// one parallel region as the CG iterations are (cg_iterations): every loop, the two V-cycles
// included, is an orphaned worksharing loop of the region; every thread adds the block sums
// itself, in block order, so all take the same branch; each of the three reductions of an
// iteration has its own part of `partial` (5 x blocks entries).
BicgstabEnd bicgstab_iterations(const CsrMatrix& matrix, double* x, const Preconditioner& preconditioner, double norm2,
                                double threshold, long long max_iterations, const BicgstabVectors& vec, double* partial,
                                long long& iterations_done) {
  const int rows = matrix.rows;
  const int blocks = block_count(rows);
  const double eps2 = std::numeric_limits<double>::epsilon() * std::numeric_limits<double>::epsilon();
  double* v_partial = partial;                    // r0 . v
  double* t_partial = partial + blocks;           // t . t, t . s
  double* update_partial = partial + 3 * blocks;  // ||r||^2, r0 . r
  BicgstabEnd end = BicgstabEnd::converged_or_budget;
  long long shared_iterations = iterations_done;
#pragma omp parallel
  {
    long long iterations = shared_iterations;
    BicgstabEnd own_end = BicgstabEnd::converged_or_budget;
    double rho = norm2;
    double residual_norm2_now = norm2;
    while (residual_norm2_now > threshold && iterations < max_iterations) {
      preconditioner.apply_in_team(vec.p, vec.y);
      multiply_dot_in_team(matrix, vec.y, vec.r0, vec.v, v_partial);  // v = A y, r0 . v
      const double r0v = sum_in_order(v_partial, blocks);
      if (r0v == 0.0 || !std::isfinite(r0v)) {
        own_end = BicgstabEnd::breakdown;
        break;
      }
      const double alpha = rho / r0v;
#pragma omp for schedule(static)
      for (int i = 0; i < rows; ++i) vec.s[i] = vec.r[i] - alpha * vec.v[i];
      preconditioner.apply_in_team(vec.s, vec.z);
      row_products_in_team(matrix, vec.z, t_partial, [&](int i, double row_sum, double& tt, double& ts) {
        vec.t[i] = row_sum;  // t = A z
        tt += row_sum * row_sum;
        ts += row_sum * vec.s[i];
      });
      const auto [tt, ts] = sum_pairs_in_order(t_partial, blocks);
      const double omega = tt > 0.0 ? ts / tt : 0.0;
      bicgstab_update_in_team(alpha, omega, vec, rows, x, update_partial);
      const auto [rr, rho_new] = sum_pairs_in_order(update_partial, blocks);
      ++iterations;
      residual_norm2_now = rr;
      if (!std::isfinite(residual_norm2_now)) {
        own_end = BicgstabEnd::not_finite;
        break;
      }
      if (!(residual_norm2_now > threshold)) break;
      // r became (nearly) orthogonal to r0, or omega = 0: restart with a fresh shadow residual.
      if (std::fabs(rho_new) < eps2 * norm2 || omega == 0.0) {
        own_end = BicgstabEnd::breakdown;
        break;
      }
      const double beta = (rho_new / rho) * (alpha / omega);
      rho = rho_new;
#pragma omp for schedule(static)
      for (int i = 0; i < rows; ++i) vec.p[i] = vec.r[i] + beta * (vec.p[i] - omega * vec.v[i]);
    }
#pragma omp single nowait
    {
      shared_iterations = iterations;
      end = own_end;
    }
  }
  iterations_done = shared_iterations;
  return end;
}

// One start of BiCGSTAB from the residual r = b - A x (norm2 = ||r||^2): shadow residual
// r0 = r, p = r, iterations until ||r||^2 <= threshold or the budget is spent. Returns true
// on a breakdown (r0 . v = 0, r nearly orthogonal to r0, or omega = 0): restart.
bool bicgstab_start(const CsrMatrix& matrix, double* x, const Preconditioner& preconditioner, double norm2,
                    double threshold, long long max_iterations, const BicgstabVectors& vec, KrylovWorkspace& work,
                    KrylovResult& result) {
  const int rows = matrix.rows;
  std::copy(vec.r, vec.r + rows, vec.r0);
  std::copy(vec.r, vec.r + rows, vec.p);
  const BicgstabEnd end = bicgstab_iterations(matrix, x, preconditioner, norm2, threshold, max_iterations, vec,
                                              work.partial.data(), result.iterations);
  return end == BicgstabEnd::breakdown;
}

}  // namespace

KrylovResult bicgstab(const CsrMatrix& matrix, const double* rhs, double* x, const Preconditioner& preconditioner,
                      const KrylovSettings& settings, KrylovWorkspace& work) {
  KrylovResult result;
  const int rows = matrix.rows;
  const int blocks = block_count(rows);
  const BicgstabVectors vec = bicgstab_vectors(work, rows);
  if (work.partial.size() < 5 * static_cast<std::size_t>(blocks))
    work.partial.resize(5 * static_cast<std::size_t>(blocks));

  const double rhs_norm2 = blocked_dot(rhs, rhs, rows, work.partial);
  if (rhs_norm2 == 0.0) return zero_solution(x, rows);
  // Continue while ||r||^2 > tol^2 ||b||^2 (Eigen's BiCGSTAB rule).
  const double threshold = settings.tolerance * settings.tolerance * rhs_norm2;

  double true_norm2 = residual_norm2(matrix, rhs, x, vec.r, work.partial);
  while (true_norm2 > threshold && result.iterations < settings.max_iterations) {
    const long long iterations_at_start = result.iterations;
    const bool breakdown =
        bicgstab_start(matrix, x, preconditioner, true_norm2, threshold, settings.max_iterations, vec, work, result);
    true_norm2 = residual_norm2(matrix, rhs, x, vec.r, work.partial);
    if (!std::isfinite(true_norm2)) break;
    // A breakdown before any step of this start cannot be cured by restarting again.
    if (breakdown && result.iterations == iterations_at_start) break;
  }
  result.residual = std::sqrt(true_norm2 / rhs_norm2);
  result.converged = true_norm2 <= threshold;
  return result;
}

}  // namespace mps_lab
