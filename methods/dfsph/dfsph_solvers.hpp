#pragma once
// The two implicit solvers of DFSPH [BK17], matrix-free over the cached neighbour list.
// Both are the paper's Jacobi-like iteration: every particle computes its stiffness increment
// from the current predicted error and its factor alpha_i, then every fluid velocity is
// corrected with the symmetric pressure force of those increments ([BK17] eqs. (7)-(8)), then
// the error is predicted again from the new velocities. Only compression is corrected (the
// predicted density is clamped at rho0 and the density change rate at 0), so a free surface
// needs no special treatment and stiffnesses never become negative.
//
// Stopping rule (both solvers): iterate while (iterations < min_iterations) or (error >
// tolerance and iterations < max_iterations). The error is measured after each velocity
// correction, so the reported error is the one of the velocities the solver returns.
//   density solver:    error = mean_i max(rho*_i - rho0, 0) / rho0,     rho*_i = rho_i + dt D rho_i/Dt
//   divergence solver: error = dt mean_i max(D rho_i/Dt, 0) / rho0
// means over the active fluid particles (a particle with no compression counts as 0).
//
// How an iteration runs (docs/methods/dfsph.md, "Performance"): two passes over the fluid
// particles in one OpenMP parallel region, each writing only its own particle:
//   correct: kappa_i += pending increment; v_i += dt (pressure acceleration of the increments);
//   predict: D rho_i/Dt from the new velocities, the error of i, and i's next increment
//            (kept pending: applied only if the stopping rule asks for another iteration).
// The mean error is a sum over fixed blocks of fluid particles whose partial sums are added in
// block order, by every thread alike, so the result and the iteration count do not depend on
// the thread count. Every sum over neighbours runs in neighbour-list order over the cached
// kernel gradients, in the arithmetic of compute_density_change_rate.
#include <cstdint>
#include <vector>

#include "methods/dfsph/dfsph_operators.hpp"

namespace mps_lab::dfsph {

struct SolverSettings {
  double tolerance = 1e-4;  // relative, see above
  long long min_iterations = 2;
  long long max_iterations = 100;
  double warm_start_fraction = 0.5;  // share of the last step's stiffness applied first (0: cold start)
  // Apply the starting stiffness everywhere, not only where the particle is compressed now:
  // set when it is this step's own estimate (the global solve, dfsph_global_density.hpp).
  bool keep_uncompressed = false;
  // Also iterate until every particle's relative error is at most this (0: off, [BK17]'s mean
  // alone). The mean over a million particles lets a band of 1e4 particles stay 1 % compressed.
  double local_tolerance = 0.0;
};

struct SolverOutcome {
  long long iterations = 0;
  double initial_error = 0.0;  // before the first iteration (after the warm start)
  double error = 0.0;          // achieved
  double largest_error = 0.0;  // achieved, the largest relative error of a particle
  bool converged = true;       // error <= tolerance (and largest_error <= local_tolerance when set)
};

// Scratch storage reused from step to step (resized, never shrunk: no allocation in the time
// loop once the particle count is reached).
struct SolverWorkspace {
  std::vector<std::uint32_t> fluid;            // indices of the fluid particles, ascending
  std::vector<Vec2> velocity;                  // the solver's velocities: fluid v_i, 0 elsewhere (v_b = 0), m/s
  std::vector<double> increment;               // kappa increment of the next correction, m^2/s^2
  std::vector<double> stiffness_over_density;  // s_i = increment / rho_i of the next correction, m^5/(kg s^2)
  std::vector<double> block_error;             // partial sums of the relative error, one per block
  std::vector<double> block_largest;           // the largest relative error, one per block
  std::vector<double> neighbour_counts;        // fluid + boundary neighbours (+ sample volumes)
  std::vector<double> neighbour_mass;          // m_j, when the kernel cache has none (kg/m)
};

// Algorithm 2 of [BK17] (§3.2): corrects the velocities so that D rho_i/Dt = 0, with
//   kappa^v_i = (1/dt) (D rho_i/Dt) alpha_i        ([BK17] eq. (11), m^2/s^2).
// Fluid particles with fewer than `min_neighbours` fluid + boundary neighbours are not
// corrected (their rate counts as 0; the authors' "particle deficiency" rule).
// `stiffness` holds the last step's total kappa^v on entry (warm start) and this step's on exit.
SolverOutcome correct_divergence_error(ParticleSet& particles, const SphSystem& system,
                                       const std::vector<double>& density, const std::vector<double>& alpha, double dt,
                                       const SolverSettings& settings, std::uint32_t min_neighbours,
                                       std::vector<double>& stiffness, SolverWorkspace& workspace);

// Algorithm 3 of [BK17] (§3.3): corrects the predicted velocities v* so that the predicted
// density rho*_i = rho_i + dt D rho_i/Dt equals rho0, with
//   kappa_i = (rho*_i - rho0) / dt^2 alpha_i        ([BK17] eq. (12), m^2/s^2).
// `stiffness` holds the last step's total kappa on entry (warm start) and this step's on exit;
// kappa_i rho_i is the pressure (Pa) this solver applied.
SolverOutcome correct_density_error(ParticleSet& particles, const SphSystem& system, const std::vector<double>& density,
                                    const std::vector<double>& alpha, double dt, const SolverSettings& settings,
                                    std::vector<double>& stiffness, SolverWorkspace& workspace);

}  // namespace mps_lab::dfsph
