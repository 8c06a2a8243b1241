// The spec's dam break to t = 2 s (scenes/dambreak.json unchanged, isph defaults), against
// Martin & Moyce (1952), n^2 = 2, Table 2 (surge front) and Table 6 (residual height); and the
// method's determinism across thread counts.
#include <catch2/catch.hpp>
#include <omp.h>

#include "core/driver.hpp"
#include "dambreak_checks.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

TEST_CASE("ISPH dam break to 2 s: no NaN, nothing lost, nothing through the walls, front on Martin & Moyce",
          "[isph][validation]") {
  // No fluid beyond the wall surfaces (domain boundary +- l0/2) in any frame.
  const DambreakOutcome outcome = run_spec_dambreak("isph", 0.5);
  const RunEvaluation& e = outcome.evaluation;
  const auto& summary = outcome.result.summary;
  CHECK(outcome.result.steps == 4000);
  CHECK(outcome.frames == 41);
  // Splash thrown over the open top at the right wall (above 0.7 m, the ghost margin): measured
  // 8; the mps method loses 4. More than 10 % of the water would be a different flow.
  CHECK(outcome.ghosts <= 17);

  // The solver: every solve reached 1e-8; measured mean 30 BiCGSTAB iterations per step.
  CHECK(summary["method_summary"]["nonconverged_solves"].get<long long>() == 0);
  CHECK(summary["solver"]["mean_iterations"].get<double>() < 60.0);

  INFO("front RMS " << e.front_rms << " max " << e.front_max << "; best shift " << e.front_shift << " -> RMS "
                    << e.front_rms_shifted << "; height RMS " << e.height_rms);
  // Measured: RMS 0.112, max 0.175; best shift +0.093 -> RMS 0.050. Tolerance 0.15: the RMS
  // difference between two independent experiments on this geometry
  // (analysis/validation/README.md), as for mps (0.126).
  CHECK(e.front_rms < 0.15);
  // With the time shift the experiment's uncertain t = 0 allows (|shift| <= 0.3), the shape
  // must match to the experimental noise floor of ~0.1 in Z (measured 0.050).
  CHECK(e.front_rms_shifted < 0.10);
  CHECK(e.front_shift > 0.0);  // ahead of the experiment, like every particle code here
  // Residual height against Table 6: measured RMS 0.020 in H* (mps: 0.043); 0.08 as for mps:
  // the table's values are given to 0.01 and digitisations differ by a few hundredths.
  CHECK(e.height_rms < 0.08);
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
