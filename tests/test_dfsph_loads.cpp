// The fluid's reaction on boundary particles in DFSPH (methods/dfsph/dfsph_operators.hpp; docs/walls.md
// "Loads on obstacles"): over one step, the momentum the fluid gains is its weight plus minus the
// reactions on every boundary particle (its own pairs, pressure and viscous, are antisymmetric).
#include <catch2/catch.hpp>

#include <algorithm>
#include <string>
#include <vector>

#include "core/run/driver.hpp"
#include "still_water_obstacles.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

TEST_CASE("obstacle loads: dfsph boundary reactions balance the fluid's momentum over a step", "[dfsph][loads]") {
  // scenes/hydrostatic.json with a submerged box, 20 steps from rest: sum_f m (v^{n+1} - v^n) / dt
  // = N m g - sum_b reaction_b, to rounding and to the solvers' s_f adding up to (kappa + kappa^v)
  // / rho_f (the same quotient summed per correction). Totals ~1e3 N/m; 1e-6 of that allowed.
  const Scene scene = load("hydrostatic.json", {"walls.obstacles=[{\"min\": [0.2, 0.1], \"max\": [0.3, 0.15]}]",
                                                "method=dfsph", "run.sort_period=0"});
  Simulation run(scene, *registries().methods.find("dfsph"));
  const double mass = scene.physics.density * scene.particle_spacing * scene.particle_spacing;
  for (int step = 0; step < 20; ++step) {
    const std::vector<Vec2> before = run.particles().velocity;
    run.advance();
    const ParticleSet& p = run.particles();
    const double dt = run.last_time_step();
    Vec2 gained = Vec2::Zero(), weight = Vec2::Zero(), reactions = Vec2::Zero();
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.type[i] == ParticleType::Fluid) {
        gained += mass * (p.velocity[i] - before[i]) / dt;
        weight += mass * scene.physics.gravity;
      }
      reactions += (*run.method().wall_reactions())[i];
    }
    INFO("step " << step << ": gained " << gained.transpose() << " N/m, weight " << weight.transpose() << ", reactions "
                 << reactions.transpose());
    CHECK(reactions.norm() > 100.0);
    CHECK((gained - weight + reactions).norm() < 1e-6 * weight.norm());
  }
}

TEST_CASE("wall sample loads: dfsph's sample reactions balance the fluid's momentum over a step", "[dfsph][loads]") {
  // scenes/hydrostatic.json with a submerged box, 20 steps from rest with each boundary model of wall
  // samples and both wall pressures: sum_f m (v^{n+1} - v^n) / dt = N m g - (the loads on the
  // obstacles + the force on the tank's samples), to rounding and to the solvers' s_f adding up to
  // (kappa + kappa^v) / rho_f (as tests/test_dfsph_loads.cpp for boundary particles). A mirror
  // image moves its source through the constraint: that is part of the sample's force on the fluid.
  // Totals ~1e3 N/m; 1e-6 of the weight allowed.
  const MethodInfo* dfsph = registries().methods.find("dfsph");
  REQUIRE(dfsph != nullptr);
  for (const WallTreatmentInfo* model : sample_models()) {
    for (const char* wall_pressure : {"mirrored", "extrapolated"}) {
      std::vector<std::string> overrides = boundary_model_overrides("hydrostatic.json", "dfsph", model->name);
      overrides.insert(overrides.end(),
                       {"walls.obstacles=[{\"min\": [0.2, 0.1], \"max\": [0.3, 0.15]}]", "run.sort_period=0",
                        std::string("methods.dfsph.wall_pressure=") + wall_pressure});
      const Scene scene = load("hydrostatic.json", overrides);
      Simulation run(scene, *dfsph);
      REQUIRE(run.reports_obstacle_loads());
      const double mass = scene.physics.density * scene.particle_spacing * scene.particle_spacing;
      double largest_box_load = 0.0;  // N/m: the box is pushed (from rest the load swings through 0)
      for (int step = 0; step < 20; ++step) {
        const std::vector<Vec2> before = run.particles().velocity;
        run.advance();
        const ParticleSet& p = run.particles();
        const double dt = run.last_time_step();
        Vec2 gained = Vec2::Zero(), weight = Vec2::Zero();
        for (std::size_t i = 0; i < p.size(); ++i) {
          if (p.type[i] != ParticleType::Fluid) continue;
          gained += mass * (p.velocity[i] - before[i]) / dt;
          weight += mass * scene.physics.gravity;
        }
        const WallSampleLoads* loads = run.method().wall_sample_loads();
        REQUIRE(loads != nullptr);
        const Vec2 walls = loads->tank_force + loads->force[0];
        INFO(model->name << ", " << wall_pressure << ", step " << step << ": gained " << gained.transpose()
                         << " N/m, weight " << weight.transpose() << ", on the walls " << walls.transpose()
                         << ", on the box " << loads->force[0].transpose());
        largest_box_load = std::max(largest_box_load, loads->force[0].norm());
        CHECK((gained - weight + walls).norm() < 1e-6 * weight.norm());
      }
      CHECK(largest_box_load > 50.0);
    }
  }
}
