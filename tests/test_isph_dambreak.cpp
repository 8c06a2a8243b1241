// The spec's dam break to t = 2 s (scenes/dambreak.json unchanged, isph defaults), against
// Martin & Moyce (1952), n^2 = 2, Table 2 (surge front) and Table 6 (residual height); and the
// method's determinism across thread counts.
#include <omp.h>
#include <catch2/catch.hpp>

#include <algorithm>

#include "core/base/error.hpp"
#include "core/run/driver.hpp"
#include "dambreak_checks.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

TEST_CASE("ISPH dam break to 2 s: no NaN - nothing lost - nothing through the walls - front on Martin & Moyce",
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

TEST_CASE("ISPH: same scene - 1 and 2 threads - bit-identical particles", "[isph][determinism]") {
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

TEST_CASE(
    "ISPH CFL step: cfl l0 / (max |u| + |g| dt) - bounded - and the dam break on Martin & Moyce in a quarter of the "
    "steps",
    "[isph][validation]") {
  const std::vector<std::string> cfl = {"methods.isph.time_step_rule=\"cfl\""};
  {
    // cfl_number 0.1: with the default 0.25 the bound (2e-3 s) holds up to 3.1 m/s, faster than
    // the surge at 0.2 s (2.7 m/s).
    std::vector<std::string> rule = cfl;
    rule.push_back("methods.isph.cfl_number=0.1");
    const Scene scene = load("dambreak.json", rule);
    Simulation simulation(scene, *registries().methods.find("isph"));
    // At rest the bound applies: max_time_step (default 2e-3 s).
    CHECK(simulation.method().time_step(simulation.particles()) == 2e-3);
    simulation.run_to(0.2);
    const auto& p = simulation.particles();
    double max_speed = 0.0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.type[i] == ParticleType::Fluid) max_speed = std::max(max_speed, p.velocity[i].norm());
    }
    max_speed += 9.81 * simulation.last_time_step();  // what gravity can add in one step
    const double expected = std::clamp(0.1 * scene.particle_spacing / max_speed, 1e-6, 2e-3);
    INFO("max speed " << max_speed << " m/s");
    CHECK(expected < 2e-3);  // the surge is fast enough for the CFL bound to act
    CHECK(simulation.method().time_step(p) == Approx(expected).epsilon(1e-12));
  }
  // The whole dam break with the rule: the same checks and tolerances as with the fixed step
  // (experimental scatter, see above). Measured: 1043 steps (fixed: 4000), front RMS 0.121
  // (fixed 0.112), best shift +0.091 -> 0.050, height RMS 0.022.
  const DambreakOutcome outcome = run_spec_dambreak("isph", 0.5, cfl, "_cfl");
  const RunEvaluation& e = outcome.evaluation;
  const auto& time_step = outcome.result.summary["method_summary"]["time_step"];
  CHECK(time_step["rule"] == "cfl");
  CHECK(time_step["max"].get<double>() <= 2e-3);
  CHECK(time_step["min"].get<double>() < 2e-3);
  // Fewer than a third of the fixed run's 4000 steps (measured 1043): what the rule is for.
  CHECK(outcome.result.steps < 4000 / 3);
  CHECK(outcome.ghosts <= 17);
  CHECK(e.front_rms < 0.15);
  CHECK(e.front_rms_shifted < 0.10);
  CHECK(e.height_rms < 0.08);
}

TEST_CASE("ISPH rejects inconsistent time-step bounds with a message naming the key", "[isph][time_step]") {
  const Scene scene = load("dambreak.json", {"methods.isph.min_time_step=0.01"});
  CHECK_THROWS_AS(Simulation(scene, *registries().methods.find("isph")), InputError);
  CHECK_THROWS_WITH(Simulation(scene, *registries().methods.find("isph")),
                    Catch::Contains("methods.isph.min_time_step"));
}
