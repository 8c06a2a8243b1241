// EISPH (methods/eisph/): the one relaxation sweep per step against a hand computation, its
// convergence to isph's implicit solution when repeated, still water, the dam break against
// Martin & Moyce and the time-step rule. The contract suite (tests/test_contract.cpp) runs it
// too (still water, walls, determinism, resume, divergence, parameters).
#if defined(MPS_LAB_WITH_EISPH)
#include <algorithm>
#include <cmath>
#include <limits>

#include <catch2/catch.hpp>

#include "core/kernels/sph_kernels.hpp"
#include "core/run/driver.hpp"
#include "dambreak_checks.hpp"
#include "methods/eisph/eisph_relaxation.hpp"
#include "support.hpp"
#if defined(MPS_LAB_WITH_ISPH)
#include "methods/isph/isph_pressure.hpp"
#endif

using namespace mps_lab;
using namespace mps_lab::eisph;
using namespace mps_lab::testing;

namespace {

const WallSampleList no_samples;  // boundary of wall particles: no wall samples

// Three particles on a horizontal line, l0 apart: wall - fluid - wall (index 0, 1, 2).
ParticleSet three_in_a_row(double l0) {
  ParticleSet particles;
  for (std::size_t k = 0; k < 3; ++k) {
    particles.add(Vec2(static_cast<double>(k) * l0, 0.0), Vec2::Zero(),
                  k == 1 ? ParticleType::Fluid : ParticleType::Wall);
  }
  return particles;
}

}  // namespace

TEST_CASE("EISPH one sweep on three particles equals the hand computation", "[eisph][unit]") {
  const double l0 = 0.025, h = 1.2 * l0, rho0 = 1000.0, mass = 0.625;  // m, m, kg/m^3, kg/m
  const ParticleSet particles = three_in_a_row(l0);
  const SphKernel kernel(SphKernelKind::CubicSpline, 2.0 * h);
  const NeighbourList neighbours = find_neighbours(particles.position, particles.type, kernel.support());
  RelaxationSettings settings;
  settings.rest_density = rho0;
  settings.mass = mass;
  settings.eta2 = std::pow(0.1 * h, 2);
  settings.relaxation = 0.5;
  const std::vector<double> density(3, rho0), surface(3, 0.0), source = {0.0, -4.0e4, 0.0};  // S in 1/s^2
  const std::vector<double> previous = {100.0, 50.0, 300.0};                                 // Pa
  std::vector<double> pressure(3, -1.0);
  const SweepResult result = relaxation_sweep(particles, neighbours, no_samples, kernel, density, surface, source,
                                              settings, previous, pressure);

  // By hand: the cubic spline in 2-D, dW/dr = 10/(7 pi h^3) (-3 q + 9/4 q^2) at q = l0/h = 1/1.2;
  // F = r . grad W / (r^2 + eta^2) = -l0 |dW/dr| / (l0^2 + eta^2) for both neighbours;
  // a = -m 8/(2 rho0)^2 F; p_J = (a 100 + a 300 - S) / (2a) = 200 - S/(2a);
  // p = (1 - omega) 50 + omega p_J.
  const double pi = std::acos(-1.0), q = l0 / h;
  const double slope = 10.0 / (7.0 * pi * h * h * h) * (-3.0 * q + 2.25 * q * q);  // dW/dr < 0, 1/m^3
  const double factor = -l0 * std::fabs(slope) / (l0 * l0 + settings.eta2);        // 1/m^4
  const double a = -mass * 8.0 / std::pow(2.0 * rho0, 2) * factor;                 // m/kg
  const double jacobi = 200.0 - source[1] / (2.0 * a);
  const double expected = 0.5 * 50.0 + 0.5 * jacobi;
  INFO("a = " << a << " m/kg, Jacobi value " << jacobi << " Pa");
  // Only rounding separates the two evaluations (a few ulps of ~1e3 Pa).
  CHECK(pressure[1] == Approx(expected).epsilon(1e-12));
  CHECK(pressure[0] == -1.0);  // walls are not written by the sweep
  CHECK(pressure[2] == -1.0);
  CHECK(result.unknowns == 1u);
  CHECK(result.surface == 0u);
  CHECK(result.largest_change == Approx(std::fabs(expected - 50.0)).epsilon(1e-12));

  // On the free surface the sweep writes p = 0 whatever the previous pressure.
  const std::vector<double> on_surface = {0.0, 1.0, 0.0};
  const SweepResult held = relaxation_sweep(particles, neighbours, no_samples, kernel, density, on_surface, source,
                                            settings, previous, pressure);
  CHECK(pressure[1] == 0.0);
  CHECK(held.surface == 1u);
  CHECK(held.unknowns == 0u);
}

