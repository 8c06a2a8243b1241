#include "lab/solver_comparison/boomeramg_solve.hpp"

#include <HYPRE.h>
#include <HYPRE_IJ_mv.h>
#include <HYPRE_krylov.h>
#include <HYPRE_parcsr_ls.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

namespace mps_lab {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

// The rows [first, last] (inclusive, hypre's convention) of this rank: an even split.
struct RowRange {
  HYPRE_BigInt first = 0;
  HYPRE_BigInt last = -1;
};

RowRange rows_of_rank(int rows, MPI_Comm communicator) {
  int rank = 0, size = 1;
  MPI_Comm_rank(communicator, &rank);
  MPI_Comm_size(communicator, &size);
  const long long n = rows;
  return {static_cast<HYPRE_BigInt>(n * rank / size), static_cast<HYPRE_BigInt>(n * (rank + 1) / size - 1)};
}

HYPRE_IJMatrix make_matrix(const CsrMatrix& matrix, const RowRange& range, MPI_Comm communicator) {
  HYPRE_IJMatrix ij = nullptr;
  HYPRE_IJMatrixCreate(communicator, range.first, range.last, range.first, range.last, &ij);
  HYPRE_IJMatrixSetObjectType(ij, HYPRE_PARCSR);
  HYPRE_IJMatrixInitialize(ij);
  for (HYPRE_BigInt row = range.first; row <= range.last; ++row) {
    const int begin = matrix.row_start[row], end = matrix.row_start[row + 1];
    HYPRE_Int count = end - begin;
    HYPRE_BigInt index = row;
    std::vector<HYPRE_BigInt> columns(matrix.column.begin() + begin, matrix.column.begin() + end);
    HYPRE_IJMatrixSetValues(ij, 1, &count, &index, columns.data(), matrix.value.data() + begin);
  }
  HYPRE_IJMatrixAssemble(ij);
  return ij;
}

HYPRE_IJVector make_vector(const std::vector<double>& values, const RowRange& range, MPI_Comm communicator) {
  HYPRE_IJVector ij = nullptr;
  HYPRE_IJVectorCreate(communicator, range.first, range.last, &ij);
  HYPRE_IJVectorSetObjectType(ij, HYPRE_PARCSR);
  HYPRE_IJVectorInitialize(ij);
  const auto count = static_cast<HYPRE_Int>(range.last - range.first + 1);
  std::vector<HYPRE_BigInt> indices(static_cast<std::size_t>(count));
  std::iota(indices.begin(), indices.end(), range.first);
  HYPRE_IJVectorSetValues(ij, count, indices.data(), values.data() + range.first);
  HYPRE_IJVectorAssemble(ij);
  return ij;
}

HYPRE_Solver make_boomeramg(const BoomerAmgSettings& settings) {
  HYPRE_Solver amg = nullptr;
  HYPRE_BoomerAMGCreate(&amg);
  HYPRE_BoomerAMGSetMaxIter(amg, 1);  // one V-cycle per application: a preconditioner
  HYPRE_BoomerAMGSetTol(amg, 0.0);
  HYPRE_BoomerAMGSetStrongThreshold(amg, settings.strength_threshold);
  HYPRE_BoomerAMGSetPrintLevel(amg, 0);
  return amg;
}

// The whole solution on every rank, from each rank's rows.
void gather_solution(HYPRE_IJVector x, const RowRange& range, int rows, MPI_Comm communicator,
                     std::vector<double>& solution) {
  const auto count = static_cast<int>(range.last - range.first + 1);
  std::vector<HYPRE_BigInt> indices(static_cast<std::size_t>(count));
  std::iota(indices.begin(), indices.end(), range.first);
  std::vector<double> local(static_cast<std::size_t>(count));
  HYPRE_IJVectorGetValues(x, count, indices.data(), local.data());
  int size = 1;
  MPI_Comm_size(communicator, &size);
  std::vector<int> counts(static_cast<std::size_t>(size)), offsets(static_cast<std::size_t>(size));
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, communicator);
  std::partial_sum(counts.begin(), counts.end() - 1, offsets.begin() + 1);
  solution.assign(static_cast<std::size_t>(rows), 0.0);
  MPI_Allgatherv(local.data(), count, MPI_DOUBLE, solution.data(), counts.data(), offsets.data(), MPI_DOUBLE,
                 communicator);
}

struct KrylovRun {
  double setup_seconds = 0.0, solve_seconds = 0.0;
  long long iterations = 0;
};

