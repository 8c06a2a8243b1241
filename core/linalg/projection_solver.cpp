#include "core/linalg/projection_solver.hpp"

#include <cmath>
#include <stdexcept>

#include "core/linalg/amg.hpp"
#include "core/linalg/pressure_system.hpp"

namespace mps_lab {

namespace {

// The row blocks of the incomplete factorisation: fixed (not the thread count), so that the
// result does not depend on it; two blocks let two threads factor and solve at once.
constexpr int kIncompleteFactorisationBlocks = 2;

}  // namespace

std::vector<std::string> preconditioner_choices() { return {"auto", "jacobi", "incomplete_factorisation", "amg"}; }

PreconditionerKind preconditioner_from_name(const std::string& name) {
  if (name == "jacobi") return PreconditionerKind::Jacobi;
  if (name == "incomplete_factorisation") return PreconditionerKind::IncompleteFactorisation;
  if (name == "amg") return PreconditionerKind::Amg;
  throw std::invalid_argument("unknown preconditioner '" + name +
                              "' (expected jacobi, incomplete_factorisation or amg)");
}

const char* preconditioner_name(PreconditionerKind kind) {
  switch (kind) {
    case PreconditionerKind::IncompleteFactorisation:
      return "incomplete_factorisation";
    case PreconditionerKind::Amg:
      return "amg";
    case PreconditionerKind::Jacobi:
      break;
  }
  return "jacobi";
}

PreconditionerKind choose_preconditioner(const std::string& choice, std::size_t fluid_particles,
                                         std::size_t amg_min_fluid_particles) {
  if (choice != "auto") return preconditioner_from_name(choice);
  return fluid_particles >= amg_min_fluid_particles ? PreconditionerKind::Amg : PreconditionerKind::Jacobi;
}

std::unique_ptr<Preconditioner> make_preconditioner(PreconditionerKind kind) {
  switch (kind) {
    case PreconditionerKind::IncompleteFactorisation:
      return std::make_unique<IncompleteLuPreconditioner>(kIncompleteFactorisationBlocks);
    case PreconditionerKind::Amg:
      return std::make_unique<AmgPreconditioner>();  // core/linalg/amg.hpp, smoothed aggregation
    case PreconditionerKind::Jacobi:
      break;
  }
  return std::make_unique<JacobiPreconditioner>();
}

void ProjectionSolver::prepare_preconditioner(const CsrMatrix& matrix, PreconditionerKind kind) {
  if (!preconditioner_ || kind_ != kind) {
    preconditioner_ = make_preconditioner(kind);
    kind_ = kind;
  }
  preconditioner_->setup(matrix);
}

MemoryBreakdown pressure_solve_breakdown(const CsrMatrix& matrix, std::size_t assembly_bytes,
                                         std::size_t unknowns_bytes, const ProjectionSolver& solver) {
  MemoryBreakdown out = {
      {"matrix", matrix.held_bytes()}, {"assembly_slots", assembly_bytes}, {"unknowns", unknowns_bytes}};
  append_breakdown(out, "solver", solver.memory_breakdown());
  return out;
}

MemoryBreakdown ProjectionSolver::memory_breakdown() const {
  MemoryBreakdown out;
  out.emplace_back("krylov_vectors", held_bytes(solution_) + workspace_.held_bytes());
  if (preconditioner_) append_breakdown(out, preconditioner_name(kind_), preconditioner_->memory_breakdown());
  return out;
}

ProjectionSolveStatistics ProjectionSolver::solve(const CsrMatrix& matrix, const std::vector<double>& rhs,
                                                  const std::vector<int>& particle_of,
                                                  const ProjectionSolverSettings& settings,
                                                  std::vector<double>& pressure) {
  ProjectionSolveStatistics statistics;
  if (matrix.rows == 0) return statistics;
  if (observer_) observer_(matrix, rhs, settings);
  prepare_preconditioner(matrix, settings.preconditioner);
  gather_unknowns(pressure, particle_of, settings.warm_start, solution_);

  KrylovSettings krylov;
  krylov.tolerance = settings.tolerance;
  krylov.max_iterations = settings.max_iterations;
  const KrylovResult solved =
      settings.method == KrylovMethod::ConjugateGradient
          ? conjugate_gradient(matrix, rhs.data(), solution_.data(), *preconditioner_, krylov, workspace_)
          : bicgstab(matrix, rhs.data(), solution_.data(), *preconditioner_, krylov, workspace_);
  if (settings.non_finite_error != nullptr && !std::isfinite(solved.residual)) {
    throw std::runtime_error(settings.non_finite_error);
  }
  statistics.iterations = solved.iterations;
  statistics.residual = solved.residual;
  statistics.converged = solved.converged;

  scatter_unknowns(solution_, particle_of, settings.clamp_negative, pressure);
  return statistics;
}

}  // namespace mps_lab
