// The dfsph method through the driver: time-step rules, stopping rules as reported per step,
// parameter checks, determinism across thread counts.
#include <omp.h>
#include <catch2/catch.hpp>

#include <cmath>

#include "core/base/error.hpp"
#include "core/run/driver.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

namespace {

const MethodInfo& dfsph() { return *registries().methods.find("dfsph"); }

// Series columns of the method, in declaration order.
enum Column { kDivergenceIterations = 0, kDivergenceError, kDensityIterations, kDensityError, kCompression };

}  // namespace

TEST_CASE("DFSPH declares its statistics and reports the density solve as the main solve", "[dfsph]") {
  CHECK(dfsph().series_columns == std::vector<std::string>{"divergence_iterations", "divergence_error",
                                                           "density_iterations", "density_error", "compression"});
  // The boundary model only, no measure: Akinci boundaries alone keep the fluid in.
  CHECK(dfsph().default_wall_treatments == std::vector<std::string>{"akinci_boundary"});
  CHECK(dfsph().wall_samples);  // and every boundary model of wall samples (tests/test_dfsph_walls.cpp)
  const Scene scene = load("dambreak.json");
  Simulation simulation(scene, dfsph());
  const StepReport& report = simulation.advance();
  CHECK(report.solver_iterations == static_cast<long long>(report.extra[kDensityIterations]));
  CHECK(report.solver_residual == report.extra[kDensityError]);
}

TEST_CASE("DFSPH CFL time step: 0.4 l0 / max |v + dt a| - bounded - landing on the end time", "[dfsph]") {
  // nu = 0: the non-pressure acceleration is exactly g, so the rule can be recomputed here.
  const Scene scene = load("dambreak.json", {"physics.kinematic_viscosity=0", "time.end_time=0.3"});
  Simulation simulation(scene, dfsph());
  const double l0 = scene.particle_spacing;
  // At rest the bound applies: max_time_step (5e-3 s).
  CHECK(simulation.method().time_step(simulation.particles()) == 5e-3);
  for (int k = 0; k < 40; ++k) simulation.advance();
  const auto& p = simulation.particles();
  double max_speed = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.type[i] == ParticleType::Fluid) {
      max_speed = std::max(max_speed, (p.velocity[i] + simulation.last_time_step() * scene.physics.gravity).norm());
    }
  }
  const double expected = std::clamp(0.4 * l0 / max_speed, 1e-4, 5e-3);
  INFO("max speed " << max_speed << " m/s, time " << simulation.time());
  CHECK(expected < 5e-3);  // the collapse is fast enough for the CFL bound to act
  CHECK(simulation.method().time_step(p) == Approx(expected).epsilon(1e-12));
  simulation.run_to(0.3);
  CHECK(simulation.time() == Approx(0.3).epsilon(1e-12));  // the last steps were evened out to land on 0.3 s
  // The fixed rule returns the scene's time step.
  const Scene fixed = load("dambreak.json", {"methods.dfsph.time_step_rule=\"fixed\""});
  Simulation fixed_simulation(fixed, dfsph());
  fixed_simulation.advance();
  CHECK(fixed_simulation.method().time_step(fixed_simulation.particles()) == 5e-4);
}

TEST_CASE("DFSPH first dam-break step: solvers stop at their tolerances and caps - per the report", "[dfsph][solver]") {
  // The first step builds the pressure of the resting column from nothing: the density solve
  // has real work (tens of iterations), so tolerance and cap both show.
  const auto first_step = [](const std::vector<std::string>& overrides) {
    const Scene scene = load("dambreak.json", overrides);
    Simulation simulation(scene, dfsph());
    return simulation.advance();
  };
  const StepReport standard = first_step({});
  CHECK(standard.extra[kDensityIterations] > 5);
  CHECK(standard.extra[kDensityError] <= 1e-4);  // default density_tolerance
  CHECK(standard.extra[kDivergenceIterations] >= 1);
  CHECK(standard.extra[kDivergenceError] <= 1e-3);  // default divergence_tolerance
  const StepReport loose = first_step({"methods.dfsph.density_tolerance=1e-3"});
  CHECK(loose.extra[kDensityError] <= 1e-3);
  CHECK(loose.extra[kDensityIterations] < standard.extra[kDensityIterations]);
  const StepReport capped =
      first_step({"methods.dfsph.density_tolerance=1e-7", "methods.dfsph.density_max_iterations=3"});
  CHECK(capped.extra[kDensityIterations] == 3);
  CHECK(capped.extra[kDensityError] > 1e-7);
  // A capped solve is counted in run.json's method summary, or stops the run if asked to.
  const Scene counted =
      load("dambreak.json", {"methods.dfsph.density_tolerance=1e-7", "methods.dfsph.density_max_iterations=3"});
  Simulation simulation(counted, dfsph());
  simulation.advance();
  CHECK(simulation.method().summary()["density_solver"]["not_converged"] == 1);
  CHECK(simulation.monitor().count("solver") == 1);
  const Scene strict =
      load("dambreak.json", {"methods.dfsph.density_tolerance=1e-7", "methods.dfsph.density_max_iterations=3",
                             "stability.on_solver_failure=stop"});
  Simulation failing(strict, dfsph());
  CHECK_THROWS_WITH(failing.advance(),
                    Catch::Contains("density solver error") && Catch::Contains("after 3 iterations"));
}

TEST_CASE("DFSPH rejects inconsistent bounds with a message naming the key", "[dfsph]") {
  const Scene scene = load("dambreak.json", {"methods.dfsph.min_time_step=0.01"});
  CHECK_THROWS_AS(Simulation(scene, dfsph()), InputError);
  CHECK_THROWS_WITH(Simulation(scene, dfsph()), Catch::Contains("methods.dfsph.min_time_step"));
  const Scene iterations =
      load("dambreak.json", {"methods.dfsph.density_min_iterations=5", "methods.dfsph.density_max_iterations=4"});
  CHECK_THROWS_WITH(Simulation(iterations, dfsph()), Catch::Contains("methods.dfsph.density_min_iterations"));
}

TEST_CASE("DFSPH: same scene - 1 and 2 threads - bit-identical particles", "[dfsph][determinism]") {
  // l0 = 0.0125 m: 1278 particles, above the size where the method's loops use threads; the
  // first 0.05 s of the collapse are the steps with the most solver iterations.
  const Scene scene = load("dambreak.json", {"particle_spacing=0.0125"});
  const int threads = omp_get_max_threads();
  std::vector<Vec2> result[2];
  for (int run = 0; run < 2; ++run) {
    omp_set_num_threads(run == 0 ? 1 : 2);
    Simulation simulation(scene, dfsph());
    REQUIRE(simulation.particles().size() >= 1024);
    simulation.run_to(0.05);
    result[run] = simulation.particles().position;
  }
  omp_set_num_threads(threads);
  std::size_t different = 0;
  for (std::size_t i = 0; i < result[0].size(); ++i) different += result[0][i] != result[1][i];
  CHECK(different == 0);
}
