#pragma once
// A density solve with global reach for DFSPH (methods.dfsph.density_solver = "amg_cg";
// docs/methods/dfsph.md, "A density solve with global reach").
//
// [BK17]'s density solver (Algorithm 3, dfsph_solvers.hpp) is a relaxed Jacobi iteration: an
// iteration carries a stiffness one kernel radius further, so a column n particles high
// needs of the order of n^2 iterations to build its hydrostatic pressure from rest, and a warm
// start that resets the stiffness "where not compressed" rebuilds it every step (measured in
// docs/performance.md: from rest at a million particles it does not reach 0.01 %). This solve
// writes the same constraints as one linear system and solves it with conjugate gradients
// preconditioned by smoothed-aggregation AMG (core/linalg/amg.hpp), whose coarse levels reach
// the whole column in every iteration.
//
// The constraint. With s_i = kappa_i / rho_i, one correction changes the velocities by
// -dt G_i(s), G_i(s) = sum_j (s_i + s_j) c_ij ([BK17] eqs. (7)-(8); a boundary neighbour has
// s = 0, the mirrored wall pressure), and the density change rate by D_i(dv) = sum_j c_ij .
// (dv_i - dv_j) ([BK17] eq. (9); boundary particles do not move), c_ij = m_j grad W_ij. The
// predicted density rho*_i = rho_i + dt D_i(v* - dt G(s)) is rho0 when
//   D G s = b,   b_i = (rho*_i(v*) - rho0) / dt^2   (kg/(m^3 s^2)).
// D G is a two-ring operator (tests/test_dfsph_global_density.cpp writes it out) and is not
// solved as it stands: it is G^T G, whose near-null space (pressure modes that alternate from
// particle to particle, with no gradient at the particles) gives the exact solution of a noisy
// b huge alternating parts (measured: with the exact two-ring matrix the dam break from rest
// diverged in 3-5 steps). The relaxed Jacobi iteration never excites those modes.
//
// The surrogate solved here. For smooth s, G s ~ rho0 grad s and D v ~ -rho0 div v, so
// D G s ~ -rho0^2 lap s. The linear system is
//   A s = b,  A = -rho0^2 <lap>,  <lap> the one-ring SPH Laplacian of Cummins & Rudman (1999):
//   (A s)_i = sum_j a_ij (s_i - s_j),  a_ij = 2 rho0 m (-r_ij . grad W_ij) / (|r_ij|^2 + eta^2),
// over the fluid neighbours j, eta = 0.1 l0; a boundary neighbour adds nothing (the wall's
// pressure is the fluid's own, mirrored: a Neumann wall). A is a symmetric M-matrix, positive
// definite once a row touches a Dirichlet particle (a group that touches none is pinned as
// mps's are, core/linalg/pressure_system.hpp). It has the long-range, smooth part of [BK17]'s
// operator and none of its alternating near-null space; the relaxed Jacobi iteration, which
// reduces the local error in a few iterations, supplies the rest.
//
// The clamp. [BK17] corrects only compression (rho* clamped at rho0, stiffness >= 0): a
// complementarity problem, not a linear one. Here (decisions in docs/methods/dfsph.md):
//   - the unknowns are the fluid particles with a full neighbourhood (the divergence solver's
//     "particle deficiency" rule: at least divergence_neighbour_fraction of the lattice's
//     neighbours); the others, the free surface, keep s = 0 (Dirichlet, as isph's surface);
//   - b_i = max(Shepard average of rho*_j - rho0 around i, 0) / dt^2: compression only, the
//     clamp after the average (right_hand_side in the .cpp);
//   - negative solutions are clamped to 0;
//   - the relaxed Jacobi iteration of dfsph_solvers.hpp then starts from this stiffness, kept
//     in full, and finishes under [BK17]'s clamp and stopping rule (density_tolerance).
// The stopping rule, the reported error and the pressure are therefore [BK17]'s.
//
// Requires boundary particles (akinci_boundary, dummy_layers) and wall_pressure = "mirrored":
// wall samples and the extrapolated wall pressure are not part of this surrogate.
#include <cstdint>
#include <memory>
#include <vector>

