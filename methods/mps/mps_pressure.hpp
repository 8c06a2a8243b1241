#pragma once
// The pressure Poisson equation of MPS (spec §8; Koshizuka & Oka 1996, eq. 16):
//   <lap P>_i = -(relaxation) (rho / dt^2) (n*_i - n0) / n0
// discretised with the Laplacian model of spec §2,
//   <lap P>_i = (2d / (n0_L lambda_L)) sum_j (P_j - P_i) w_L(r_ij),
// over the particles that carry pressure (fluid and the wall layers the method lets carry
// it). Free-surface particles (n*_i < threshold n0) have P = 0 (Dirichlet, spec §7); the
// others are unknowns. Written as A p = b with A_ii = sum_j a_ij, A_ij = -a_ij, the matrix
// is symmetric and, where every connected group of unknowns touches a Dirichlet particle,
// positive definite: conjugate gradients apply (core/linalg/krylov.hpp).
//
// The matrix is assembled straight into compressed rows (core/linalg/sparse_matrix.hpp), rows in
// parallel, into storage kept from step to step.
#include <utility>
#include <vector>

#include <Eigen/Sparse>

#include "core/base/particles.hpp"
#include "core/linalg/projection_solver.hpp"
#include "core/linalg/sparse_matrix.hpp"
#include "core/search/neighbour_search.hpp"
#include "core/walls/wall_samples.hpp"
#include "methods/mps/mps_operators.hpp"
#include "methods/mps/mps_schemes.hpp"

namespace mps_lab::mps {

struct PressureSolveSettings {
  double density = 1000.0;               // kg/m^3
  Vec2 gravity = Vec2(0.0, -9.81);       // m/s^2 (hydrostatic part of wall-sample pressures)
  double relaxation = 0.2;               // spec §3
  double free_surface_threshold = 0.97;  // beta: surface if n*/n0 < beta
  double tolerance = 1.0e-8;             // relative residual ||b - A p|| / ||b||
  long long max_iterations = 10000;
  bool warm_start = true;  // start CG from the previous pressure
  // core/linalg/projection_solver.hpp: jacobi, incomplete_factorisation (IC(0) here) or amg
  PreconditionerKind preconditioner = PreconditionerKind::Jacobi;
  // AMG: preconditioner applications a reused hierarchy may cost beyond its first solve
  // (core/linalg/projection_solver.hpp; 0: a new hierarchy for every system).
  double amg_reuse_budget = 0.0;
  bool clamp_negative = true;  // spec §5.2-7
  // The Laplacian of the PPE's matrix (methods/mps/mps_schemes.hpp): spec (spec §2) or hl
  // (Khayyer & Gotoh 2010, with the radius and n0 of `laplacian`).
  PpeLaplacianScheme laplacian_scheme = PpeLaplacianScheme::Spec;
  // When not null, b_i = (*source_term)[i] (Pa/m^2, a source term of mps_schemes.hpp) replaces
  // the spec's relaxation (rho/dt^2)(n*_i - n0)/n0; the free surface still follows n*.
  const std::vector<double>* source_term = nullptr;
  // m: the water surface's distance beyond a free-surface particle's centre. 0: the spec's P = 0
  // on the surface particles (§3); > 0: a fluid surface particle with water below it holds the
  // hydrostatic head rho |g| surface_offset, and a wall particle on the surface the head of the
  // same water surface at its height (surface_value below): Dirichlet values that the rows beside
  // them carry to their right-hand sides. mps also makes the dry-wall rule's level tolerance this
  // distance (DryWallRule, core/walls/wall_samples.hpp).
  double surface_offset = 0.0;
};

// The dry-wall rule of mps (`dry_wall_points` "excluded" when `exclude`; DryWallRule, core/walls/
// wall_samples.hpp): its level tolerance is the water surface's offset, so a wall particle at P <= 0
// less than surface_offset below a fluid particle is above the water, not its zero (docs/methods/
// mps.md, "The water line on the wall"); 0 with the spec's surface.
inline DryWallRule dry_wall_rule(bool exclude, const PressureSolveSettings& settings) {
  return {exclude, settings.gravity, settings.density, settings.surface_offset};
}

struct PressureSolveResult {
  long long iterations = 0;
  double residual = 0.0;  // ||b - A p|| / ||b|| of the returned pressure
  bool converged = true;
  std::size_t unknowns = 0;
  std::size_t surface = 0;            // pressure-carrying particles held at P = 0
  std::size_t ungrounded_groups = 0;  // groups of unknowns without a Dirichlet neighbour
};

class PressurePoissonSolver {
 public:
  // Hands `observer` to the projection solver (MethodSetup::pressure_system_observer).
  void observe(PressureSystemObserver observer) { solver_.observe(std::move(observer)); }
  // The projection solver (checkpoints, cell order and run.json's counts of its AMG hierarchy).
  ProjectionSolver& projection_solver() { return solver_; }
  const ProjectionSolver& projection_solver() const { return solver_; }
  // What it holds between steps (mps_lab bench's memory breakdown, docs/performance.md
  // "Memory"): the matrix, the assembler's slots, the unknowns' arrays and the solver's.
  MemoryBreakdown memory_breakdown() const;

