// The stability monitor on hand-made states (core/run/stability.hpp): each check fires at its
// threshold and not below it, "continue" records without stopping, a non-finite state
// always stops, and escapes are told apart from wall penetrations.
#include <cmath>
#include <limits>

#include <catch2/catch.hpp>

#include "core/bodies/rigid_bodies.hpp"
#include "core/io/geometry.hpp"
#include "core/run/method.hpp"
#include "core/run/stability.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

namespace {

// The spec's dam break: 171 fluid particles, l0 = 0.025 m, dt = 5e-4 s, domain [0,1]x[0,0.6],
// walls bottom, left, right.
Scene dambreak(const std::vector<std::string>& overrides = {}) { return load("dambreak.json", overrides); }

std::size_t first_fluid(const ParticleSet& particles) {
  std::size_t i = 0;
  while (particles.type[i] != ParticleType::Fluid) ++i;
  return i;
}

}  // namespace

TEST_CASE("mechanical energy of the initial column: rho g sum of heights above the bed line", "[monitor]") {
  const Scene scene = dambreak();
  const ParticleSet particles = build_particles(scene);
  // 9 columns x 19 rows at y = j l0 (j = 1..19) above the domain's bottom, m = rho l0^2:
  // E0 = 9 rho l0^2 g l0 (1 + ... + 19) = 9 * 1000 * 0.025^3 * 9.81 * 190.
  const double expected = 9.0 * 1000.0 * std::pow(0.025, 3) * 9.81 * 190.0;
  CHECK(mechanical_energy(particles, scene) == Approx(expected).epsilon(1e-12));
  // E_scale = E0 + 1/2 M (0.01 l0/dt)^2 = E0 + 1/2 (171 * 0.625) (0.5)^2.
  CHECK(stability_energy_scale(expected, 171 * 0.625, 0.025, 5e-4) == Approx(expected + 0.5 * 171 * 0.625 * 0.25));
}

TEST_CASE("Courant check: fires just above the limit - not just below", "[monitor]") {
  const Scene scene = dambreak();
  ParticleSet particles = build_particles(scene);
  StabilityMonitor monitor(scene, scene.stability);
  monitor.start(particles);
  const std::size_t i = first_fluid(particles);
  const double limit_speed = 1.0 * 0.025 / 5e-4;  // courant_limit l0 / dt = 50 m/s
  particles.velocity[i] = Vec2(0.99 * limit_speed, 0.0);
  // (Its kinetic energy, 0.5 * 0.625 * 49.5^2 = 766 J/m, is far beyond the energy limit:
  // check with the energy limit out of the way.)
  Scene loose = dambreak({"stability.energy_growth_limit=1e9"});
  StabilityMonitor courant_only(loose, loose.stability);
  courant_only.start(build_particles(loose));
  CHECK_NOTHROW(courant_only.check_step(particles, StepReport{}, 1, 5e-4, 5e-4));
  CHECK(courant_only.state().last_courant == Approx(0.99));
  particles.velocity[i] = Vec2(1.01 * limit_speed, 0.0);
  CHECK_THROWS_AS(courant_only.check_step(particles, StepReport{}, 2, 1e-3, 5e-4), RunStopped);
  CHECK(courant_only.count("courant") == 1);
}

TEST_CASE("energy check: E0 + 0.5 E_scale is the line", "[monitor]") {
  const Scene scene = dambreak();
  ParticleSet particles = build_particles(scene);
  StabilityMonitor monitor(scene, scene.stability);
  monitor.start(particles);
  const double allowed = 0.5 * monitor.state().energy_scale;  // J/m
  // Give the whole fluid a uniform speed whose kinetic energy is just below / above it.
  const double mass = 171 * 1000.0 * 0.025 * 0.025;
  for (const double factor : {0.98, 1.02}) {
    const double speed = std::sqrt(2.0 * factor * allowed / mass);
    for (std::size_t k = 0; k < particles.size(); ++k) {
      if (particles.type[k] == ParticleType::Fluid) particles.velocity[k] = Vec2(0.0, speed);
    }
    if (factor < 1.0) {
      CHECK_NOTHROW(monitor.check_step(particles, StepReport{}, 1, 5e-4, 5e-4));
    } else {
      CHECK_THROWS_WITH(monitor.check_step(particles, StepReport{}, 2, 1e-3, 5e-4),
                        Catch::StartsWith("diverged at t = 0.001 s (step 2), because the mechanical energy grew"));
    }
  }
}

