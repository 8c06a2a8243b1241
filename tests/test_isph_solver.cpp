// The ISPH pressure solve (BiCGSTAB on the fluid + wall system): its stopping rule, its
// iteration cap, the residual it reports, warm start and the preconditioners, on a real
// system: the dam break after its first step, with the density-invariance source.
#include <cmath>

#include <catch2/catch.hpp>

#include "core/kernels/sph_kernels.hpp"
#include "core/run/driver.hpp"
#include "methods/isph/isph_operators.hpp"
#include "methods/isph/isph_pressure.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::isph;
using namespace mps_lab::testing;

namespace {

struct System {
  ParticleSet particles;
  NeighbourList neighbours;
  SphKernel kernel{SphKernelKind::CubicSpline, 1.0};
  std::vector<double> density, surface, source;
  PressureSolveSettings settings;
};

// The dam break after one ISPH step (particles at r^1, surface flags and rho* of that step),
// with S_i = (rho0 - rho*_i) / (rho0 dt^2): 144 fluid and 65 wall unknowns.
System dam_break_system() {
  const Scene scene = load("dambreak.json");
  Simulation simulation(scene, *registries().methods.find("isph"));
  simulation.advance();
  System system;
  system.particles = simulation.particles();
  const double l0 = scene.particle_spacing, rho0 = scene.physics.density, dt = scene.time.time_step;
  system.kernel = SphKernel(SphKernelKind::CubicSpline, 2.4 * l0);
  system.neighbours = find_neighbours(system.particles.position, system.particles.type, system.kernel.support());
  system.density.assign(system.particles.size(), rho0);
  system.surface = system.particles.field("free_surface");
  system.source.assign(system.particles.size(), 0.0);
  const auto& rho_star = system.particles.field("density");
  for (std::size_t i = 0; i < system.particles.size(); ++i) {
    if (system.particles.type[i] == ParticleType::Fluid) system.source[i] = (rho0 - rho_star[i]) / (rho0 * dt * dt);
    system.particles.pressure[i] = 0.0;
  }
  system.settings.rest_density = rho0;
  system.settings.spacing = l0;
  system.settings.mass = rho0 / lattice_kernel_sum(system.kernel, l0);
  system.settings.eta2 = std::pow(0.12 * l0, 2);
  system.settings.gravity = scene.physics.gravity;
  system.settings.warm_start = false;
  return system;
}

// ||b - A p|| / ||b|| recomputed from the assembled system and the pressures written back.
double recomputed_residual(const PressurePoissonSolver& solver, const ParticleSet& particles) {
  Eigen::VectorXd p(static_cast<Eigen::Index>(solver.particle_of_row().size()));
  for (std::size_t row = 0; row < solver.particle_of_row().size(); ++row) {
    p[static_cast<Eigen::Index>(row)] = particles.pressure[static_cast<std::size_t>(solver.particle_of_row()[row])];
  }
  return (solver.rhs() - solver.matrix() * p).norm() / solver.rhs().norm();
}

}  // namespace