TEST_CASE("EISPH Adami wall pressure: the fluid pressure plus the hydrostatic head by hand", "[eisph][unit]") {
  // A wall particle l0 below one fluid particle: Adami et al. (2012) eq. 27 with one neighbour
  // gives p_w = p_f + g . rho0 (x_w - x_f) = p_f + rho0 |g| l0 (the kernel weight cancels).
  const double l0 = 0.025, rho0 = 1000.0;
  ParticleSet particles;  // wall, fluid above it, a lone wall far away
  particles.add(Vec2(0.0, 0.0), Vec2::Zero(), ParticleType::Wall);
  particles.add(Vec2(0.0, l0), Vec2::Zero(), ParticleType::Fluid);
  particles.add(Vec2(1.0, 0.0), Vec2::Zero(), ParticleType::Wall);
  const SphKernel kernel(SphKernelKind::CubicSpline, 2.4 * l0);
  const NeighbourList neighbours = find_neighbours(particles.position, particles.type, kernel.support());
  std::vector<double> pressure = {-5.0, 700.0, -5.0};
  adami_wall_pressure(particles, neighbours, kernel, std::vector<double>(3, rho0), Vec2(0.0, -9.81), pressure);
  CHECK(pressure[0] == Approx(700.0 + rho0 * 9.81 * l0).epsilon(1e-12));
  CHECK(pressure[1] == 700.0);  // fluid untouched
  CHECK(pressure[2] == 0.0);    // no fluid within the support
}

