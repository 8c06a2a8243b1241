#pragma once
// The pressure Poisson equation of the ISPH projection, fluid and walls in one linear system.
//
// Unknowns: the pressures of the fluid particles that are not on the free surface, and of
// every wall particle with at least one non-ghost fluid particle within the kernel support.
// Free-surface fluid particles have p = 0 at their centres (Dirichlet; Shao & Lo 2003) or, with
// a surface offset delta > 0, at the water surface delta beyond them: then each is an unknown
// with the row (SURF) of isph_surface.hpp,
//   p_i - delta / ((delta + d_i) sum_j W_ij) sum_j W_ij p_j = 0   (fluid neighbours j),
// which grounds the system as a Dirichlet particle does (its row sum is positive); a surface
// particle without fluid beneath it keeps p = 0. Other wall particles carry no pressure.
//
// Fluid row i (Cummins & Rudman 1999; Shao & Lo 2003):
//   <div(grad p / rho)>_i = sum_j a_ij (p_j - p_i) = S_i,
//   a_ij = -m 8/(rho_i + rho_j)^2 r_ij.grad W_ij / (r_ij^2 + eta^2)   (isph_operators.hpp),
// over every non-ghost neighbour j (fluid and wall), S_i the source term of the method.
// Wall row w (Adami, Hu & Adams 2012, eq. 27, with a fixed wall, a_w = 0):
//   p_w sum_f W_wf - sum_f p_f W_wf = g . sum_f rho_f (x_w - x_f) W_wf,
// over the non-ghost fluid neighbours f: the wall pressure is the kernel-weighted average of
// the fluid pressure around it plus the hydrostatic head between them, which is the pressure
// a wall must carry for the fluid next to it to have no wall-normal acceleration.
//
// Wall samples (core/walls/wall_samples.hpp; boundary models without wall particles, then there are
// no wall rows): fluid row i also sums a_iw (p_i - p_w) over its samples w, a_iw the pair
// coefficient with mass m V_w and density rho0, p_w = p_s + rho0 g . (x_w - x_s):
//   s = i (dummy layers, distance function): the p terms cancel, a_iw rho0 g . (x_w - x_i)
//          goes to the right-hand side (a Neumann wall: nothing on the diagonal);
//   s != i an unknown (a mirror image of fluid particle s): A_ii += a_iw, A_is -= a_iw, and
//          the hydrostatic part a_iw rho0 g . (x_w - x_s) to the right-hand side;
//   s on the free surface (p_s = 0): A_ii += a_iw and the hydrostatic part only.
//
// Every row is scaled to pascals (fluid rows by rho0 l0^2, wall rows by 1 / sum_f W_wf), so the
// relative residual ||b - A p|| / ||b|| weighs all rows alike. The wall rows make A
// non-symmetric: BiCGSTAB (core/linalg/krylov.hpp) through the projection solver
// (core/linalg/projection_solver.hpp), preconditioned by jacobi, incomplete_factorisation
// (ILU(0)) or amg.
// The matrix is assembled straight into compressed rows (core/linalg/sparse_matrix.hpp,
// CsrInPlaceAssembler), rows in parallel, into storage kept from step to step: a first pass
// counts each row's entries (its unknowns among the neighbours and wall samples), the second
// writes them in place.
#include <utility>
#include <vector>

#include <Eigen/Sparse>

#include "core/base/particles.hpp"
#include "core/kernels/sph_kernels.hpp"
#include "core/linalg/projection_solver.hpp"
#include "core/search/neighbour_search.hpp"
#include "core/walls/wall_samples.hpp"

namespace mps_lab::isph {

struct PressureSolveSettings {
  double rest_density = 1000.0;     // rho0, kg/m^3
  double spacing = 0.025;           // l0, m (row scaling and the (SURF) depth bound)
  double mass = 0.625;              // m, kg/m (per unit depth)
  double eta2 = 0.0;                // eta^2 of the Laplacian, m^2
  double surface_offset = 0.0;      // delta, m: p = 0 delta beyond the surface particles (0: at them)
  Vec2 gravity = Vec2(0.0, -9.81);  // m/s^2
  double tolerance = 1.0e-8;        // relative residual ||b - A p|| / ||b||
  long long max_iterations = 1000;  // BiCGSTAB iterations (all restarts together)
  bool warm_start = true;           // start from particles.pressure
  // core/linalg/projection_solver.hpp: jacobi, incomplete_factorisation (ILU(0) here) or amg
  PreconditionerKind preconditioner = PreconditionerKind::Jacobi;
  // AMG: preconditioner applications a reused hierarchy may cost beyond its first solve
  // (core/linalg/projection_solver.hpp; 0: a new hierarchy for every system).
  double amg_reuse_budget = 0.0;
};

struct PressureSolveResult {
  long long iterations = 0;
  double residual = 0.0;  // achieved ||b - A p|| / ||b||, recomputed after the solve
  bool converged = true;
  std::size_t fluid_unknowns = 0;
  std::size_t wall_unknowns = 0;
  std::size_t surface = 0;           // fluid particles on the free surface (held at p = 0, or rows (SURF))
  std::size_t surface_unknowns = 0;  // of them, the rows (SURF) (surface offset > 0)
  std::size_t ungrounded_groups = 0;
};

class PressurePoissonSolver {
 public:
  // Hands `observer` to the projection solver (MethodSetup::pressure_system_observer).
  void observe(PressureSystemObserver observer) { solver_.observe(std::move(observer)); }
  // The projection solver (checkpoints, cell order and run.json's counts of its AMG hierarchy).
  ProjectionSolver& projection_solver() { return solver_; }
  const ProjectionSolver& projection_solver() const { return solver_; }

