// The spec's dam break to t = 2 s (scenes/dambreak.json unchanged) with --method dfsph and
// its defaults (CFL time step, Akinci-style boundary particles, no wall treatment), against
// Martin & Moyce (1952), n^2 = 2: Table 2 (surge front) and Table 6 (residual height).
#include <catch2/catch.hpp>

#include <cmath>

#include "core/driver.hpp"
#include "core/validation.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

TEST_CASE("DFSPH dam break to 2 s: no NaN, nothing lost, nothing through the walls, front on Martin & Moyce",
          "[dfsph][dambreak][validation]") {
  const auto out = fresh_directory("dfsph_dambreak");
  RunOptions options;
  options.scene_path = scene_path("dambreak.json");
  options.method = "dfsph";
  options.output_directory = out.string();
  const RunResult result = run_simulation(options, registries().methods, registries().walls);
  REQUIRE(result.status == "completed");
  CHECK(result.simulated_time == Approx(2.0).epsilon(1e-12));  // the CFL steps land on the end time
  INFO("steps " << result.steps);
  CHECK(result.summary["method_summary"]["density_solver"]["not_converged"] == 0);
  CHECK(result.summary["method_summary"]["divergence_solver"]["not_converged"] == 0);

  // Particles: every one of the 444 is fluid, wall or a counted ghost; the last frame is
  // finite and no fluid lies beyond a wall surface (l0/2 inside the domain boundary).
  const auto last_frame = out / ("output_" + [&] {
    char name[16];
    std::snprintf(name, sizeof name, "%06lld", static_cast<long long>(result.steps));
    return std::string(name);
  }() + ".csv");
  const Table last = read_table(last_frame);
  const auto type = last.column("type");
  const auto x = last.column("x"), y = last.column("y");
  const auto ghosts = result.summary["particles"]["ghost_final"].get<std::size_t>();
  CHECK(type.size() + ghosts == 444);
  std::size_t fluid = 0;
  for (std::size_t k = 0; k < type.size(); ++k) {
    if (type[k] != 0) continue;
    ++fluid;
    CHECK(std::isfinite(x[k]));
    CHECK(x[k] >= 0.0125 - 1e-12);
    CHECK(x[k] <= 0.9875 + 1e-12);
    CHECK(y[k] >= 0.0125 - 1e-12);
  }
  CHECK(fluid + ghosts == 171);
  // Measured 8 ghosts: drops thrown above y = 0.7 m by the run-up on the right wall (t ~ 0.5 s)
  // leave through the open top, as in the mps run (4). A loss of more than 5 % of the water
  // would mean the walls leak.
  CHECK(ghosts < 9);
  for (const auto& name : {"vx", "vy", "pressure"}) {
    for (double value : last.column(name)) CHECK(std::isfinite(value));
  }

  // Front against Martin & Moyce, with the column as the particles represent it.
  const Table series = read_table(out / "series.csv");
  const double a = result.summary["column"]["width"], h = result.summary["column"]["height"];
  const Curve front = front_curve(series.column("time"), series.column("front"), a, h, 9.81);
  const Curve experiment = read_curve_csv(validation_data_path("martin_moyce_1952_n2_front.csv"),
                                          "T_n_t_sqrt_g_over_a", "Z_x_over_a");
  const CurveError error = curve_error(front, experiment);
  const CurveError shifted = best_shift_error(front, experiment, 0.3);
  INFO("front RMS " << error.rms << " max " << error.max << "; best shift " << shifted.shift << " -> RMS "
                    << shifted.rms);
  REQUIRE(error.points == experiment.x.size());
  // Measured RMS 0.123, max 0.215 (the mps method: 0.126). Tolerance 0.15: the RMS difference
  // between two independent experiments on this geometry (analysis/validation/README.md).
  CHECK(error.rms < 0.15);
  // Best shift +0.036 -> RMS 0.115. The experimental noise floor is ~0.1 in Z; the CFL rule
  // writes a series row every 10 steps of ~4 ms, i.e. every dT ~ 0.38, and the linear
  // interpolation between rows adds ~0.01 (0.115 with a row every step vs 0.123 here), so
  // the shape must match within 0.13.
  CHECK(shifted.rms < 0.13);
  CHECK(shifted.shift >= 0.0);  // the simulation is ahead, never behind

  // Residual height against Table 6.
  const Curve height = height_curve(series.column("time"), series.column("height"), a, h, 9.81);
  const Curve table6 = read_curve_csv(validation_data_path("martin_moyce_1952_n2_height.csv"),
                                      "tau_t_sqrt_g_over_a", "H_h_over_n2a");
  const CurveError height_error = curve_error(height, table6);
  INFO("height RMS " << height_error.rms);
  // Table 6 is given to 0.01 and its digitisations differ by a few hundredths: 0.08, as for mps.
  CHECK(height_error.points == table6.x.size());
  CHECK(height_error.rms < 0.08);
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