#if defined(MPS_LAB_WITH_ISPH)
TEST_CASE("EISPH sweeps repeated at fixed particles converge to the isph solve of the same PPE", "[eisph][unit]") {
  // The dam break after one eisph step: particles at r^1, its surface flags, S_i = (rho0 -
  // rho*_i)/(rho0 dt^2) (density invariance, a source of every sign), rho0 in the operators.
  const Scene scene = load("dambreak.json");
  Simulation simulation(scene, *registries().methods.find("eisph"));
  simulation.advance();
  ParticleSet particles = simulation.particles();
  const double l0 = scene.particle_spacing, rho0 = scene.physics.density, dt = simulation.last_time_step();
  const SphKernel kernel(SphKernelKind::CubicSpline, 2.4 * l0);
  const NeighbourList neighbours = find_neighbours(particles.position, particles.type, kernel.support());
  const std::vector<double> density(particles.size(), rho0);
  const std::vector<double> surface = particles.field("free_surface");
  const auto& rho_star = particles.field("density");
  std::vector<double> source(particles.size(), 0.0);
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] == ParticleType::Fluid) source[i] = (rho0 - rho_star[i]) / (rho0 * dt * dt);
    particles.pressure[i] = 0.0;
  }

  // The implicit solution: isph's BiCGSTAB to 1e-12.
  isph::PressureSolveSettings implicit;
  implicit.rest_density = rho0;
  implicit.spacing = l0;
  implicit.mass = rho0 / lattice_kernel_sum(kernel, l0);
  implicit.eta2 = std::pow(0.12 * l0, 2);
  implicit.gravity = scene.physics.gravity;
  implicit.tolerance = 1e-12;
  implicit.warm_start = false;
  ParticleSet solved = particles;
  isph::PressurePoissonSolver solver;
  const isph::PressureSolveResult solve = solver.solve(solved, neighbours, kernel, density, surface, source, implicit);
  REQUIRE(solve.converged);
  REQUIRE(solve.ungrounded_groups == 0u);  // no regularised row: the same equations on both sides
  double largest = 0.0;
  for (double p : solved.pressure) largest = std::max(largest, std::fabs(p));

  // EISPH: (WALL) then (SWEEP), omega = 1, from p = 0, k times.
  RelaxationSettings settings{rho0, implicit.mass, implicit.eta2, scene.physics.gravity, 1.0};
  std::vector<double> previous(particles.size(), 0.0), next(particles.size(), 0.0);
  const auto error_after = [&](int sweeps) {
    for (int k = 0; k < sweeps; ++k) {
      adami_wall_pressure(particles, neighbours, kernel, density, settings.gravity, previous);
      next = previous;
      relaxation_sweep(particles, neighbours, no_samples, kernel, density, surface, source, settings, previous, next);
      previous.swap(next);
    }
    adami_wall_pressure(particles, neighbours, kernel, density, settings.gravity, previous);
    double error = 0.0;
    for (std::size_t i = 0; i < particles.size(); ++i) {
      if (particles.type[i] != ParticleType::Ghost)
        error = std::max(error, std::fabs(previous[i] - solved.pressure[i]));
    }
    return error / largest;
  };
  const double e1 = error_after(1), e100 = error_after(99), e1000 = error_after(900), e2000 = error_after(1000);
  INFO("largest |p| " << largest << " Pa; max error / largest after 1, 100, 1000, 2000 sweeps: " << e1 << ", " << e100
                      << ", " << e1000 << ", " << e2000);
  // A block Jacobi iteration contracts the error by the same factor rho per sweep once the
  // slowest mode dominates. Measured: errors 0.69, 0.046, 7.0e-8, 1.1e-12 after 1, 100, 1000,
  // 2000 sweeps, so rho = (e1000 / e100)^(1/900) = 0.985; after 2000 sweeps the error is at the
  // floor of the reference itself (BiCGSTAB to a relative residual of 1e-12). Bounds: rho < 0.99
  // (a third of the measured distance to 1 as margin), and the 2000-sweep error below both the
  // contraction's prediction e100 0.99^1900 = 2.4e-10 and 1e-9.
  CHECK(e100 < e1);
  CHECK(e1000 < e100);
  CHECK(e2000 < e1000);
  const double contraction = std::pow(e1000 / e100, 1.0 / 900.0);  // per sweep
  INFO("contraction per sweep " << contraction);
  CHECK(contraction < 0.99);
  CHECK(e2000 < e100 * std::pow(0.99, 1900.0));
  CHECK(e2000 < 1e-9);
}
#endif

