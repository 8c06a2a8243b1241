// The spec's dam break to t = 2 s (scenes/dambreak.json, spec parameters), against
// Martin & Moyce (1952), n^2 = 2, Table 2 (surge front) and Table 6 (residual height).
#include <catch2/catch.hpp>

#include "core/driver.hpp"
#include "core/validation.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

TEST_CASE("MPS dam break to 2 s: no NaN, nothing lost, nothing through the walls, front on Martin & Moyce",
          "[mps][dambreak][validation]") {
  const auto out = fresh_directory("mps_dambreak");
  RunOptions options;
  options.scene_path = scene_path("dambreak.json");
  options.method = "mps";
  options.output_directory = out.string();
  const RunResult result = run_simulation(options, registries().methods, registries().walls);
  REQUIRE(result.status == "completed");
  CHECK(result.steps == 4000);
  CHECK(result.simulated_time == Approx(2.0).epsilon(1e-12));

  // Particles: every one of the 444 is fluid, wall or a counted ghost; no fluid outside.
  const Table last = read_table(out / "output_004000.csv");
  const auto type = last.column("type");
  const auto x = last.column("x"), y = last.column("y");
  const auto ghosts = result.summary["particles"]["ghost_final"].get<std::size_t>();
  CHECK(type.size() + ghosts == 444);
  std::size_t fluid = 0;
  for (std::size_t k = 0; k < type.size(); ++k) {
    if (type[k] != 0) continue;
    ++fluid;
    CHECK(std::isfinite(x[k]));
    CHECK(x[k] >= 0.0125 - 1e-12);  // wall surfaces (spec §6.3)
    CHECK(x[k] <= 0.9875 + 1e-12);
    CHECK(y[k] >= 0.0125 - 1e-12);
  }
  CHECK(fluid + ghosts == 171);
  for (const auto& name : {"vx", "vy", "pressure"}) {
    for (double value : last.column(name)) CHECK(std::isfinite(value));
  }

  // Front against Martin & Moyce: Z = front / a against T = t sqrt(g H) / a, with the column
  // as the particles represent it (a = 0.225 m, H = 0.475 m).
  const Table series = read_table(out / "series.csv");
  const double a = result.summary["column"]["width"], h = result.summary["column"]["height"];
  CHECK(a == Approx(0.225).epsilon(1e-12));
  CHECK(h == Approx(0.475).epsilon(1e-12));
  const Curve front = front_curve(series.column("time"), series.column("front"), a, h, 9.81);
  const Curve experiment = read_curve_csv(validation_data_path("martin_moyce_1952_n2_front.csv"),
                                          "T_n_t_sqrt_g_over_a", "Z_x_over_a");
  const CurveError error = curve_error(front, experiment);
  const CurveError shifted = best_shift_error(front, experiment, 0.3);
  INFO("front RMS " << error.rms << " max " << error.max << "; best shift " << shifted.shift << " -> RMS "
                    << shifted.rms);
  REQUIRE(error.points == experiment.x.size());
  // Measured: RMS 0.126, max 0.243 (the spec's MPS runs ahead of the experiment, as most
  // particle codes do: the experiment's gate opens in finite time). Tolerance 0.15: the
  // RMS difference between two independent experiments on this geometry
  // (analysis/validation/README.md); beyond it the method disagrees with experiment by
  // more than experiments disagree with each other.
  CHECK(error.rms < 0.15);
  // With the time shift that the experiment's t = 0 uncertainty allows (|shift| <= 0.3;
  // measured shift 0.10, RMS 0.071), the shape must match to the experimental noise floor
  // of ~0.1 in Z.
  CHECK(shifted.rms < 0.10);
  CHECK(shifted.shift > 0.0);  // the simulation is ahead, never behind

  // Residual height against Table 6 (tau = t sqrt(g/a), H* = h / H).
  const Curve height = height_curve(series.column("time"), series.column("height"), a, h, 9.81);
  const Curve table6 = read_curve_csv(validation_data_path("martin_moyce_1952_n2_height.csv"),
                                      "tau_t_sqrt_g_over_a", "H_h_over_n2a");
  const CurveError height_error = curve_error(height, table6);
  INFO("height RMS " << height_error.rms);
  // Measured RMS 0.043 in H*; the table's values are given to 0.01 and digitisations of
  // such tables differ by a few hundredths, so 0.08 flags a real change.
  CHECK(height_error.points == table6.x.size());
  CHECK(height_error.rms < 0.08);
}
