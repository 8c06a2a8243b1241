// core/run/time_step.hpp: the CFL rule, its bounds, the evened-out end, the clock and its checkpoint;
// the rule as mps, isph and eisph apply it.
#include <algorithm>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "core/io/checkpoint.hpp"
#include "core/run/driver.hpp"
#include "core/run/time_step.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

namespace {

TimeStepSettings cfl_settings() {
  TimeStepSettings settings;
  settings.cfl = true;
  settings.fixed_time_step = 5e-4;
  settings.cfl_number = 0.25;
  settings.min_time_step = 1e-5;
  settings.max_time_step = 2e-3;
  return settings;
}

}  // namespace

TEST_CASE("CFL time step: cfl l0 / v_max within its bounds - an evened-out end - fixed: the scene's step",
          "[time_step]") {
  const TimeStepSettings settings = cfl_settings();
  const double l0 = 0.025, end = 1.0;
  TimeStepClock clock;
  CHECK(clock.next(settings, 5.0, l0, end) == 0.25 * 0.025 / 5.0);  // 1.25e-3 s, inside the bounds
  CHECK(clock.next(settings, 0.0, l0, end) == 2e-3);                // at rest: the upper bound
  CHECK(clock.next(settings, 2.0, l0, end) == 2e-3);                // 3.1e-3 s, capped
  CHECK(clock.next(settings, 1000.0, l0, end) == 1e-5);             // 6.25e-6 s, floored
  TimeStepSettings fixed = settings;
  fixed.cfl = false;
  CHECK(clock.next(fixed, 1000.0, l0, end) == 5e-4);

  // The end: 0.9990 s done, 1.0e-3 s left <= dt: one step lands on it; 2.0e-3 s left < 2 dt
  // (dt = 1.25e-3 s): two halves of 1.0e-3 s rather than 1.25e-3 and a sliver of 0.75e-3.
  for (int k = 0; k < 999; ++k) clock.advance(1e-3);
  CHECK(clock.next(settings, 5.0, l0, end) == Approx(1e-3).epsilon(1e-9));
  TimeStepClock early;
  for (int k = 0; k < 998; ++k) early.advance(1e-3);
  CHECK(early.next(settings, 5.0, l0, end) == Approx(1e-3).epsilon(1e-9));
  // The clock sums as the driver does (compensated): 998 steps of 1 ms are 0.998 s to round-off.
  CHECK(early.elapsed() == Approx(0.998).epsilon(1e-15));
  CHECK(early.steps() == 998);
}

TEST_CASE("Time-step clock: summary - and a checkpoint restores it bit for bit", "[time_step][checkpoint]") {
  const TimeStepSettings settings = cfl_settings();
  TimeStepClock clock;
  clock.start(5e-4);
  CHECK(clock.last() == 5e-4);
  CHECK(clock.summary(settings)["mean"] == 0.0);
  for (const double dt : {2e-3, 1.5e-3, 1e-3, 1.7e-3}) clock.advance(dt);
  const auto summary = clock.summary(settings);
  CHECK(summary["rule"] == "cfl");
  CHECK(summary["min"] == 1e-3);
  CHECK(summary["max"] == 2e-3);
  CHECK(summary["mean"].get<double>() == Approx(6.2e-3 / 4).epsilon(1e-14));

  CheckpointWriter writer;
  writer.begin_section("clock");
  clock.save(writer);
  writer.end_section();
  CheckpointReader reader(writer.file_content("rev"), "run/checkpoint.bin", "rev");
  reader.begin_section("clock");
  TimeStepClock restored;
  restored.restore(reader);
  reader.end_section();
  CHECK(restored.summary(settings) == summary);
  CHECK(restored.last() == 1.7e-3);
  CHECK(restored.steps() == 4);
  restored.advance(1e-3);
  clock.advance(1e-3);
  CHECK(restored.elapsed() == clock.elapsed());  // the compensation term came back too
}

TEST_CASE("CFL rule of mps, isph and eisph: each step is cfl l0 / (max |u| + |g| dt_prev) within its bounds",
          "[time_step][contract]") {
  // The spec's dam break (l0 = 0.025 m) under "cfl" with cfl_number 0.1 and bounds [1e-4, 2e-3] s,
  // 120 steps (to about 0.16 s, the surge at 2 m/s). Before each step the test takes
  // v = max_i |u_i| over the fluid and the previous step; the step taken must be
  // clamp(0.1 l0 / (v + |g| dt_prev), 1e-4, 2e-3) to round-off, the first one 2e-3 (at rest), and
  // the steps must shrink below the bound as the flow speeds up (the rule is not ignored).
  const std::vector<std::string> methods = {"mps", "isph", "eisph"};
  for (const std::string& name : methods) {
    INFO("method " << name);
    const MethodInfo* method = registries().methods.find(name);
    REQUIRE(method != nullptr);
    const std::string block = "methods." + name + ".";
    const Scene scene =
        load("dambreak.json", {block + "time_step_rule=\"cfl\"", block + "cfl_number=0.1", block + "min_time_step=1e-4",
                               block + "max_time_step=2e-3", "time.end_time=1"});
    Simulation simulation(scene, *method);
    const double l0 = scene.particle_spacing, g = 9.81;
    double previous = 0.0, smallest = 1.0;
    for (int step = 0; step < 120; ++step) {
      const double speed = largest_fluid_speed(simulation.particles());
      const double estimate = speed + (step > 0 ? g * previous : 0.0);
      const double expected = estimate > 0.0 ? std::clamp(0.1 * l0 / estimate, 1e-4, 2e-3) : 2e-3;
      const double before = simulation.time();
      simulation.advance();
      const double taken = simulation.time() - before;
      INFO("step " << step << ", v = " << speed << " m/s");
      REQUIRE(taken == Approx(expected).epsilon(1e-9));
      previous = taken;
      smallest = std::min(smallest, taken);
    }
    CHECK(smallest < 0.6 * 2e-3);  // measured: 0.99e-3 s for each of the three by step 120 (2.5 m/s)
  }
}