TEST_CASE("EISPH still water: time-mean bed pressure hydrostatic", "[eisph][validation]") {
  // scenes/hydrostatic.json (water 0.275 m deep between the bed surface and the top particle
  // centres, top row at y = 0.275 m) to 2 s with eisph's defaults; a wall transducer on the bed
  // at mid-width (core/run/pressure_sensors.hpp: it reads on the bed surface, y = l0/2 = 0.0125 m).
  const auto out = fresh_directory("eisph_still_water");
  RunOptions options;
  options.scene_path = scene_path("hydrostatic.json");
  options.method = "eisph";
  options.overrides = {R"(diagnostics.pressure_sensors=[{"name": "bed", "position": [0.25, 0.0]}])"};
  options.output_directory = out.string();
  const RunResult result = run_simulation(options, registries().methods, registries().walls);
  REQUIRE(result.status == "completed");
  const Table series = read_table(out / "series.csv");
  const auto time = series.column("time"), bed = series.column("pressure_bed"),
             energy = series.column("kinetic_energy");
  double sum = 0.0, largest_energy = 0.0;
  std::size_t count = 0;
  for (std::size_t k = 0; k < time.size(); ++k) {
    if (time[k] < 1.0) continue;
    sum += bed[k];
    ++count;
    largest_energy = std::max(largest_energy, energy[k]);
  }
  REQUIRE(count > 10u);
  const double mean = sum / static_cast<double>(count);
  // The Dirichlet surface lies at the top particle centres (p = 0 there, as isph) or half a
  // spacing above: rho g (0.275 - 0.0125) = 2575.1 Pa to rho g (0.2875 - 0.0125) = 2697.8 Pa.
  const double lower = 1000.0 * 9.81 * 0.2625, upper = 1000.0 * 9.81 * 0.275;
  INFO("time-mean bed pressure over [1, 2] s " << mean << " Pa (" << mean / lower
                                               << " of the lower reference); largest kinetic energy " << largest_energy
                                               << " J/m");
  // Measured with the earlier in-fluid sensor (bottom row, Shepard average): 0.992 of its lower
  // reference; with the bed transducer 2628 Pa = 1.021 of the lower one (2026-11-24). Bounds: 3 % below the lower
  // reference (the measured 0.8 % with margin for the sensor's averaging over a row that moves by a few per cent of l0)
  // and 5 % above the upper one, the README's "hydrostatic within 5 %" for mps.
  CHECK(mean > 0.97 * lower);
  CHECK(mean < 1.05 * upper);
}

TEST_CASE("EISPH initial_pressure hydrostatic: still water starts at rest instead of falling", "[eisph][validation]") {
  // scenes/hydrostatic.json to 0.5 s, every step in series.csv. From p = 0 (the default, Hosseini
  // et al. 2007) the column falls until one sweep per step has built its pressure; from the
  // hydrostatic pressure (core/io/geometry.hpp, zero at the top particle centres where the default
  // free_surface_offset puts p = 0) it starts in equilibrium. Measured 2026-11-28: largest kinetic
  // energy 3.26 J/m and largest mean density error 3.9 % from zero, 0.015 J/m and 0.30 % from the
  // hydrostatic pressure (0.010 J/m and 0.34 % with free_surface_offset 0.5). Bounds: kinetic
  // energy 0.05 J/m, 1/65 of the fall's; density error 1 %, the still-water target of issue 14
  // (a sensor reads the weight of the water above it, which a compressed column lowers by about
  // its density error).
  const auto largest = [](const std::string& start) {
    const auto out = fresh_directory("eisph_initial_pressure_" + start);
    RunOptions options;
    options.scene_path = scene_path("hydrostatic.json");
    options.method = "eisph";
    options.overrides = {"time.end_time=0.5", "output.series_every_steps=1", "output.frame_every_steps=100000",
                         "methods.eisph.initial_pressure=\"" + start + "\""};
    options.output_directory = out.string();
    const RunResult result = run_simulation(options, registries().methods, registries().walls);
    REQUIRE(result.status == "completed");
    const Table series = read_table(out / "series.csv");
    const auto energy = series.column("kinetic_energy"), error = series.column("density_error");
    return std::make_pair(*std::max_element(energy.begin(), energy.end()),
                          *std::max_element(error.begin(), error.end()));
  };
  const auto [zero_energy, zero_error] = largest("zero");
  const auto [hydrostatic_energy, hydrostatic_error] = largest("hydrostatic");
  INFO("largest kinetic energy (J/m) and density error from zero "
       << zero_energy << ", " << zero_error << "; from hydrostatic " << hydrostatic_energy << ", "
       << hydrostatic_error);
  CHECK(zero_energy > 1.0);  // the fall the option removes (the test sees the option ignored)
  CHECK(zero_error > 0.01);
  CHECK(hydrostatic_energy < 0.05);
  CHECK(hydrostatic_error < 0.01);
  // The start's zero is where the sweep holds p = 0: with free_surface_offset 0.5, l0/2 above the
  // top particle centres (0.275 m), so the bed row (y = 0.025 m) starts at rho0 g (0.2875 - 0.025).
  const Scene scene = load("hydrostatic.json",
                           {"methods.eisph.initial_pressure=\"hydrostatic\"", "methods.eisph.free_surface_offset=0.5"});
  const Simulation simulation(scene, *registries().methods.find("eisph"));
  const ParticleSet& particles = simulation.particles();
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] != ParticleType::Fluid) continue;
    CHECK(particles.pressure[i] == Approx(1000.0 * 9.81 * (0.2875 - particles.position[i].y())).epsilon(1e-12));
  }
}

