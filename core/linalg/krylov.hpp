#pragma once
// Krylov solvers over CsrMatrix (core/linalg/sparse_matrix.hpp) with a pluggable preconditioner: the
// pressure solvers of mps (conjugate gradients) and isph (BiCGSTAB).
//
// A preconditioner M ~ A is any class derived from Preconditioner:
//   setup(A)         once per assembled matrix (may allocate on the first calls only);
//   apply(r, z)      z = M^-1 r, both of length A.rows; must not depend on the thread count
//                    (the determinism tests compare 1 and 2 threads byte for byte).
// Jacobi (the inverse diagonal) and ILU(0) (incomplete LU without fill on fixed row blocks,
// which is IC(0) for a symmetric matrix) are here; other files may add more (core/linalg/amg.*).
//
// Stopping rule, the same as Eigen's ConjugateGradient / BiCGSTAB: the relative residual
// ||b - A x||_2 / ||b||_2 in the unpreconditioned 2-norm below `tolerance`. Unlike Eigen, the
// residual of the returned x is recomputed (one more product): when the recurrence residual
// has drifted from the true one, the iteration restarts from x with the iterations left, so
// the reported residual is always the true one of the returned x.
//
// Every reduction is a deterministic blocked sum (fixed blocks, partial sums added in block
// order), so results are bit-identical for any number of OpenMP threads.
#include <cstddef>
#include <vector>

#include "core/base/memory_bytes.hpp"
#include "core/linalg/sparse_matrix.hpp"

namespace mps_lab {

class Preconditioner {
 public:
  virtual ~Preconditioner() = default;
  // Prepares M for `matrix` (called once per assembled matrix, before any apply).
  virtual void setup(const CsrMatrix& matrix) = 0;
  // result = M^-1 residual (arrays of matrix.rows entries, not aliased), called outside any
  // parallel region.
  virtual void apply(const double* residual, double* result) const = 0;
  // The same, called by every thread of an enclosing parallel region together (conjugate
  // gradients run their iterations in one region): the loops are shared with orphaned
  // worksharing constructs and the call returns after a barrier. The default has one thread
  // call apply(), whose own parallel loops then run on that thread only.
  virtual void apply_in_team(const double* residual, double* result) const;
  // The heap it holds between setups (core/base/memory_bytes.hpp).
  virtual MemoryBreakdown memory_breakdown() const { return {}; }
};

// M = diag(A); a zero diagonal entry is treated as 1 (as Eigen's DiagonalPreconditioner).
class JacobiPreconditioner final : public Preconditioner {
 public:
  void setup(const CsrMatrix& matrix) override;
  void apply(const double* residual, double* result) const override;
  void apply_in_team(const double* residual, double* result) const override;
  const std::vector<double>& inverse_diagonal() const { return inverse_diagonal_; }
  MemoryBreakdown memory_breakdown() const override { return {{"inverse_diagonal", held_bytes(inverse_diagonal_)}}; }

 private:
  std::vector<double> inverse_diagonal_;
};

// ILU(0) on diagonal blocks of consecutive rows (block Jacobi with incomplete-LU blocks; Saad,
// "Iterative Methods for Sparse Linear Systems", 2nd ed., §10.3.2, algorithm 10.4): entries
// coupling two blocks are dropped, so the blocks factor and solve independently, in
// parallel. The rows are split into `block_count` nearly equal ranges: the partition depends
// on the row count only, never on the thread count. For a symmetric matrix ILU(0) is IC(0)
// (L U with U = D L^T). A missing or zero pivot is replaced by 1.
class IncompleteLuPreconditioner final : public Preconditioner {
 public:
  explicit IncompleteLuPreconditioner(int block_count = 1) : block_count_(block_count < 1 ? 1 : block_count) {}
  void setup(const CsrMatrix& matrix) override;
  void apply(const double* residual, double* result) const override;
  void apply_in_team(const double* residual, double* result) const override;
  MemoryBreakdown memory_breakdown() const override {
    return {{"factors", held_bytes(row_start_, column_, diagonal_, value_, inverse_pivot_, block_start_, position_)}};
  }

 private:
  int block_count_;
  int rows_ = 0;
  // The factors in the block-local pattern of A, columns sorted: L strictly below the
  // diagonal (unit diagonal implied), U from the diagonal on; diagonal_[r] indexes U's pivot.
  std::vector<int> row_start_, column_, diagonal_;
  std::vector<double> value_;
  std::vector<double> inverse_pivot_;  // 1 / u_rr
  std::vector<int> block_start_;
  std::vector<int> position_;  // scratch of setup: column -> entry of the current row, or -1
};

struct KrylovSettings {
  double tolerance = 1.0e-8;        // relative residual ||b - A x|| / ||b||
  long long max_iterations = 1000;  // iterations (CG: one matrix-vector product each, BiCGSTAB: two)
};

struct KrylovResult {
  long long iterations = 0;  // iterations done (0 when the initial guess already satisfies the tolerance)
  double residual = 0.0;     // ||b - A x|| / ||b|| of the returned x (0 when b = 0, then x = 0)
  bool converged = false;
};

// Vectors of the iterations, kept between solves so that nothing is allocated once the sizes
// have been seen.
struct KrylovWorkspace {
  std::vector<double> residual, direction, product, preconditioned, shadow, t, y, z;  // BiCGSTAB's s: in residual
  std::vector<double> partial;  // per-block partial sums of the reductions

  std::size_t held_bytes() const {
    return mps_lab::held_bytes(residual, direction, product, preconditioned, shadow, t, y, z, partial);
  }
};

// Preconditioned conjugate gradients (Saad §9.2, algorithm 9.1) for symmetric positive
// definite A: on entry x is the initial guess (warm start), on exit the solution.
KrylovResult conjugate_gradient(const CsrMatrix& matrix, const double* rhs, double* x,
                                const Preconditioner& preconditioner, const KrylovSettings& settings,
                                KrylovWorkspace& workspace);

// Right-preconditioned BiCGSTAB (van der Vorst 1992; Saad §7.4.2, as Eigen's BiCGSTAB) for a
// general non-singular A. A breakdown (rho = 0 or a vanishing denominator) restarts from the
// current x with a fresh shadow residual.
KrylovResult bicgstab(const CsrMatrix& matrix, const double* rhs, double* x, const Preconditioner& preconditioner,
                      const KrylovSettings& settings, KrylovWorkspace& workspace);

}  // namespace mps_lab