// PCG (symmetric) or BiCGSTAB preconditioned by `amg`: set-up (BoomerAMG's hierarchy) and solve.
KrylovRun run_krylov(const PressureSystem& system, HYPRE_ParCSRMatrix a, HYPRE_ParVector b, HYPRE_ParVector x,
                     HYPRE_Solver amg, const BoomerAmgSettings& settings, MPI_Comm communicator) {
  KrylovRun run;
  HYPRE_Solver krylov = nullptr;
  HYPRE_Int iterations = 0;
  const bool symmetric = system.krylov == KrylovMethod::ConjugateGradient;
  if (symmetric) {
    HYPRE_ParCSRPCGCreate(communicator, &krylov);
    HYPRE_ParCSRPCGSetTol(krylov, system.tolerance);
    HYPRE_ParCSRPCGSetTwoNorm(krylov, 1);  // ||r|| / ||b|| in the 2-norm, as core/linalg/krylov.hpp
    HYPRE_ParCSRPCGSetMaxIter(krylov, settings.max_iterations);
    HYPRE_ParCSRPCGSetPrecond(krylov, HYPRE_BoomerAMGSolve, HYPRE_BoomerAMGSetup, amg);
  } else {
    HYPRE_ParCSRBiCGSTABCreate(communicator, &krylov);
    HYPRE_ParCSRBiCGSTABSetTol(krylov, system.tolerance);
    HYPRE_ParCSRBiCGSTABSetMaxIter(krylov, settings.max_iterations);
    HYPRE_ParCSRBiCGSTABSetPrecond(krylov, HYPRE_BoomerAMGSolve, HYPRE_BoomerAMGSetup, amg);
  }
  MPI_Barrier(communicator);
  const auto setup_start = Clock::now();
  symmetric ? HYPRE_ParCSRPCGSetup(krylov, a, b, x) : HYPRE_ParCSRBiCGSTABSetup(krylov, a, b, x);
  MPI_Barrier(communicator);
  run.setup_seconds = seconds_since(setup_start);
  const auto solve_start = Clock::now();
  symmetric ? HYPRE_ParCSRPCGSolve(krylov, a, b, x) : HYPRE_ParCSRBiCGSTABSolve(krylov, a, b, x);
  MPI_Barrier(communicator);
  run.solve_seconds = seconds_since(solve_start);
  symmetric ? HYPRE_ParCSRPCGGetNumIterations(krylov, &iterations)
            : HYPRE_ParCSRBiCGSTABGetNumIterations(krylov, &iterations);
  symmetric ? HYPRE_ParCSRPCGDestroy(krylov) : HYPRE_ParCSRBiCGSTABDestroy(krylov);
  run.iterations = iterations;
  return run;
}

double summed_over_ranks(double value, MPI_Comm communicator) {
  double sum = 0.0;
  MPI_Allreduce(&value, &sum, 1, MPI_DOUBLE, MPI_SUM, communicator);
  return sum;
}

}  // namespace

SolveMeasure solve_with_boomeramg(const PressureSystem& system, MPI_Comm communicator,
                                  const BoomerAmgSettings& settings, int repeats, std::vector<double>& solution) {
  const RowRange range = rows_of_rank(system.matrix.rows, communicator);
  HYPRE_IJMatrix a = make_matrix(system.matrix, range, communicator);
  HYPRE_IJVector b = make_vector(system.rhs, range, communicator);
  HYPRE_ParCSRMatrix parcsr_a = nullptr;
  HYPRE_ParVector par_b = nullptr;
  HYPRE_IJMatrixGetObject(a, reinterpret_cast<void**>(&parcsr_a));
  HYPRE_IJVectorGetObject(b, reinterpret_cast<void**>(&par_b));
  SolveMeasure best;
  best.setup_seconds = best.solve_seconds = std::numeric_limits<double>::infinity();
  const std::vector<double> zero(system.rhs.size(), 0.0);
  for (int repeat = 0; repeat < repeats; ++repeat) {
    HYPRE_IJVector x = make_vector(zero, range, communicator);
    HYPRE_ParVector par_x = nullptr;
    HYPRE_IJVectorGetObject(x, reinterpret_cast<void**>(&par_x));
    const double memory_before = heap_bytes_in_use();
    HYPRE_Solver amg = make_boomeramg(settings);
    const KrylovRun run = run_krylov(system, parcsr_a, par_b, par_x, amg, settings, communicator);
    best.memory_bytes = summed_over_ranks(heap_bytes_in_use() - memory_before, communicator);
    HYPRE_BoomerAMGDestroy(amg);
    best.setup_seconds = std::min(best.setup_seconds, run.setup_seconds);
    best.solve_seconds = std::min(best.solve_seconds, run.solve_seconds);
    best.iterations = run.iterations;
    gather_solution(x, range, system.matrix.rows, communicator, solution);
    HYPRE_IJVectorDestroy(x);
  }
  HYPRE_IJVectorDestroy(b);
  HYPRE_IJMatrixDestroy(a);
  best.residual = relative_residual(system.matrix, system.rhs, solution);
  best.converged = best.residual <= system.tolerance * 1.0001;
  return best;
}

}  // namespace mps_lab