TEST_CASE("EISPH dam break to 2 s on Martin & Moyce - nothing lost - nothing through the walls",
          "[eisph][validation]") {
  const DambreakOutcome outcome = run_spec_dambreak("eisph", 0.5);
  const RunEvaluation& e = outcome.evaluation;
  INFO("steps " << outcome.result.steps << "; front RMS " << e.front_rms << " max " << e.front_max << "; best shift "
                << e.front_shift << " -> RMS " << e.front_rms_shifted << "; height RMS " << e.height_rms << "; ghosts "
                << outcome.ghosts);
  // Measured (1121 steps): front RMS 0.098, max 0.165; best shift +0.071 -> 0.049; height RMS
  // 0.022; 7 ghosts (isph: 0.112, 0.050, 0.020, 8).
  // The bounds of docs/validation.md (as isph and mps): 0.15 is the RMS difference between two
  // independent experiments on this geometry; 0.10 with the best time shift is the noise floor
  // of the experiment; 0.08 in H* for the height (Table 6's rounding and digitisations).
  CHECK(e.front_rms < 0.15);
  CHECK(e.front_rms_shifted < 0.10);
  CHECK(e.height_rms < 0.08);
  CHECK(outcome.ghosts <= 17);  // more than 10 % of the water thrown out would be a different flow
}

TEST_CASE("EISPH load setting: the spec dam break to 2 s with every boundary model", "[eisph][validation]") {
  // The load setting (MethodInfo::load_setting: free_surface_offset 0.5, the hydrostatic start,
  // dry_wall_points "excluded") with each boundary model eisph supports, the bounds of the test
  // above. Measured 2026-11-28: front RMS 0.102-0.223 (mirror particles the highest), shifted
  // 0.064-0.082, 6-7 ghosts; 2026-11-29 (the exclusion, the wall points' wet share): 0.103-0.223,
  // shifted 0.062-0.094, 5-8 ghosts. From p = 0 (the setting before 2026-11-28) the distance
  // function diverged at the far-wall impact (step 194, 0.355 s) in each of 6 realisations; from
  // the hydrostatic pressure it completes.
  check_load_setting_dambreak("eisph");
}

TEST_CASE("EISPH sweeps_per_step: at a 0.5 ms step one sweep loses the mirror particles' impact, four keep it",
          "[eisph][validation]") {
  // The spec's dam break to 0.5 s with the load setting, mirror_particles and the step bounded at
  // 0.5 ms (force_number 0.009: 0.009 sqrt(0.03 / 9.81) = 4.98e-4 s). Measured 2026-12-08: one
  // sweep per step diverges at the far-wall impact (energy growth, t = 0.3315 s, step 663), as
  // docs/methods/eisph.md's table of steps records; 2, 4, 6 and 16 sweeps complete the impact
  // (and the 2 s run). The test fails if the option is ignored (then 4 behaves as 1) or if the
  // repeated pass is not the full (WALL)-(SWEEP) pair. series.csv reports the sweeps per step.
  const auto run_with = [](int sweeps) {
    const MethodInfo& method = *registries().methods.find("eisph");
    std::vector<std::string> overrides = load_setting_with(method, "mirror_particles");
    overrides.insert(overrides.end(),
                     {"time.end_time=0.5", "methods.eisph.force_number=0.009",
                      "methods.eisph.sweeps_per_step=" + std::to_string(sweeps), "output.frame_every_steps=100000"});
    const auto out = fresh_directory("eisph_sweeps_" + std::to_string(sweeps));
    RunOptions options;
    options.scene_path = scene_path("dambreak.json");
    options.method = "eisph";
    options.overrides = overrides;
    options.output_directory = out.string();
    RunResult result = run_simulation(options, registries().methods, registries().walls);
    return std::make_pair(result, out);
  };
  const auto [one, one_out] = run_with(1);
  INFO("one sweep: " << one.status << " at t = " << one.simulated_time << " s");
  CHECK(one.status == "diverged");
  CHECK(one.simulated_time < 0.4);  // at the impact on the far wall (0.33 s)
  const auto [four, four_out] = run_with(4);
  INFO("four sweeps: " << four.status << " at t = " << four.simulated_time << " s");
  REQUIRE(four.status == "completed");
  CHECK(four.simulated_time == Approx(0.5).epsilon(1e-12));
  CHECK(four.summary["method_summary"]["relaxation_sweeps_per_step"].get<int>() == 4);
  const Table series = read_table(four_out / "series.csv");
  const auto time = series.column("time"), iterations = series.column("solver_iterations");
  for (std::size_t k = 0; k < time.size(); ++k) {
    if (time[k] > 0.0) CHECK(iterations[k] == 4.0);  // the row at t = 0 precedes the first step
  }
}

