#include "methods/dfsph/dfsph_solvers.hpp"

#include <algorithm>
#include <cstddef>

namespace mps_lab::dfsph {
namespace {

// Mean of per-particle errors over the fluid particles, summed in index order (the same
// result whatever the thread count).
double fluid_mean(const ParticleSet& particles, const std::vector<double>& values) {
  double sum = 0.0;
  std::size_t count = 0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] != ParticleType::Fluid) continue;
    sum += values[i];
    ++count;
  }
  return count > 0 ? sum / static_cast<double>(count) : 0.0;
}

// The iteration shared by Algorithms 2 and 3 of [BK17].
//   predict():    fills workspace.source from the current velocities, returns the error;
//   increment(i): the stiffness increment of fluid particle i from workspace.source (>= 0).
template <class Predict, class Increment>
SolverOutcome iterate(ParticleSet& particles, const SphSystem& system, const std::vector<double>& density, double dt,
                      const SolverSettings& settings, std::vector<double>& stiffness, SolverWorkspace& workspace,
                      Predict predict, Increment increment) {
  const std::size_t n = particles.size();
  const auto count = static_cast<std::ptrdiff_t>(n);
  stiffness.resize(n, 0.0);
  auto& s = workspace.stiffness_over_density;
  s.assign(n, 0.0);

  double error = predict();
  // Warm start ([BK17]; the fraction and the reset are the authors' code's): apply the last
  // step's total stiffness, times the fraction, to the particles that are compressed now;
  // the others start from zero, so that a stiffness left over from a past compression
  // cannot push apart particles that are no longer compressed (increments are >= 0: a
  // stiffness can only grow within a step).
  const bool warm = settings.warm_start_fraction > 0.0;
#pragma omp parallel for schedule(static) if (count >= kThreadedLoopMinimum)
  for (std::ptrdiff_t i = 0; i < count; ++i) {
    const bool keep = warm && particles.type[i] == ParticleType::Fluid && increment(i) > 0.0;
    stiffness[i] = keep ? settings.warm_start_fraction * stiffness[i] : 0.0;
    s[i] = keep ? stiffness[i] / density[i] : 0.0;
  }
  if (warm) {
    apply_pressure_velocity_change(particles, system, s, dt);
    error = predict();
  }

  SolverOutcome outcome;
  outcome.initial_error = error;
  while (outcome.iterations < settings.max_iterations &&
         (outcome.iterations < settings.min_iterations || error > settings.tolerance)) {
#pragma omp parallel for schedule(static) if (count >= kThreadedLoopMinimum)
    for (std::ptrdiff_t i = 0; i < count; ++i) {
      if (particles.type[i] != ParticleType::Fluid) {
        s[i] = 0.0;
        continue;
      }
      const double change = increment(i);  // m^2/s^2
      stiffness[i] += change;
      s[i] = change / density[i];
    }
    apply_pressure_velocity_change(particles, system, s, dt);
    error = predict();
    ++outcome.iterations;
  }
  outcome.error = error;
  outcome.converged = error <= settings.tolerance;
  return outcome;
}

}  // namespace

SolverOutcome correct_divergence_error(ParticleSet& particles, const SphSystem& system,
                                       const std::vector<double>& density, const std::vector<double>& alpha,
                                       double dt, const SolverSettings& settings, std::uint32_t min_neighbours,
                                       std::vector<double>& stiffness, SolverWorkspace& workspace) {
  count_active_neighbours(particles, system, workspace.neighbour_counts);
  auto& rate = workspace.source;  // max(D rho_i/Dt, 0), kg/(m^3 s)
  auto& relative = workspace.relative_error;
  relative.assign(particles.size(), 0.0);
  const auto count = static_cast<std::ptrdiff_t>(particles.size());
  const double rho0 = system.rest_density;
  const auto predict = [&]() {
    compute_density_change_rate(particles, system, rate);  // [BK17] eq. (9)
#pragma omp parallel for schedule(static) if (count >= kThreadedLoopMinimum)
    for (std::ptrdiff_t i = 0; i < count; ++i) {
      // Only compression is corrected; a particle short of neighbours is left alone.
      if (workspace.neighbour_counts[i] < min_neighbours) rate[i] = 0.0;
      rate[i] = std::max(rate[i], 0.0);
      relative[i] = dt * rate[i] / rho0;
    }
    return fluid_mean(particles, relative);
  };
  const auto increment = [&](std::ptrdiff_t i) { return rate[i] / dt * alpha[i]; };  // [BK17] eq. (11)
  return iterate(particles, system, density, dt, settings, stiffness, workspace, predict, increment);
}

SolverOutcome correct_density_error(ParticleSet& particles, const SphSystem& system,
                                    const std::vector<double>& density, const std::vector<double>& alpha, double dt,
                                    const SolverSettings& settings, std::vector<double>& stiffness,
                                    SolverWorkspace& workspace) {
  auto& predicted = workspace.source;  // max(rho*_i, rho0), kg/m^3
  auto& relative = workspace.relative_error;
  relative.assign(particles.size(), 0.0);
  const auto count = static_cast<std::ptrdiff_t>(particles.size());
  const double rho0 = system.rest_density;
  const auto predict = [&]() {
    compute_density_change_rate(particles, system, predicted);
#pragma omp parallel for schedule(static) if (count >= kThreadedLoopMinimum)
    for (std::ptrdiff_t i = 0; i < count; ++i) {
      // rho*_i = rho_i + dt D rho_i/Dt ([BK17] §3.3), clamped: only compression is corrected.
      predicted[i] = particles.type[i] == ParticleType::Fluid ? std::max(density[i] + dt * predicted[i], rho0) : rho0;
      relative[i] = (predicted[i] - rho0) / rho0;
    }
    return fluid_mean(particles, relative);
  };
  const double inverse_dt2 = 1.0 / (dt * dt);
  const auto increment = [&](std::ptrdiff_t i) {
    return (predicted[i] - rho0) * inverse_dt2 * alpha[i];  // [BK17] eq. (12)
  };
  return iterate(particles, system, density, dt, settings, stiffness, workspace, predict, increment);
}

}  // namespace mps_lab::dfsph
