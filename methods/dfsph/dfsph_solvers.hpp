#pragma once
// The two implicit solvers of DFSPH [BK17], matrix-free over the cached neighbour list.
// Both are the paper's Jacobi-like iteration: every particle computes its stiffness increment
// from the current predicted error and its factor alpha_i, then every fluid velocity is
// corrected with the symmetric pressure force of those increments
// (apply_pressure_velocity_change), then the error is predicted again from the new
// velocities. Only compression is corrected (the predicted density is clamped at rho0 and
// the density change rate at 0), so a free surface needs no special treatment and
// stiffnesses never become negative.
//
// Stopping rule (both solvers): iterate while (iterations < min_iterations) or (error >
// tolerance and iterations < max_iterations). The error is measured after each velocity
// correction, so the reported error is the one of the velocities the solver returns.
//   density solver:    error = mean_i max(rho*_i - rho0, 0) / rho0,     rho*_i = rho_i + dt D rho_i/Dt
//   divergence solver: error = dt mean_i max(D rho_i/Dt, 0) / rho0
// means over the active fluid particles (a particle with no compression counts as 0).
#include <cstdint>
#include <vector>

#include "methods/dfsph/dfsph_operators.hpp"

namespace mps_lab::dfsph {

struct SolverSettings {
  double tolerance = 1e-4;          // relative, see above
  long long min_iterations = 2;
  long long max_iterations = 100;
  double warm_start_fraction = 0.5;  // share of the last step's stiffness applied first (0: cold start)
};

struct SolverOutcome {
  long long iterations = 0;
  double initial_error = 0.0;  // before the first iteration (after the warm start)
  double error = 0.0;          // achieved
  bool converged = true;       // error <= tolerance
};

// Scratch storage reused from step to step.
struct SolverWorkspace {
  std::vector<double> source;                  // rho*_i (kg/m^3) or D rho_i/Dt (kg/(m^3 s))
  std::vector<double> stiffness_over_density;  // s_i = kappa_i / rho_i of one correction, m^5/(kg s^2)
  std::vector<double> relative_error;          // per particle, for the mean
  std::vector<double> neighbour_counts;      // fluid + boundary neighbours (+ sample volumes)
};

// Algorithm 2 of [BK17] (§3.2): corrects the velocities so that D rho_i/Dt = 0, with
//   kappa^v_i = (1/dt) (D rho_i/Dt) alpha_i        ([BK17] eq. (11), m^2/s^2).
// Fluid particles with fewer than `min_neighbours` fluid + boundary neighbours are not
// corrected (their rate counts as 0; the authors' "particle deficiency" rule).
// `stiffness` holds the last step's total kappa^v on entry (warm start) and this step's on exit.
SolverOutcome correct_divergence_error(ParticleSet& particles, const SphSystem& system,
                                       const std::vector<double>& density, const std::vector<double>& alpha,
                                       double dt, const SolverSettings& settings, std::uint32_t min_neighbours,
                                       std::vector<double>& stiffness, SolverWorkspace& workspace);

// Algorithm 3 of [BK17] (§3.3): corrects the predicted velocities v* so that the predicted
// density rho*_i = rho_i + dt D rho_i/Dt equals rho0, with
//   kappa_i = (rho*_i - rho0) / dt^2 alpha_i        ([BK17] eq. (12), m^2/s^2).
// `stiffness` holds the last step's total kappa on entry (warm start) and this step's on exit;
// kappa_i rho_i is the pressure (Pa) this solver applied.
SolverOutcome correct_density_error(ParticleSet& particles, const SphSystem& system,
                                    const std::vector<double>& density, const std::vector<double>& alpha, double dt,
                                    const SolverSettings& settings, std::vector<double>& stiffness,
                                    SolverWorkspace& workspace);

}  // namespace mps_lab::dfsph
