// The spec's dam break to t = 2 s (scenes/dambreak.json unchanged) with --method dfsph and
// its defaults (CFL time step, Akinci-style boundary particles, no wall treatment), against
// Martin & Moyce (1952), n^2 = 2: Table 2 (surge front) and Table 6 (residual height).
#include <catch2/catch.hpp>

#include <cmath>

#include "core/run/driver.hpp"
#include "dambreak_checks.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

TEST_CASE("DFSPH dam break to 2 s: no NaN - nothing lost - nothing through the walls - front on Martin & Moyce",
          "[dfsph][dambreak][validation]") {
  // In every frame no fluid closer than 0.40 l0 to a wall particle line (the boundary
  // particles' stand-off, see the next test); at t = 2 s none beyond the wall surfaces.
  const DambreakOutcome outcome = run_spec_dambreak("dfsph", 0.40);
  const RunEvaluation& e = outcome.evaluation;
  const auto& summary = outcome.result.summary;
  INFO("steps " << outcome.result.steps);
  CHECK(summary["method_summary"]["density_solver"]["not_converged"] == 0);
  CHECK(summary["method_summary"]["divergence_solver"]["not_converged"] == 0);
  CHECK(outcome.final_wall_distance >= 0.0125 - 1e-12);
  // Measured 8 ghosts: drops thrown above y = 0.7 m by the run-up on the right wall (t ~ 0.5 s)
  // leave through the open top, as in the mps run (4). A loss of more than 5 % of the water
  // would mean the walls leak.
  CHECK(outcome.ghosts < 9);

  INFO("front RMS " << e.front_rms << " max " << e.front_max << "; best shift " << e.front_shift << " -> RMS "
                    << e.front_rms_shifted << "; height RMS " << e.height_rms);
  // Measured RMS 0.116, max 0.229 (the mps method: 0.126). Tolerance 0.15: the RMS difference
  // between two independent experiments on this geometry (analysis/validation/README.md).
  CHECK(e.front_rms < 0.15);
  // Best shift +0.017 -> RMS 0.114. The experimental noise floor is ~0.1 in Z; the series is
  // sampled every 0.005 s (dT ~ 0.05) and the CFL steps (~4 ms) quantise the front's history,
  // so the shape must match within 0.13.
  CHECK(e.front_rms_shifted < 0.13);
  CHECK(e.front_shift >= 0.0);  // the simulation is ahead, never behind
  // Residual height: measured RMS 0.025. Table 6 is given to 0.01 and its digitisations
  // differ by a few hundredths: 0.08, as for mps.
  CHECK(e.height_rms < 0.08);
}

TEST_CASE("DFSPH dam break with the extrapolated wall pressure: the front's shape on Martin & Moyce - ahead in time",
          "[dfsph][dambreak][validation]") {
  // methods.dfsph.wall_pressure = extrapolated (docs/methods/dfsph.md "At the walls"): the same
  // run and checks as above, but the front is not within the 0.15 of the default: measured RMS
  // 0.217 (max 0.294), the front 0.175 in T ahead of the experiment, then RMS 0.068. The
  // mirrored default's first row sinks 0.2 l0 into the bed and holds the surge back (shift
  // +0.017); mps and isph at this spacing run +0.10 / +0.09 ahead, every method +0.17-0.20 at
  // l0 = 0.0125 m (docs/validation.md, gate study). Bounds: the shape as above (0.13), the
  // unshifted RMS below 0.25 (measured 0.217: a front further ahead fails), the height as above.
  const DambreakOutcome outcome =
      run_spec_dambreak("dfsph", 0.40, {"methods.dfsph.wall_pressure=\"extrapolated\""}, "_extrapolated");
  const RunEvaluation& e = outcome.evaluation;
  const auto& summary = outcome.result.summary;
  CHECK(summary["method_summary"]["density_solver"]["not_converged"] == 0);
  CHECK(summary["method_summary"]["divergence_solver"]["not_converged"] == 0);
  CHECK(outcome.ghosts < 9);  // measured 8, as the default
  CHECK(e.front_rms < 0.25);
  CHECK(e.front_rms_shifted < 0.13);
  CHECK(e.front_shift >= 0.0);
  CHECK(e.height_rms < 0.08);  // measured 0.018
}

