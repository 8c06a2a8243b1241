#pragma once
// The linear solve of the projection methods (mps, isph): one component for the Krylov
// method, the preconditioner, the warm start, the stopping rule and the statistics.
//
// A method assembles its pressure system A p = b (CsrMatrix, diagonal first in each row) with
// row r standing for particle particle_of[r], then calls ProjectionSolver::solve, which
//   1. sets up the preconditioner chosen from the one vocabulary below (kept between calls;
//      an AMG hierarchy may serve several systems: amg_reuse_budget, projection_solver.cpp),
//   2. starts from the particles' pressures (warm start) or from zero (gather_unknowns),
//   3. runs conjugate gradients (A symmetric positive definite: mps) or BiCGSTAB (A not
//      symmetric: isph's wall rows) until ||b - A p|| / ||b|| < tolerance or the iteration
//      budget is spent (core/linalg/krylov.hpp: the residual reported is recomputed),
//   4. writes the pressures back (scatter_unknowns), negative values clamped to 0 when asked
//      (spec §5.2-7 for mps).
//
// The preconditioner vocabulary, the same for every method:
//   "jacobi"                    the inverse diagonal;
//   "incomplete_factorisation"  ILU(0) on two fixed row blocks, which is IC(0) when A is
//                               symmetric (core/linalg/krylov.hpp);
//   "amg"                       smoothed-aggregation algebraic multigrid (core/linalg/amg.hpp);
//   "auto"                      amg from a fluid-particle count on, jacobi below
//                               (choose_preconditioner; the count is the method's parameter).
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "core/base/parameters.hpp"
#include "core/linalg/amg.hpp"
#include "core/linalg/krylov.hpp"
#include "core/linalg/sparse_matrix.hpp"

namespace mps_lab {

enum class PreconditionerKind { Jacobi, IncompleteFactorisation, Amg };
enum class KrylovMethod { ConjugateGradient, Bicgstab };

// The values a method's `preconditioner` parameter accepts: auto, jacobi,
// incomplete_factorisation, amg (for ParameterSpec::one_of: another name is a one-line
// error naming the key and these values).
std::vector<std::string> preconditioner_choices();

// The kind called `name` (not "auto"); throws std::invalid_argument for another name.
PreconditionerKind preconditioner_from_name(const std::string& name);
// The vocabulary's name of `kind` (run.json's method summary).
const char* preconditioner_name(PreconditionerKind kind);

// The default of the methods' `amg_min_fluid_particles`: the measured break-even of AMG (with
// its degree-1 smoother) against Jacobi, 1 thread, the dam break from rest (docs/performance.md,
// "A degree-1 smoother"): Jacobi faster at 288 fluid particles, even at 406 and 578, AMG
// faster from 741 on (mps's solve 0.54-0.56 against 0.60-0.92 ms, isph's 0.77-0.78 against
// 1.02-1.38 ms per step).
constexpr int kDefaultAmgMinFluidParticles = 600;

// The default of the methods' `amg_reuse_budget`: an AMG set-up costs about as much as nine
// preconditioner applications with their products (docs/performance.md, "A reused hierarchy"),
// so a hierarchy is reused until the applications it has cost beyond its first solve add up to
// that much.
constexpr double kDefaultAmgReuseBudget = 8.0;

// The parameters of the solve every projection method declares (core/parameters.hpp):
// `preconditioner` (the vocabulary above), `amg_min_fluid_particles`, `amg_reuse_budget` and
// `amg_cycle`;
// `krylov` and `factorisation` name the method's Krylov solver and what its
// incomplete_factorisation is ("CG", "IC(0)").
std::vector<ParameterSpec> projection_solver_parameters(const std::string& krylov, const std::string& factorisation);

// Resolves a `preconditioner` parameter: "auto" is amg from `amg_min_fluid_particles` fluid
// particles on and jacobi below (decided once per run from the initial particles, so that a
// restored checkpoint decides the same); any other value names its kind.
PreconditionerKind choose_preconditioner(const std::string& choice, std::size_t fluid_particles,
                                         std::size_t amg_min_fluid_particles);

// The AMG options of a method's parameters: `amg_cycle` "w" (the default; AmgOptions::coarse_cycles
// 2) or "v" (1).
AmgOptions amg_options(const ParameterValues& parameters);

// A new preconditioner of `kind` (incomplete factorisation on fixed row blocks, so that the
// result does not depend on the thread count; AMG with `amg`).
std::unique_ptr<Preconditioner> make_preconditioner(PreconditionerKind kind, const AmgOptions& amg = AmgOptions{});

struct ProjectionSolverSettings {
  KrylovMethod method = KrylovMethod::ConjugateGradient;
  PreconditionerKind preconditioner = PreconditionerKind::Jacobi;
  double tolerance = 1.0e-8;         // relative residual ||b - A p|| / ||b||
  long long max_iterations = 10000;  // Krylov iterations (all restarts together)
  bool warm_start = true;            // start from the particles' pressures, else from 0
  bool clamp_negative = false;       // write max(p, 0) back (spec §5.2-7 for mps)
  // A non-finite residual throws std::runtime_error with this message, before anything is
  // written back (isph); null: the pressures are written back as they are (mps, whose
  // stability monitor reports the NaN).
  const char* non_finite_error = nullptr;
  // AMG only: preconditioner applications a reused hierarchy may cost above the first solve
  // with it before it is built again (0: built for every system; ProjectionSolver::solve).
  double amg_reuse_budget = 0.0;
};

struct ProjectionSolveStatistics {
  long long iterations = 0;
  double residual = 0.0;  // ||b - A p|| / ||b|| of the returned pressure
  bool converged = true;
};

struct ProjectionSolverSettings;

// Sees each pressure system a ProjectionSolver is about to solve (matrix, right-hand side and
// settings), before anything is changed: the solver comparison (lab/solver_comparison/) records
// a method's systems with it. Empty by default: a run pays nothing for it.
using PressureSystemObserver =
    std::function<void(const CsrMatrix& matrix, const std::vector<double>& rhs, const ProjectionSolverSettings&)>;

class ProjectionSolver;
class CheckpointWriter;
class CheckpointReader;
struct ParticleOrder;

// The memory of a projection method's pressure solve under the names `mps_lab bench` reports
// (docs/performance.md, "Memory"): "matrix", "assembly_slots" (the assembler's held bytes),
// "unknowns" (the caller's per-unknown arrays, bytes) and "solver.*" (the solver's).
MemoryBreakdown pressure_solve_breakdown(const CsrMatrix& matrix, std::size_t assembly_bytes,
                                         std::size_t unknowns_bytes, const ProjectionSolver& solver);

class ProjectionSolver {
 public:
  // Calls `observer` with every system solve() receives from now on (empty: none).
  void observe(PressureSystemObserver observer) { observer_ = std::move(observer); }
  // The options of its AMG hierarchies from now on (amg_options of the method's parameters).
  void configure_amg(const AmgOptions& options) { amg_options_ = options; }