TEST_CASE("ISPH BiCGSTAB stops at its tolerance - respects its cap and reports the true residual", "[isph]") {
  System system = dam_break_system();
  PressurePoissonSolver solver;

  // A loose tolerance: converged, residual at or below it, and the reported residual is the
  // one of the pressures written back (recomputed, not BiCGSTAB's recurrence estimate).
  system.settings.tolerance = 1e-3;
  ParticleSet loose_particles = system.particles;
  const PressureSolveResult loose = solver.solve(loose_particles, system.neighbours, system.kernel, system.density,
                                                 system.surface, system.source, system.settings);
  INFO("loose: " << loose.iterations << " iterations, residual " << loose.residual << "; unknowns "
                 << loose.fluid_unknowns << " fluid + " << loose.wall_unknowns << " wall");
  CHECK(loose.fluid_unknowns > 100u);
  CHECK(loose.wall_unknowns > 50u);
  CHECK(loose.converged);
  CHECK(loose.residual <= 1e-3);
  CHECK(loose.residual == Approx(recomputed_residual(solver, loose_particles)).epsilon(1e-6));
  // "Just below": measured residual histories of this system (capping at k = 1..45 iterations,
  // first step and step 400 of the dam break) fall by a factor of 1.4-3 per iteration and never
  // by more than 8x in one iteration above round-off (1e-3 is reached after 20 iterations, 1e-10
  // after 37). Stopping at the first iterate below 1e-3 therefore lands above 1e-3 / 8; below
  // 1e-3 / 30 the rule would not have been checked at every iteration.
  CHECK(loose.residual > 1e-3 / 30.0);

  // A tight tolerance needs more iterations and reaches it.
  system.settings.tolerance = 1e-10;
  ParticleSet tight_particles = system.particles;
  const PressureSolveResult tight = solver.solve(tight_particles, system.neighbours, system.kernel, system.density,
                                                 system.surface, system.source, system.settings);
  INFO("tight: " << tight.iterations << " iterations, residual " << tight.residual);
  CHECK(tight.converged);
  CHECK(tight.residual <= 1e-10);
  CHECK(tight.iterations > loose.iterations);
  CHECK(tight.residual == Approx(recomputed_residual(solver, tight_particles)).epsilon(1e-3));

  // The iteration cap is respected and reported: 3 iterations, not converged, residual above.
  system.settings.max_iterations = 3;
  ParticleSet capped_particles = system.particles;
  const PressureSolveResult capped = solver.solve(capped_particles, system.neighbours, system.kernel, system.density,
                                                  system.surface, system.source, system.settings);
  INFO("capped: " << capped.iterations << " iterations, residual " << capped.residual);
  CHECK(capped.iterations == 3);
  CHECK_FALSE(capped.converged);
  CHECK(capped.residual > 1e-10);
  CHECK(capped.residual == Approx(recomputed_residual(solver, capped_particles)).epsilon(1e-6));

  // Warm start from the converged pressure: nothing left to do.
  system.settings.max_iterations = 1000;
  system.settings.warm_start = true;
  const PressureSolveResult warm = solver.solve(tight_particles, system.neighbours, system.kernel, system.density,
                                                system.surface, system.source, system.settings);
  CHECK(warm.iterations == 0);
  CHECK(warm.residual <= 1e-10);
}

TEST_CASE("ISPH solve: both preconditioners give the same pressure - incomplete LU in fewer iterations", "[isph]") {
  System system = dam_break_system();
  PressurePoissonSolver solver;
  system.settings.tolerance = 1e-10;
  ParticleSet diagonal_particles = system.particles, lut_particles = system.particles;
  system.settings.preconditioner = PreconditionerKind::Jacobi;
  const PressureSolveResult diagonal = solver.solve(diagonal_particles, system.neighbours, system.kernel,
                                                    system.density, system.surface, system.source, system.settings);
  system.settings.preconditioner = PreconditionerKind::IncompleteFactorisation;
  const PressureSolveResult lut = solver.solve(lut_particles, system.neighbours, system.kernel, system.density,
                                               system.surface, system.source, system.settings);
  INFO("diagonal " << diagonal.iterations << ", incomplete LU " << lut.iterations << " iterations");
  CHECK(diagonal.converged);
  CHECK(lut.converged);
  CHECK(lut.iterations < diagonal.iterations);
  // Same solution: both within 1e-10 of b, and the system's condition number is modest
  // (rows scaled to Pa), so pressures agree to far better than 1e-4 of the largest (~kPa).
  double largest = 0.0, difference = 0.0;
  for (std::size_t i = 0; i < system.particles.size(); ++i) {
    largest = std::max(largest, std::fabs(diagonal_particles.pressure[i]));
    difference = std::max(difference, std::fabs(diagonal_particles.pressure[i] - lut_particles.pressure[i]));
  }
  CHECK(largest > 1000.0);
  CHECK(difference < 1e-4 * largest);
}