  // Assembles and solves; writes particles.pressure of every fluid and wall particle (0 for
  // surface fluid, for walls without fluid neighbours and for ghosts). `density` as in
  // isph_operators.hpp; `free_surface[i]` != 0 marks Dirichlet fluid particles; `source[i]`
  // is S_i of fluid row i, 1/s^2.
  // `samples`: the boundary model's wall samples (empty for wall particles).
  PressureSolveResult solve(ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                            const SphKernel& kernel, const std::vector<double>& density,
                            const std::vector<double>& free_surface, const std::vector<double>& source,
                            const PressureSolveSettings& settings);
  PressureSolveResult solve(ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                            const std::vector<double>& density, const std::vector<double>& free_surface,
                            const std::vector<double>& source, const PressureSolveSettings& settings) {
    return solve(particles, neighbours, WallSampleList{}, kernel, density, free_surface, source, settings);
  }

  // Assembly alone (free-surface rows, fluid and wall rows, regularisation); fills the counts
  // of the result. solve() = assemble() + solve_assembled().
  PressureSolveResult assemble(ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                               const SphKernel& kernel, const std::vector<double>& density,
                               const std::vector<double>& free_surface, const std::vector<double>& source,
                               const PressureSolveSettings& settings);
  // BiCGSTAB on the assembled system; writes the pressures of the unknowns.
  void solve_assembled(ParticleSet& particles, const PressureSolveSettings& settings, PressureSolveResult& result);

  // The last assembled system and its unknowns (for tests).
  const CsrMatrix& csr_matrix() const { return matrix_; }
  Eigen::SparseMatrix<double, Eigen::RowMajor> matrix() const;
  Eigen::Map<const Eigen::VectorXd> rhs() const { return {rhs_.data(), static_cast<Eigen::Index>(matrix_.rows)}; }
  const std::vector<int>& row_of_particle() const { return row_of_; }  // -1: not an unknown
  const std::vector<int>& particle_of_row() const { return particle_of_; }

  // The heap it holds between solves (core/base/memory_bytes.hpp): the matrix, the assembly's
  // storage, the maps between particles and unknowns, the solver's vectors and preconditioner.
  MemoryBreakdown memory_breakdown() const;

 private:
  // What every row of the assembly reads.
  struct RowInputs {
    const ParticleSet& particles;
    const NeighbourList& neighbours;
    const WallSampleList& samples;
    const SphKernel& kernel;
    const std::vector<double>& density;
    const std::vector<double>& source;
    const PressureSolveSettings& settings;
    double fluid_scale;  // rho0 l0^2, kg/m: fluid rows in Pa
  };
  int row_count(const RowInputs& in, std::size_t i) const;
  bool fluid_row(const RowInputs& in, int row, std::size_t i, CsrInPlaceAssembler::RowWriter& writer);
  bool wall_row(const RowInputs& in, int row, std::size_t i, CsrInPlaceAssembler::RowWriter& writer);
  void surface_row(const RowInputs& in, int row, std::size_t i, CsrInPlaceAssembler::RowWriter& writer);
  void assemble_rows(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                     const SphKernel& kernel, const std::vector<double>& density, const std::vector<double>& source,
                     const PressureSolveSettings& settings);

  std::vector<int> row_of_;
  std::vector<double> surface_factor_;  // factor_i of (SURF) per particle; 0: not a surface row
  std::vector<int> particle_of_;
  std::size_t fluid_rows_ = 0;     // rows [0, fluid_rows_) are fluid, the rest walls
  std::vector<char> grounded_;     // per unknown: touches a Dirichlet particle
  std::vector<char> reached_;      // per unknown: connected to a grounded one (pin_ungrounded_groups scratch)
  CsrInPlaceAssembler assembler_;  // rows straight into matrix_ (no padded copy beside it)
  CsrMatrix matrix_;
  std::vector<double> rhs_;  // Pa
  ProjectionSolver solver_;
};

}  // namespace mps_lab::isph