TEST_CASE("DFSPH dam break with the extrapolated wall pressure and a 2.4 l0 kernel: front on Martin & Moyce",
          "[dfsph][dambreak][validation]") {
  // The setting whose still water reads rho g h within 1 % (docs/methods/dfsph.md, "A wider
  // kernel"), in the spec's dam break with the domain and walls raised to 1.5 m: in the spec's
  // 0.6 m tank its run-up throws 9 particles (5.26 %) over the top at 0.72 s, past the
  // monitor's 5 %, as with the extrapolated pressure's wall samples (the test above). Measured
  // (2026-11-25): front RMS 0.128, best shift +0.082 -> 0.091 (the extrapolated pressure at 2 l0:
  // 0.217, +0.175 -> 0.068): the wider kernel takes back most of the lead. Bounds: the default's
  // (0.15 unshifted, 0.13 shifted, never behind, height 0.08), so the load setting is validated
  // on the front as the default is. Stand-off: the fluid comes to 0.19 l0 of a wall particle
  // line (measured, frame 100 on the bed, the run-up on the right wall), against 0.40 l0 at 2 l0:
  // the cubic spline's gradient vanishes at r -> 0 and peaks at 2/3 of the smoothing length, so a
  // wider kernel repels less at close range; bound 0.15 l0, still never through a wall line.
  const DambreakOutcome outcome = run_spec_dambreak(
      "dfsph", 0.15,
      {"methods.dfsph.wall_pressure=\"extrapolated\"", "methods.dfsph.kernel_support=2.4", "domain.max=[1.0,1.5]"},
      "_extrapolated_wide");
  const RunEvaluation& e = outcome.evaluation;
  const auto& summary = outcome.result.summary;
  INFO("front RMS " << e.front_rms << "; best shift " << e.front_shift << " -> RMS " << e.front_rms_shifted
                    << "; height RMS " << e.height_rms << "; ghosts " << outcome.ghosts);
  CHECK(summary["method_summary"]["density_solver"]["not_converged"] == 0);
  CHECK(summary["method_summary"]["divergence_solver"]["not_converged"] == 0);
  CHECK(outcome.ghosts < 9);
  CHECK(e.front_rms < 0.15);
  CHECK(e.front_rms_shifted < 0.13);
  CHECK(e.front_shift >= 0.0);
  CHECK(e.height_rms < 0.08);
}

TEST_CASE("DFSPH load setting: the spec dam break to 2 s with every boundary model", "[dfsph][validation]") {
  // The load setting (MethodInfo::load_setting: the extrapolated wall pressure, 2.4 l0, the
  // density solve to 0.001 % and particle shifting with the fixed part 0.01) in the spec's
  // 0.6 m tank with each boundary model, the bounds of the eisph and mps load-setting tests
  // (docs/validation.md: 0.10 with the best time shift is the experiment's noise floor, 0.08 in
  // H* for the height, at most 10 % of the water thrown out). Measured 2026-12-07: completes
  // with every model, front RMS 0.103 / 0.104 / 0.107 / 0.209 (shifted 0.052 / 0.051 / 0.047 /
  // 0.039) for akinci_boundary / dummy_layers / distance_function / mirror_particles, 4-6 ghosts.
  // Without the quiet pool (the setting before 2026-12-07) the run-up threw 9 particles over the
  // top and the monitor stopped akinci_boundary at 0.72 s and distance_function at 0.67 s.
  check_load_setting_dambreak("dfsph");
}

