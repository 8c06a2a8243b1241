// The fluid's reaction on boundary particles in DFSPH (methods/dfsph/dfsph_operators.hpp; docs/walls.md
// "Loads on obstacles"): over one step, the momentum the fluid gains is its weight plus minus the
// reactions on every boundary particle (its own pairs, pressure and viscous, are antisymmetric).
#include <catch2/catch.hpp>

#include <vector>

#include "core/run/driver.hpp"
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
