// The spec's dam break to t = 2 s (scenes/dambreak.json unchanged, isph defaults), against
// Martin & Moyce (1952), n^2 = 2, Table 2 (surge front) and Table 6 (residual height); and the
// method's determinism across thread counts.
#include <catch2/catch.hpp>
#include <omp.h>

#include "core/driver.hpp"
#include "core/validation.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

TEST_CASE("ISPH dam break to 2 s: no NaN, nothing lost, nothing through the walls, front on Martin & Moyce",
          "[isph][validation]") {
  const auto out = fresh_directory("isph_dambreak");
  RunOptions options;
  options.scene_path = scene_path("dambreak.json");
  options.method = "isph";
  options.output_directory = out.string();
  const RunResult result = run_simulation(options, registries().methods, registries().walls);
  REQUIRE(result.status == "completed");
  CHECK(result.steps == 4000);
  CHECK(result.simulated_time == Approx(2.0).epsilon(1e-12));

  // Particles: every one of the 444 is fluid, wall or a counted ghost; no fluid beyond the wall
  // surfaces (domain boundary +- l0/2) in any frame.
  const auto ghosts = result.summary["particles"]["ghost_final"].get<std::size_t>();
  std::size_t frames = 0;
  for (long long step = 0; step <= 4000; step += 100) {
    char name[32];
    std::snprintf(name, sizeof name, "output_%06lld.csv", step);
    const Table frame = read_table(out / name);
    ++frames;
    const auto type = frame.column("type");
    const auto x = frame.column("x"), y = frame.column("y");
    for (std::size_t k = 0; k < type.size(); ++k) {
      if (type[k] != 0) continue;
      CHECK(std::isfinite(x[k]));
      CHECK(x[k] >= 0.0125 - 1e-12);
      CHECK(x[k] <= 0.9875 + 1e-12);
      CHECK(y[k] >= 0.0125 - 1e-12);
    }
  }
  CHECK(frames == 41);
  const Table last = read_table(out / "output_004000.csv");
  const auto type = last.column("type");
  std::size_t fluid = 0;
  for (double t : type) fluid += t == 0 ? 1 : 0;
  CHECK(type.size() + ghosts == 444);
  CHECK(fluid + ghosts == 171);
  // Splash thrown over the open top at the right wall (above 0.7 m, the ghost margin): measured
  // 8; the mps method loses 4. More than 10 % of the water would be a different flow.
  CHECK(ghosts <= 17);
  for (const auto& name : {"vx", "vy", "pressure"}) {
    for (double value : last.column(name)) CHECK(std::isfinite(value));
  }

  // The solver: every solve reached 1e-8; measured mean 30 BiCGSTAB iterations per step.
  CHECK(result.summary["method_summary"]["nonconverged_solves"].get<long long>() == 0);
  CHECK(result.summary["solver"]["mean_iterations"].get<double>() < 60.0);

  // Front against Martin & Moyce: Z = front / a against T = t sqrt(g H) / a, with the column
  // as the particles represent it (a = 0.225 m, H = 0.475 m).
  const Table series = read_table(out / "series.csv");
  const double a = result.summary["column"]["width"], h = result.summary["column"]["height"];
  const Curve front = front_curve(series.column("time"), series.column("front"), a, h, 9.81);
  const Curve experiment =
      read_curve_csv(validation_data_path("martin_moyce_1952_n2_front.csv"), "T_n_t_sqrt_g_over_a", "Z_x_over_a");
  const CurveError error = curve_error(front, experiment);
  const CurveError shifted = best_shift_error(front, experiment, 0.3);
  INFO("front RMS " << error.rms << " max " << error.max << "; best shift " << shifted.shift << " -> RMS "
                    << shifted.rms);
  REQUIRE(error.points == experiment.x.size());
  // Measured: RMS 0.112, max 0.175; best shift +0.093 -> RMS 0.050. Tolerance 0.15: the RMS
  // difference between two independent experiments on this geometry
  // (analysis/validation/README.md), as for mps (0.126).
  CHECK(error.rms < 0.15);
  // With the time shift the experiment's uncertain t = 0 allows (|shift| <= 0.3), the shape
  // must match to the experimental noise floor of ~0.1 in Z (measured 0.050).
  CHECK(shifted.rms < 0.10);
  CHECK(shifted.shift > 0.0);  // ahead of the experiment, like every particle code here

  // Residual height against Table 6 (tau = t sqrt(g/a), H* = h / H).
  const Curve height = height_curve(series.column("time"), series.column("height"), a, h, 9.81);
  const Curve table6 =
      read_curve_csv(validation_data_path("martin_moyce_1952_n2_height.csv"), "tau_t_sqrt_g_over_a", "H_h_over_n2a");
  const CurveError height_error = curve_error(height, table6);
  INFO("height RMS " << height_error.rms);
  // Measured RMS 0.04 in H* (mps: 0.043); 0.08 as for mps: the table's values are given to
  // 0.01 and digitisations differ by a few hundredths.
  CHECK(height_error.points == table6.x.size());
  CHECK(height_error.rms < 0.08);
}

TEST_CASE("ISPH: same scene, 1 and 2 threads, bit-identical particles", "[isph][determinism]") {
  // Every parallel loop writes its own particle, the assembly is serial and Eigen's sparse
  // product splits rows: the thread count must not change a single bit (0.25 s of dam break,
  // through the first surge and its BiCGSTAB solves).
  const Scene scene = load("dambreak.json");
  const int threads = omp_get_max_threads();
  std::vector<Vec2> result[2];
  std::vector<double> pressure[2];
  for (int run = 0; run < 2; ++run) {
    omp_set_num_threads(run == 0 ? 1 : 2);
    Simulation simulation(scene, *registries().methods.find("isph"));
    simulation.run_to(0.25);
    result[run] = simulation.particles().position;
    pressure[run] = simulation.particles().pressure;
  }
  omp_set_num_threads(threads);
  REQUIRE(result[0].size() == result[1].size());
  std::size_t different = 0;
  for (std::size_t i = 0; i < result[0].size(); ++i) {
    different += (result[0][i] != result[1][i]) || (pressure[0][i] != pressure[1][i]) ? 1 : 0;
  }
  CHECK(different == 0);
}
