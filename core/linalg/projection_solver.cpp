#include "core/linalg/projection_solver.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/base/particle_order.hpp"
#include "core/io/checkpoint.hpp"
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

std::vector<ParameterSpec> projection_solver_parameters(const std::string& krylov, const std::string& factorisation) {
  return {
      string_parameter("preconditioner", "auto",
                       krylov + " preconditioner (incomplete_factorisation: " + factorisation +
                           "); auto: amg from amg_min_fluid_particles fluid particles on, jacobi below")
          .one_of(preconditioner_choices()),
      integer_parameter("amg_min_fluid_particles", kDefaultAmgMinFluidParticles,
                        "preconditioner auto: the fluid particle count from which AMG beats Jacobi (measured)")
          .at_least(0),
      number_parameter("amg_reuse_budget", kDefaultAmgReuseBudget, "",
                       "AMG: reuse a hierarchy for later systems until the preconditioner applications it costs "
                       "beyond its first solve add up to this (0: a new hierarchy for every system; "
                       "core/linalg/projection_solver.hpp)")
          .at_least(0.0),
      string_parameter("amg_cycle", "w",
                       "AMG: w, each coarse level cycled twice per visit (iterations flat in the size), or v, once "
                       "(docs/performance.md, \"A W-cycle\")")
          .one_of({"w", "v"}),
  };
}

AmgOptions amg_options(const ParameterValues& parameters) {
  AmgOptions options;
  options.coarse_cycles = parameters.string("amg_cycle") == "v" ? 1 : 2;
  return options;
}

PreconditionerKind choose_preconditioner(const std::string& choice, std::size_t fluid_particles,
                                         std::size_t amg_min_fluid_particles) {
  if (choice != "auto") return preconditioner_from_name(choice);
  return fluid_particles >= amg_min_fluid_particles ? PreconditionerKind::Amg : PreconditionerKind::Jacobi;
}

std::unique_ptr<Preconditioner> make_preconditioner(PreconditionerKind kind, const AmgOptions& amg) {
  switch (kind) {
    case PreconditionerKind::IncompleteFactorisation:
      return std::make_unique<IncompleteLuPreconditioner>(kIncompleteFactorisationBlocks);
    case PreconditionerKind::Amg:
      return std::make_unique<AmgPreconditioner>(amg);  // core/linalg/amg.hpp, smoothed aggregation
    case PreconditionerKind::Jacobi:
      break;
  }
  return std::make_unique<JacobiPreconditioner>();
}

// Reuse of an AMG hierarchy (docs/performance.md, "A reused hierarchy"): a system is solved
// with the hierarchy of an earlier one (AmgPreconditioner::refresh, rows matched through their
// particles) while the preconditioner applications the reuse has cost above the first solve
// with that hierarchy stay below `amg_reuse_budget`; then, or when a solve did not converge,
// the hierarchy is built again. For an excess that grows linearly with the hierarchy's age,
// rebuilding when the summed excess reaches the set-up's own cost minimises the cost per step.
bool ProjectionSolver::can_reuse_hierarchy(std::size_t particles, const ProjectionSolverSettings& settings) const {
  return settings.amg_reuse_budget > 0.0 && reuse_.solves > 0 && reuse_.last_converged &&
         reuse_.excess_applications < settings.amg_reuse_budget && base_row_of_particle_.size() == particles;
}