#include "core/linalg/krylov.hpp"
#include "core/linalg/projection_solver.hpp"
#include "core/linalg/sparse_matrix.hpp"
#include "methods/dfsph/dfsph_operators.hpp"

namespace mps_lab::dfsph {

// The defaults of methods.dfsph.density_cg_tolerance and density_cg_max_iterations.
constexpr double kDefaultCgTolerance = 1.0e-3;
constexpr long long kDefaultCgIterations = 200;
// ... and of density_cg_cycles and density_cg_smoothing (the method's cycles, dfsph_method.cpp).
constexpr long long kDefaultCgCycles = 4;
constexpr long long kDefaultCgSmoothing = 2;

struct GlobalDensitySettings {
  double tolerance = kDefaultCgTolerance;           // relative residual ||b - A s|| / ||b|| of the CG solve
  long long max_iterations = kDefaultCgIterations;  // CG iterations
  std::uint32_t min_neighbours = 0;                 // an unknown needs this many fluid + boundary neighbours
};

struct GlobalDensityOutcome {
  bool solved = false;       // false: nothing compressed, no solve
  long long iterations = 0;  // CG iterations
  double residual = 0.0;     // achieved relative residual
  bool converged = true;
  std::size_t unknowns = 0;  // rows of A
};

// Storage reused from step to step (never shrunk: nothing is allocated once the sizes are seen).
struct GlobalDensityWorkspace {
  std::vector<int> row_of;             // by particle: its row, -1 for no unknown
  std::vector<int> particle_of;        // by row: its particle
  std::vector<double> rhs;             // b, kg/(m^3 s^2)
  std::vector<double> excess;          // rho*_i - rho0 by particle (fluid), kg/m^3
  std::vector<double> solution;        // ds by row, m^5/(kg s^2)
  std::vector<double> neighbour_mass;  // m_j when the kernel cache has none, kg/m
  std::vector<char> grounded;          // by row: touches a Dirichlet particle
  std::vector<char> reached;           // scratch of pin_ungrounded_groups
  std::size_t ungrounded_groups = 0;   // pinned in the last system
  CsrMatrix matrix;
  std::unique_ptr<Preconditioner> preconditioner;  // AMG, set up once per step
  KrylovWorkspace krylov;
};

// The unknowns and A of this step, and A's AMG hierarchy (once per step: A depends on the
// positions only). `counts` are count_active_neighbours' (fluid + boundary neighbours per
// fluid particle). Returns the rows.
std::size_t assemble_density_system(const ParticleSet& particles, const SphSystem& system,
                                    const std::vector<double>& counts, const GlobalDensitySettings& settings,
                                    GlobalDensityWorkspace& workspace);

// b of the current velocities (particles.velocity) into workspace.rhs (exposed for the tests):
//   b_i = max(<rho* - rho0>_i, 0) / dt^2,  <.>_i the Shepard average over the fluid in the
// kernel's support of the predicted excess rho*_j - rho0 = rho_j + dt D_j(v) - rho0
// (only compression is a source, as in [BK17]; the average comes first: the .cpp says why).
void density_right_hand_side(const ParticleSet& particles, const SphSystem& system, const std::vector<double>& density,
                             double dt, GlobalDensityWorkspace& workspace);

// One global correction: b from the current velocities, A ds = b by AMG-preconditioned CG
// from ds = 0, and kappa_i <- max(kappa_i + rho_i ds_i, 0) on the unknowns (`stiffness`, m^2/s^2).
// Nothing is solved (and nothing changed) when no unknown is compressed.
GlobalDensityOutcome add_density_increment(const ParticleSet& particles, const SphSystem& system,
                                           const std::vector<double>& density, double dt,
                                           const GlobalDensitySettings& settings, std::vector<double>& stiffness,
                                           GlobalDensityWorkspace& workspace);

}  // namespace mps_lab::dfsph