  // Solves matrix p = rhs (rhs has matrix.rows entries) and writes p of row r to
  // pressure[particle_of[r]]. Nothing is done (and nothing written) for an empty matrix.
  ProjectionSolveStatistics solve(const CsrMatrix& matrix, const std::vector<double>& rhs,
                                  const std::vector<int>& particle_of, const ProjectionSolverSettings& settings,
                                  std::vector<double>& pressure);

  // The heap it holds between solves: the preconditioner's, the solution and the Krylov vectors.
  MemoryBreakdown memory_breakdown() const;

  // Preconditioner set-ups and the solves that reused an AMG hierarchy, since the start (run.json).
  long long setups() const { return setups_; }
  long long reused_solves() const { return reused_solves_; }

  // Checkpoints: a reused AMG hierarchy and its reuse state, so that a restored run rebuilds
  // and reuses it at the same steps, bit for bit (docs/checkpoints.md). A method writes it in
  // its save_state; restore_state needs the preconditioner kind of the next solve.
  void save_state(CheckpointWriter& out) const;
  void restore_state(CheckpointReader& in, PreconditionerKind kind);
  // Cell-ordered particles: the reused hierarchy's rows by particle move with the particles.
  void permute_state(const ParticleOrder& order);

 private:
  void prepare_preconditioner(const CsrMatrix& matrix, const std::vector<int>& particle_of, std::size_t particles,
                              const ProjectionSolverSettings& settings);

  PreconditionerKind kind_ = PreconditionerKind::Jacobi;
  AmgOptions amg_options_;
  PressureSystemObserver observer_;
  std::unique_ptr<Preconditioner> preconditioner_;
  std::vector<double> solution_;  // Pa
  // The hierarchy's reuse since its set-up (core/linalg/projection_solver.cpp).
  struct HierarchyReuse {
    long long solves = 0;              // with this hierarchy, the set-up's own solve included
    double first_applications = 0.0;   // preconditioner applications of the set-up's solve
    double excess_applications = 0.0;  // summed excess of the later solves over it
    bool last_converged = true;
  };
  bool can_reuse_hierarchy(std::size_t particles, const ProjectionSolverSettings& settings) const;
  void record_reuse(const KrylovResult& solved, KrylovMethod method);

  HierarchyReuse reuse_;
  long long setups_ = 0;
  long long reused_solves_ = 0;
  std::vector<int> base_row_of_particle_;  // the rows of the last set-up, by particle (-1: none)
  std::vector<int> base_row_of_row_;       // this system's rows' rows in it
  KrylovWorkspace workspace_;
};

}  // namespace mps_lab
