#include "core/linalg/krylov.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mps_lab {

namespace {

// Rows per block of the fused loops: each block's partial sums are formed in row order and the
// blocks' partials are added in block order, whatever thread ran the block.
constexpr int kBlockRows = 1024;

int block_count(int rows) { return (rows + kBlockRows - 1) / kBlockRows; }

struct BlockRange {
  int begin, end;
};
BlockRange block_range(int block, int rows) { return {block * kBlockRows, std::min(rows, (block + 1) * kBlockRows)}; }

double sum_in_order(const std::vector<double>& partial, int blocks) {
  double total = 0.0;
  for (int b = 0; b < blocks; ++b) total += partial[static_cast<std::size_t>(b)];
  return total;
}

void ensure_size(std::vector<double>& vector, int rows) {
  if (vector.size() < static_cast<std::size_t>(rows)) vector.resize(static_cast<std::size_t>(rows));
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

// out = A x, returns x . out (both in one pass over the rows).
double multiply_dot(const CsrMatrix& matrix, const double* x, double* out, std::vector<double>& partial) {
  const int rows = matrix.rows;
  const int blocks = block_count(rows);
  const int* start = matrix.row_start.data();
  const int* column = matrix.column.data();
  const double* value = matrix.value.data();
#pragma omp parallel for schedule(static)
  for (int b = 0; b < blocks; ++b) {
    const BlockRange range = block_range(b, rows);
    double sum = 0.0;
    for (int r = range.begin; r < range.end; ++r) {
      const double row_sum = row_product(value, column, x, start[r], start[r + 1]);
      out[r] = row_sum;
      sum += x[r] * row_sum;
    }
    partial[static_cast<std::size_t>(b)] = sum;
  }
  return sum_in_order(partial, blocks);
}

// residual = rhs - A x, returns ||residual||^2.
double residual_norm2(const CsrMatrix& matrix, const double* rhs, const double* x, double* residual,
                      std::vector<double>& partial) {
  const int rows = matrix.rows;
  const int blocks = block_count(rows);
  const int* start = matrix.row_start.data();
  const int* column = matrix.column.data();
  const double* value = matrix.value.data();
#pragma omp parallel for schedule(static)
  for (int b = 0; b < blocks; ++b) {
    const BlockRange range = block_range(b, rows);
    double sum = 0.0;
    for (int r = range.begin; r < range.end; ++r) {
      const double row_sum = row_product(value, column, x, start[r], start[r + 1]);
      const double difference = rhs[r] - row_sum;
      residual[r] = difference;
      sum += difference * difference;
    }
    partial[static_cast<std::size_t>(b)] = sum;
  }
  return sum_in_order(partial, blocks);
}

double blocked_dot(const double* a, const double* b, int rows, std::vector<double>& partial) {
  const int blocks = block_count(rows);
#pragma omp parallel for schedule(static)
  for (int block = 0; block < blocks; ++block) {
    const BlockRange range = block_range(block, rows);
    double sum = 0.0;
    for (int r = range.begin; r < range.end; ++r) sum += a[r] * b[r];
    partial[static_cast<std::size_t>(block)] = sum;
  }
  return sum_in_order(partial, blocks);
}

}  // namespace

// --- Jacobi ----------------------------------------------------------------------------------

void JacobiPreconditioner::setup(const CsrMatrix& matrix) {
  const int rows = matrix.rows;
  inverse_diagonal_.resize(static_cast<std::size_t>(rows));
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

void JacobiPreconditioner::apply(const double* residual, double* result) const {
  const auto rows = static_cast<int>(inverse_diagonal_.size());
  const double* inverse = inverse_diagonal_.data();
#pragma omp parallel for schedule(static)
  for (int r = 0; r < rows; ++r) result[r] = inverse[r] * residual[r];
}

// --- block ILU(0) ----------------------------------------------------------------------------

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
  row_start_.resize(static_cast<std::size_t>(rows_) + 1);
  row_start_[0] = 0;
  for (int b = 0; b < blocks; ++b) {
    const int first = block_start_[static_cast<std::size_t>(b)], last = block_start_[static_cast<std::size_t>(b) + 1];
    for (int r = first; r < last; ++r) {
      int inside = 0;
      bool has_diagonal = false;
      for (int k = matrix.row_start[r]; k < matrix.row_start[r + 1]; ++k) {
        const int c = matrix.column[k];
        if (c >= first && c < last) ++inside;
        has_diagonal = has_diagonal || c == r;
      }
      row_start_[static_cast<std::size_t>(r) + 1] = row_start_[static_cast<std::size_t>(r)] + inside + (has_diagonal ? 0 : 1);
    }
  }
  const auto entries = static_cast<std::size_t>(row_start_[static_cast<std::size_t>(rows_)]);
  column_.resize(entries);
  value_.resize(entries);
  diagonal_.resize(static_cast<std::size_t>(rows_));
  inverse_pivot_.resize(static_cast<std::size_t>(rows_));
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
        const double factor = value_[static_cast<std::size_t>(k)] / value_[static_cast<std::size_t>(diagonal_[static_cast<std::size_t>(c)])];
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
  const auto blocks = static_cast<int>(block_start_.size()) - 1;
  const int* start = row_start_.data();
  const int* column = column_.data();
  const int* diagonal = diagonal_.data();
  const double* value = value_.data();
  const double* inverse_pivot = inverse_pivot_.data();
  // Two partial sums per row halve the chain of dependent additions (the sweeps are bound by
  // latency, not by memory).
#pragma omp parallel for schedule(static, 1)
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

KrylovResult conjugate_gradient(const CsrMatrix& matrix, const double* rhs, double* x,
                                const Preconditioner& preconditioner, const KrylovSettings& settings,
                                KrylovWorkspace& work) {
  KrylovResult result;
  const int rows = matrix.rows;
  const int blocks = block_count(rows);
  ensure_size(work.residual, rows);
  ensure_size(work.direction, rows);
  ensure_size(work.product, rows);
  ensure_size(work.preconditioned, rows);
  if (work.partial.size() < 2 * static_cast<std::size_t>(blocks)) work.partial.resize(2 * static_cast<std::size_t>(blocks));
  double* r = work.residual.data();
  double* p = work.direction.data();
  double* q = work.product.data();
  double* z = work.preconditioned.data();

  const double rhs_norm2 = blocked_dot(rhs, rhs, rows, work.partial);
  if (rhs_norm2 == 0.0) {  // as Eigen: x = 0
    std::fill(x, x + rows, 0.0);
    result.converged = true;
    return result;
  }
  // Stop when ||r||^2 < tol^2 ||b||^2 (Eigen's threshold, never below the smallest normal).
  const double threshold =
      std::max(settings.tolerance * settings.tolerance * rhs_norm2, std::numeric_limits<double>::min());
  const auto* jacobi = dynamic_cast<const JacobiPreconditioner*>(&preconditioner);
  const double* inverse_diagonal = jacobi != nullptr ? jacobi->inverse_diagonal().data() : nullptr;

  double true_norm2 = residual_norm2(matrix, rhs, x, r, work.partial);
  while (true_norm2 >= threshold && result.iterations < settings.max_iterations) {
    // (Re)start from the true residual r = b - A x: p = z = M^-1 r.
    preconditioner.apply(r, z);
    double rz = blocked_dot(r, z, rows, work.partial);
    std::copy(z, z + rows, p);
    double recurrence_norm2 = true_norm2;
    while (result.iterations < settings.max_iterations) {
      const double pq = multiply_dot(matrix, p, q, work.partial);  // q = A p
      const double alpha = rz / pq;
      ++result.iterations;
      // x += alpha p, r -= alpha q, ||r||^2, and for Jacobi z = D^-1 r and r.z, in one pass.
#pragma omp parallel for schedule(static)
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
        work.partial[static_cast<std::size_t>(b)] = rr_sum;
        work.partial[static_cast<std::size_t>(blocks + b)] = rz_sum;
      }
      recurrence_norm2 = sum_in_order(work.partial, blocks);
      if (!(recurrence_norm2 >= threshold)) break;  // below the tolerance (or NaN: stop, reported below)
      double rz_new = 0.0;
      if (inverse_diagonal != nullptr) {
        for (int b = 0; b < blocks; ++b) rz_new += work.partial[static_cast<std::size_t>(blocks + b)];
      } else {
        preconditioner.apply(r, z);
        rz_new = blocked_dot(r, z, rows, work.partial);
      }
      const double beta = rz_new / rz;
      rz = rz_new;
#pragma omp parallel for schedule(static)
      for (int i = 0; i < rows; ++i) p[i] = z[i] + beta * p[i];
    }
    // The recurrence residual can drift from b - A x: check the true one (and restart if needed).
    true_norm2 = residual_norm2(matrix, rhs, x, r, work.partial);
    if (!std::isfinite(true_norm2)) break;
  }
  result.residual = std::sqrt(true_norm2 / rhs_norm2);
  result.converged = true_norm2 < threshold;
  return result;
}

// --- BiCGSTAB --------------------------------------------------------------------------------

KrylovResult bicgstab(const CsrMatrix& matrix, const double* rhs, double* x, const Preconditioner& preconditioner,
                      const KrylovSettings& settings, KrylovWorkspace& work) {
  KrylovResult result;
  const int rows = matrix.rows;
  const int blocks = block_count(rows);
  for (auto* vector : {&work.residual, &work.shadow, &work.direction, &work.product, &work.s, &work.t, &work.y,
                       &work.z}) {
    ensure_size(*vector, rows);
  }
  if (work.partial.size() < 2 * static_cast<std::size_t>(blocks)) work.partial.resize(2 * static_cast<std::size_t>(blocks));
  double* r = work.residual.data();
  double* r0 = work.shadow.data();
  double* p = work.direction.data();
  double* v = work.product.data();
  double* s = work.s.data();
  double* t = work.t.data();
  double* y = work.y.data();
  double* z = work.z.data();

  const double rhs_norm2 = blocked_dot(rhs, rhs, rows, work.partial);
  if (rhs_norm2 == 0.0) {
    std::fill(x, x + rows, 0.0);
    result.converged = true;
    return result;
  }
  // Continue while ||r||^2 > tol^2 ||b||^2 (Eigen's BiCGSTAB rule).
  const double threshold = settings.tolerance * settings.tolerance * rhs_norm2;
  const double eps2 = std::numeric_limits<double>::epsilon() * std::numeric_limits<double>::epsilon();

  double true_norm2 = residual_norm2(matrix, rhs, x, r, work.partial);
  while (true_norm2 > threshold && result.iterations < settings.max_iterations) {
    // (Re)start: shadow residual r0 = r, p = r.
    const long long iterations_at_start = result.iterations;
    std::copy(r, r + rows, r0);
    std::copy(r, r + rows, p);
    double rho = true_norm2;  // r0 . r
    const double r0_norm2 = true_norm2;
    double residual_norm2_now = true_norm2;
    bool breakdown = false;
    while (residual_norm2_now > threshold && result.iterations < settings.max_iterations) {
      preconditioner.apply(p, y);
      const double r0v = [&] {  // v = A y, r0 . v
        const int* start = matrix.row_start.data();
        const int* column = matrix.column.data();
        const double* value = matrix.value.data();
#pragma omp parallel for schedule(static)
        for (int b = 0; b < blocks; ++b) {
          const BlockRange range = block_range(b, rows);
          double sum = 0.0;
          for (int i = range.begin; i < range.end; ++i) {
            const double row_sum = row_product(value, column, y, start[i], start[i + 1]);
            v[i] = row_sum;
            sum += r0[i] * row_sum;
          }
          work.partial[static_cast<std::size_t>(b)] = sum;
        }
        return sum_in_order(work.partial, blocks);
      }();
      if (r0v == 0.0 || !std::isfinite(r0v)) {
        breakdown = true;
        break;
      }
      const double alpha = rho / r0v;
#pragma omp parallel for schedule(static)
      for (int i = 0; i < rows; ++i) s[i] = r[i] - alpha * v[i];
      preconditioner.apply(s, z);
      // t = A z, with t.t and t.s in the same pass.
      {
        const int* start = matrix.row_start.data();
        const int* column = matrix.column.data();
        const double* value = matrix.value.data();
#pragma omp parallel for schedule(static)
        for (int b = 0; b < blocks; ++b) {
          const BlockRange range = block_range(b, rows);
          double tt = 0.0, ts = 0.0;
          for (int i = range.begin; i < range.end; ++i) {
            const double row_sum = row_product(value, column, z, start[i], start[i + 1]);
            t[i] = row_sum;
            tt += row_sum * row_sum;
            ts += row_sum * s[i];
          }
          work.partial[static_cast<std::size_t>(b)] = tt;
          work.partial[static_cast<std::size_t>(blocks + b)] = ts;
        }
      }
      double tt = 0.0, ts = 0.0;
      for (int b = 0; b < blocks; ++b) {
        tt += work.partial[static_cast<std::size_t>(b)];
        ts += work.partial[static_cast<std::size_t>(blocks + b)];
      }
      const double omega = tt > 0.0 ? ts / tt : 0.0;
      // x += alpha y + omega z, r = s - omega t, ||r||^2 and r0 . r in one pass.
#pragma omp parallel for schedule(static)
      for (int b = 0; b < blocks; ++b) {
        const BlockRange range = block_range(b, rows);
        double rr = 0.0, r0r = 0.0;
        for (int i = range.begin; i < range.end; ++i) {
          x[i] += alpha * y[i] + omega * z[i];
          const double ri = s[i] - omega * t[i];
          r[i] = ri;
          rr += ri * ri;
          r0r += r0[i] * ri;
        }
        work.partial[static_cast<std::size_t>(b)] = rr;
        work.partial[static_cast<std::size_t>(blocks + b)] = r0r;
      }
      ++result.iterations;
      residual_norm2_now = 0.0;
      double rho_new = 0.0;
      for (int b = 0; b < blocks; ++b) {
        residual_norm2_now += work.partial[static_cast<std::size_t>(b)];
        rho_new += work.partial[static_cast<std::size_t>(blocks + b)];
      }
      if (!std::isfinite(residual_norm2_now)) break;
      if (!(residual_norm2_now > threshold)) break;
      // r became (nearly) orthogonal to r0, or omega = 0: restart with a fresh shadow residual.
      if (std::fabs(rho_new) < eps2 * r0_norm2 || omega == 0.0) {
        breakdown = true;
        break;
      }
      const double beta = (rho_new / rho) * (alpha / omega);
      rho = rho_new;
#pragma omp parallel for schedule(static)
      for (int i = 0; i < rows; ++i) p[i] = r[i] + beta * (p[i] - omega * v[i]);
    }
    true_norm2 = residual_norm2(matrix, rhs, x, r, work.partial);
    if (!std::isfinite(true_norm2)) break;
    // A breakdown before any step of this start cannot be cured by restarting again.
    if (breakdown && result.iterations == iterations_at_start) break;
  }
  result.residual = std::sqrt(true_norm2 / rhs_norm2);
  result.converged = true_norm2 <= threshold;
  return result;
}

}  // namespace mps_lab