void ProjectionSolver::prepare_preconditioner(const CsrMatrix& matrix, const std::vector<int>& particle_of,
                                              std::size_t particles, const ProjectionSolverSettings& settings) {
  const PreconditionerKind kind = settings.preconditioner;
  if (!preconditioner_ || kind_ != kind) {
    preconditioner_ = make_preconditioner(kind, amg_options_);
    kind_ = kind;
    reuse_ = HierarchyReuse{};
  }
  auto* amg = kind_ == PreconditionerKind::Amg ? static_cast<AmgPreconditioner*>(preconditioner_.get()) : nullptr;
  if (amg != nullptr && can_reuse_hierarchy(particles, settings)) {
    base_row_of_row_.resize(particle_of.size());
    for (std::size_t r = 0; r < particle_of.size(); ++r)
      base_row_of_row_[r] = base_row_of_particle_[static_cast<std::size_t>(particle_of[r])];
    amg->refresh(matrix, base_row_of_row_);
    ++reused_solves_;
    return;
  }
  preconditioner_->setup(matrix);
  ++setups_;
  reuse_ = HierarchyReuse{};
  if (amg == nullptr || !(settings.amg_reuse_budget > 0.0)) {
    base_row_of_particle_.clear();
    return;
  }
  base_row_of_particle_.assign(particles, -1);
  for (std::size_t r = 0; r < particle_of.size(); ++r)
    base_row_of_particle_[static_cast<std::size_t>(particle_of[r])] = static_cast<int>(r);
}

// After a solve: its preconditioner applications (CG one per iteration, BiCGSTAB two) against
// the first solve with the hierarchy.
void ProjectionSolver::record_reuse(const KrylovResult& solved, KrylovMethod method) {
  const double applications = static_cast<double>(solved.iterations) * (method == KrylovMethod::Bicgstab ? 2.0 : 1.0);
  if (reuse_.solves == 0) reuse_.first_applications = applications;
  reuse_.excess_applications += std::max(0.0, applications - reuse_.first_applications);
  reuse_.last_converged = solved.converged;
  ++reuse_.solves;
}

void ProjectionSolver::save_state(CheckpointWriter& out) const {
  out.write_int(setups_);
  out.write_int(reused_solves_);
  const bool kept =
      kind_ == PreconditionerKind::Amg && preconditioner_ && !base_row_of_particle_.empty() && reuse_.solves > 0;
  out.write_bool(kept);
  if (!kept) return;
  out.write_int(reuse_.solves);
  out.write_double(reuse_.first_applications);
  out.write_double(reuse_.excess_applications);
  out.write_bool(reuse_.last_converged);
  std::vector<std::uint32_t> rows(base_row_of_particle_.size());
  for (std::size_t i = 0; i < rows.size(); ++i) rows[i] = static_cast<std::uint32_t>(base_row_of_particle_[i] + 1);
  out.write_u32s(rows);
  static_cast<const AmgPreconditioner&>(*preconditioner_).save_state(out);
}

void ProjectionSolver::restore_state(CheckpointReader& in, PreconditionerKind kind) {
  setups_ = in.read_int();
  reused_solves_ = in.read_int();
  reuse_ = HierarchyReuse{};
  base_row_of_particle_.clear();
  if (!in.read_bool()) return;
  if (kind != PreconditionerKind::Amg) in.fail("an AMG hierarchy for a run whose preconditioner is not amg");
  preconditioner_ = make_preconditioner(kind, amg_options_);
  kind_ = kind;
  reuse_.solves = in.read_int();
  reuse_.first_applications = in.read_double();
  reuse_.excess_applications = in.read_double();
  reuse_.last_converged = in.read_bool();
  const std::vector<std::uint32_t> rows = in.read_u32s();
  base_row_of_particle_.resize(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) base_row_of_particle_[i] = static_cast<int>(rows[i]) - 1;
  static_cast<AmgPreconditioner&>(*preconditioner_).restore_state(in);
}

void ProjectionSolver::permute_state(const ParticleOrder& order) { permute_values(base_row_of_particle_, order); }

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
  if (!base_row_of_particle_.empty())
    out.emplace_back("amg_reuse_rows", held_bytes(base_row_of_particle_, base_row_of_row_));
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
  prepare_preconditioner(matrix, particle_of, pressure.size(), settings);
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
  record_reuse(solved, settings.method);
  statistics.iterations = solved.iterations;
  statistics.residual = solved.residual;
  statistics.converged = solved.converged;

  scatter_unknowns(solution_, particle_of, settings.clamp_negative, pressure);
  return statistics;
}

}  // namespace mps_lab