TEST_CASE("DFSPH dam break: the boundary particles alone keep every fluid particle off the wall lines",
          "[dfsph][dambreak][validation]") {
  // The whole run, every step (the frames above only show t = 2 s). A particle with no fluid
  // neighbours reaches rho0 against a flat three-layer wall at 0.44 l0 from the wall particle
  // line (lattice boundary volumes, derived in docs/methods/dfsph.md); the density solver's
  // linear prediction lets a fast particle at the front tip overshoot that a little.
  // Measured minimum 0.41 l0 (the tip sliding along the bed at ~3 m/s); bound 0.40 l0, i.e.
  // at most 0.1 l0 = 2.5 mm past the wall surface.
  const Scene scene = load("dambreak.json");
  Simulation simulation(scene, *registries().methods.find("dfsph"));
  const double l0 = scene.particle_spacing;
  double closest = 1e9;
  while (simulation.time() < 2.0 - 1e-9) {
    simulation.advance();
    const auto& p = simulation.particles();
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.type[i] != ParticleType::Fluid) continue;
      closest = std::min({closest, p.position[i].x() - scene.domain.min.x(), scene.domain.max.x() - p.position[i].x(),
                          p.position[i].y() - scene.domain.min.y()});
    }
  }
  INFO("closest approach " << closest / l0 << " l0");
  CHECK(closest > 0.40 * l0);
}

TEST_CASE("DFSPH extrapolated wall pressure: dummy layers and distance function reach 1 s in a tank above the run-up",
          "[dfsph][dambreak][validation]") {
  // Why the spec's dam break stops at 0.64-0.66 s with wall_pressure = extrapolated and these two
  // boundary models (docs/methods/dfsph.md "At the walls", measured 2026-11-24): the particles
  // counted as escaped leave through the domain's open top at y = 0.6 m = 1.2 H, *inside* the
  // tank (x = 0.65-0.99 m), carried up by the run-up on the right wall at 2-5 m/s with p = 0 (a
  // free jet: no negative wall pressure is involved, the extrapolated p_b is >= 0 by construction).
  // The run-up of this dam break is physically far above 1.2 H (front speed ~2 sqrt(g H) =
  // 4.4 m/s, v^2 / 2g ~ 1 m); 9 particles = 5.26 % pass the ceiling, just past the monitor's
  // 5 % (8.55), where the mirrored default passes 7. With the domain (and the walls) raised to
  // 1.5 m = 3 H the same runs complete: at most 12 (dummy layers) / 14 (distance function)
  // particles are above 0.6 m at once (mirrored: 11 / 7) and 1 spray drop each leaves above
  // 1.5 m (mirrored 1 / 0). Bound: at most 2 particles (1.2 % of 171) lost by 1 s: the measured
  // 1 plus one drop of margin; a scheme that pushed the water through the walls or blew up
  // would lose far more.
  for (const std::string model : {"dummy_layers", "distance_function"}) {
    INFO("boundary model " << model);
    const auto out = fresh_directory("dfsph_dambreak_tall_" + model);
    RunOptions options;
    options.scene_path = scene_path("dambreak.json");
    options.method = "dfsph";
    options.overrides = {"methods.dfsph.wall_pressure=\"extrapolated\"",
                         "methods.dfsph.wall_treatments={\"" + model + "\":{}}", "domain.max=[1.0,1.5]",
                         "output.frame_every_steps=100000"};
    options.output_directory = out.string();
    options.end_time = 1.0;
    const RunResult result = run_simulation(options, registries().methods, registries().walls);
    INFO(result.message);
    REQUIRE(result.status == "completed");
    CHECK(result.simulated_time == Approx(1.0).epsilon(1e-12));
    const auto ghosts = result.summary["particles"]["ghost_final"].get<std::size_t>();
    INFO("ghosts " << ghosts);
    CHECK(ghosts <= 2);
    CHECK(result.summary["method_summary"]["density_solver"]["not_converged"] == 0);
  }
}