  // Free surface, matrix and right-hand side (spec §5.2-5, §8): sets free_surface[i] = 1 and
  // P = 0 for surface particles (their head with settings.surface_offset > 0), whose values the
  // neighbouring rows carry to b; fills unknowns, surface and ungrounded_groups of the result.
  // `n0` is the number-density constant of the source term, `laplacian` the radius and
  // constants of the Laplacian model.
  // Wall samples (core/walls/wall_samples.hpp) add a_iw (p_s + rho g.(x_w - x_s) - p_i) to the
  // Laplacian of row i: for s = i only the known hydrostatic part remains (right-hand side),
  // for a mirror image of j the row couples to j (symmetric: the image of i seen from j has
  // the same weight), and a Dirichlet source leaves its constant part.
  PressureSolveResult assemble(ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                               const std::vector<double>& number_density, const std::vector<char>& carries_pressure,
                               const OperatorRadius& laplacian, double n0, double dt,
                               const PressureSolveSettings& settings, std::vector<double>& free_surface);

  // Solves the assembled system by preconditioned CG (spec §5.2-6; the projection solver of
  // core/linalg/projection_solver.hpp) from the previous pressure (warm start) or zero, and
  // writes P of every unknown, negative values clamped to 0 when asked (spec §5.2-7). Fills
  // iterations, residual and converged of `result`.
  void solve_assembled(ParticleSet& particles, const PressureSolveSettings& settings, PressureSolveResult& result);

  // Both of the above.
  PressureSolveResult solve(ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                            const std::vector<double>& number_density, const std::vector<char>& carries_pressure,
                            const OperatorRadius& laplacian, double n0, double dt,
                            const PressureSolveSettings& settings, std::vector<double>& free_surface) {
    PressureSolveResult result = assemble(particles, neighbours, samples, number_density, carries_pressure, laplacian,
                                          n0, dt, settings, free_surface);
    solve_assembled(particles, settings, result);
    return result;
  }

  // The last assembled system (for tests).
  const CsrMatrix& csr_matrix() const { return matrix_; }
  Eigen::SparseMatrix<double, Eigen::RowMajor> matrix() const;
  Eigen::Map<const Eigen::VectorXd> rhs() const { return {rhs_.data(), static_cast<Eigen::Index>(matrix_.rows)}; }

 private:
  // What every row of the assembly reads.
  struct RowInputs {
    const ParticleSet& particles;
    const NeighbourList& neighbours;
    const WallSampleList& samples;
    const std::vector<double>& number_density;
    const std::vector<char>& carries_pressure;
    const OperatorRadius& laplacian;
    const PressureSolveSettings& settings;
    double n0;
    double coefficient;  // 2d / (n0_L lambda_L), 1/m^2
    double source;       // relaxation rho / dt^2, kg/(m^3 s^2)
  };
  // An upper bound of particle i's entries: the diagonal and one per unknown neighbour or
  // wall-sample source in its lists (the count itself when the lists' radius is the
  // Laplacian's; a pair beyond it, or a term that is exactly 0, e.g. a sample of volume 0, makes
  // the row shorter, which the assembler closes up).
  int row_count(const RowInputs& in, std::size_t i) const;
  void assemble_row(const RowInputs& in, int row);
  // a_ij of one pair at distance r (1/m^2): the spec's coefficient w_L(r) or the HL term.
  static double laplacian_term(const RowInputs& in, double r);
  // The Dirichlet value of surface particle i (Pa): 0 unless settings.surface_offset > 0, then
  // surface_pressure (a fluid particle) or wall_surface_pressure (a wall particle).
  static double surface_value(const ParticleSet& particles, const NeighbourList& neighbours,
                              const OperatorRadius& radius, const PressureSolveSettings& settings, std::size_t i);
  // A wall surface particle's head: rho |g| max(0, offset - its height above its highest fluid
  // neighbour).
  static double wall_surface_pressure(const ParticleSet& particles, const NeighbourList& neighbours,
                                      const OperatorRadius& radius, const PressureSolveSettings& settings,
                                      std::size_t i);
  // A fluid surface particle's head: rho |g| offset where its water lies below it, else 0.
  static double surface_pressure(const ParticleSet& particles, const NeighbourList& neighbours,
                                 const OperatorRadius& radius, const PressureSolveSettings& settings, std::size_t i);

  std::vector<int> row_of_;  // particle -> unknown index, -1 if not an unknown
  std::vector<int> particle_of_;
  std::vector<char> grounded_;     // per unknown: touches a Dirichlet particle
  std::vector<char> reached_;      // per unknown: connected to a grounded one (pin_ungrounded_groups scratch)
  CsrInPlaceAssembler assembler_;  // rows straight into matrix_ (no padded copy beside it)
  CsrMatrix matrix_;
  std::vector<double> rhs_;  // Pa/m^2
  ProjectionSolver solver_;
};

}  // namespace mps_lab::mps