TEST_CASE("penetration and escape are told apart - continue records without stopping", "[monitor]") {
  const Scene scene = dambreak({"stability.on_divergence=continue"});
  ParticleSet particles = build_particles(scene);
  StabilityMonitor monitor(scene, scene.stability);
  monitor.start(particles);
  const std::size_t i = first_fluid(particles);
  // Inside the left wall (beyond its first particle line at x = 0).
  particles.position[i] = Vec2(-0.01, 0.1);
  monitor.check_step(particles, StepReport{}, 1, 5e-4, 5e-4);
  CHECK(monitor.count("penetration") == 1);
  CHECK(monitor.count("escaped") == 0);
  // Over the open top: a ghost above the domain is an escape, not a penetration.
  particles.position[i] = Vec2(0.5, 0.8);
  particles.type[i] = ParticleType::Ghost;
  monitor.check_step(particles, StepReport{}, 2, 1e-3, 5e-4);
  CHECK(monitor.count("escaped") == 1);
  CHECK(monitor.count("penetration") == 1);  // nothing new beyond a wall
  CHECK(monitor.state().ghosts == 1);
  CHECK(monitor.state().ghosts_through_walls == 0);
  // Through the right wall and out: a ghost beside the wall is a penetration.
  const std::size_t j = i + 1;
  particles.position[j] = Vec2(1.2, 0.1);
  particles.type[j] = ParticleType::Ghost;
  monitor.check_step(particles, StepReport{}, 3, 1.5e-3, 5e-4);
  CHECK(monitor.count("penetration") == 2);
  CHECK(monitor.state().ghosts_through_walls == 1);
  CHECK(monitor.summary()["events"].size() == 3);
}

TEST_CASE("a non-finite state stops the run even with on_divergence = continue", "[monitor]") {
  const Scene scene = dambreak({"stability.on_divergence=continue"});
  ParticleSet particles = build_particles(scene);
  StabilityMonitor monitor(scene, scene.stability);
  monitor.start(particles);
  particles.pressure[first_fluid(particles)] = std::numeric_limits<double>::quiet_NaN();
  try {
    monitor.check_step(particles, StepReport{}, 7, 3.5e-3, 5e-4);
    FAIL("no stop");
  } catch (const RunStopped& stopped) {
    CHECK(stopped.status() == "diverged");
    CHECK_THAT(stopped.what(), Catch::Contains("non-finite"));
  }
  CHECK(monitor.count("non_finite") == 1);
}

TEST_CASE("solver failures: recorded - and a stop only when the scene asks", "[monitor]") {
  StepReport failed;
  failed.solver_converged = false;
  failed.solver_note = "CG residual 1e-3 > cg_tolerance 1e-08 after 5 iterations";
  const Scene going_on = dambreak();
  const ParticleSet particles = build_particles(going_on);
  StabilityMonitor monitor(going_on, going_on.stability);
  monitor.start(particles);
  CHECK_NOTHROW(monitor.check_step(particles, failed, 1, 5e-4, 5e-4));
  CHECK(monitor.count("solver") == 1);
  const Scene stopping = dambreak({"stability.on_solver_failure=stop"});
  StabilityMonitor strict(stopping, stopping.stability);
  strict.start(particles);
  try {
    strict.check_step(particles, failed, 1, 5e-4, 5e-4);
    FAIL("no stop");
  } catch (const RunStopped& stopped) {
    CHECK(stopped.status() == "solver_failed");
    CHECK(std::string(stopped.what()) ==
          "solver failed at t = 0.0005 s (step 1), because the pressure solver did not converge: " +
              failed.solver_note);
  }
}

TEST_CASE("a speed cap on more than 5 % of the fluid is a divergence", "[monitor]") {
  const Scene scene = dambreak();
  const ParticleSet particles = build_particles(scene);
  StabilityMonitor monitor(scene, scene.stability);
  monitor.start(particles);
  StepReport report;
  report.speed_limited_particles = 8;  // 4.7 % of 171
  CHECK_NOTHROW(monitor.check_step(particles, report, 1, 5e-4, 5e-4));
  report.speed_limited_particles = 9;  // 5.3 %
  CHECK_THROWS_WITH(monitor.check_step(particles, report, 2, 1e-3, 5e-4),
                    Catch::Contains("capped the speed of 9 fluid particles"));
  CHECK(monitor.count("speed_limited") == 2);
}

TEST_CASE("bad stability settings are input errors naming the key", "[monitor]") {
  CHECK_THROWS_WITH(dambreak({"stability.on_divergence=halt"}), Catch::Contains("stability.on_divergence"));
  CHECK_THROWS_WITH(dambreak({"stability.courant_limit=0"}), Catch::Contains("stability.courant_limit"));
  CHECK_THROWS_WITH(dambreak({"stability.max_escape=0.1"}), Catch::Contains("stability.max_escape"));
}

TEST_CASE("stability monitor: the rigid bodies' mechanical energy is part of the energy it watches",
          "[stability][bodies]") {
  // scenes/disc_on_slope.json's disc (no fluid) at rest where the scene puts it: its energy is its
  // potential energy above the domain's lowest corner, m g (y_c - y_min) (g = (0, -9.81) m/s^2), and
  // the monitor's E0 is that plus the fluid's (none). A body's energy then enters every check: a
  // body that sinks gives its potential energy to the water (docs/stability.md, "energy_growth").
  const Scene scene = load("disc_on_slope.json");
  const RigidBodies bodies(scene);
  REQUIRE(bodies.size() == 1);
  const double m = bodies.mass(0).mass, y = bodies.state(0).position.y();
  const double expected = m * 9.81 * (y - scene.domain.min.y());
  CHECK(bodies_mechanical_energy(bodies, scene) == Approx(expected).epsilon(1e-12));
  const ParticleSet particles = build_particles(scene, true);
  StabilityMonitor monitor(scene, scene.stability);
  monitor.start(particles, bodies_mechanical_energy(bodies, scene));
  CHECK(monitor.state().initial_energy == Approx(mechanical_energy(particles, scene) + expected).epsilon(1e-12));
}