TEST_CASE("EISPH time step: cfl l0 / (max |u| + |g| dt) within its bounds and the viscous and force limits",
          "[eisph][unit]") {
  const double l0 = 0.025, h = 1.2 * l0, g = 9.81;
  {  // The dam break's first 200 steps: each step is what the rule gives from the state before it.
    const Scene scene = load("dambreak.json", {"time.end_time=10"});
    Simulation simulation(scene, *registries().methods.find("eisph"));
    int bounded_below_max = 0;
    for (int k = 0; k < 200; ++k) {
      double speed = 0.0;
      const ParticleSet& particles = simulation.particles();
      for (std::size_t i = 0; i < particles.size(); ++i) {
        if (particles.type[i] == ParticleType::Fluid) speed = std::max(speed, particles.velocity[i].norm());
      }
      const double gained = k > 0 ? g * simulation.last_time_step() : 0.0;
      const double cfl = speed + gained > 0.0 ? 0.2 * l0 / (speed + gained) : 2e-3;
      const double expected = std::clamp(cfl, 1e-6, 2e-3);
      simulation.advance();
      INFO("step " << k << ": v_max " << speed);
      // The same arithmetic in another order: a few ulps.
      CHECK(simulation.last_time_step() == Approx(expected).epsilon(1e-12));
      if (expected < 2e-3) ++bounded_below_max;
    }
    CHECK(bounded_below_max > 50);  // the rule, not the bound, sets most steps once the column falls
  }
  {  // Viscous limit (Morris et al. 1997): nu = 0.1 m^2/s gives 0.125 h^2 / nu = 1.125e-3 s < 2e-3 s.
    const Scene scene = load("dambreak.json", {"physics.kinematic_viscosity=0.1"});
    Simulation simulation(scene, *registries().methods.find("eisph"));
    simulation.advance();  // at rest: the largest step the limits allow
    CHECK(simulation.last_time_step() == Approx(0.125 * h * h / 0.1).epsilon(1e-12));
  }
  {  // Body-force limit (Monaghan 1992): 0.01 sqrt(h / |g|) = 5.53e-4 s.
    const Scene scene = load("dambreak.json", {"methods.eisph.force_number=0.01"});
    Simulation simulation(scene, *registries().methods.find("eisph"));
    simulation.advance();
    CHECK(simulation.last_time_step() == Approx(0.01 * std::sqrt(h / g)).epsilon(1e-12));
  }
  {  // "fixed": the scene's step whatever the flow.
    const Scene scene = load("dambreak.json", {"methods.eisph.time_step_rule=\"fixed\""});
    Simulation simulation(scene, *registries().methods.find("eisph"));
    for (int k = 0; k < 20; ++k) simulation.advance();
    CHECK(simulation.last_time_step() == scene.time.time_step);
  }
}

#endif  // MPS_LAB_WITH_EISPH
