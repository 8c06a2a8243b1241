// The fluid's reaction on wall particles in WCSPH (methods/wcsph/wcsph_operators.hpp; docs/walls.md
// "Loads on obstacles"): the wall side of the momentum pair terms is exactly minus what momentum()
// gives the fluid from the wall particles.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "core/io/geometry.hpp"
#include "methods/wcsph/wcsph_operators.hpp"
#include "still_water_obstacles.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::wcsph;
using namespace mps_lab::testing;

namespace {

// Either viscosity model with values large enough that its sums lie far above rounding: alpha = 0.02,
// nu = 1e-3 m^2/s, h = 1.5 l0 (m), eta = 0.1 h.
ViscositySettings test_viscosity(Viscosity model, double l0, const TaitEquation& eos) {
  ViscositySettings viscosity;
  viscosity.model = model;
  viscosity.alpha_h_c0 = 0.02 * 1.5 * l0 * eos.sound_speed;
  viscosity.kinematic_viscosity = 1e-3;
  viscosity.eta2 = 0.01 * 1.5 * l0 * 1.5 * l0;
  return viscosity;
}

}  // namespace

TEST_CASE("obstacle loads: wcsph wall pair terms are equal and opposite to what the fluid receives", "[wcsph][loads]") {
  // Fluid side: momentum() with the wall particles and with them turned into ghosts (skipped by
  // every sum), gravity 0; wall side: add_momentum_wall_reactions. ~1e3 pair terms of at most
  // ~1e2 N/m: rounding ~1e-10 N/m; 1e-8 N/m leaves a factor 100. Both viscosity models.
  const Scene scene = load("hydrostatic.json", {"walls.obstacles=[{\"min\": [0.2, 0.1], \"max\": [0.3, 0.15]}]"});
  const double l0 = scene.particle_spacing;
  const SphKernel kernel(SphKernelKind::WendlandC2, 3.0 * l0);
  const double mass = 1000.0 * l0 * l0;
  const ParticleSet p = build_particles(scene, true);
  ParticleSet no_walls = p;
  for (auto& type : no_walls.type) type = type == ParticleType::Wall ? ParticleType::Ghost : type;
  const NeighbourList neighbours = find_neighbours(p.position, p.type, kernel.support());
  std::vector<double> density(p.size()), pressure(p.size());
  std::vector<Vec2> velocity(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec2& x = p.position[i];
    pressure[i] = 9810.0 * (0.2875 - x.y()) + 50.0 * std::cos(30.0 * x.x() + 7.0 * x.y());
    density[i] = 1000.0 + 2.0 * std::sin(17.0 * x.x());
    velocity[i] = Vec2(std::sin(11.0 * x.y()), std::cos(13.0 * x.x()));
  }
  const WallSampleList none;
  const TaitEquation eos;
  for (const Viscosity model : {Viscosity::Artificial, Viscosity::Laminar}) {
    const ViscositySettings viscosity = test_viscosity(model, l0, eos);
    const FluidState with{p, neighbours, none, kernel, mass, density, velocity, pressure, eos, Vec2::Zero(), true};
    const FluidState without{no_walls, neighbours, none, kernel,       mass, density,
                             velocity, pressure,   eos,  Vec2::Zero(), true};
    std::vector<Vec2> a_with, a_without, reaction(p.size(), Vec2::Zero());
    momentum(with, viscosity, a_with);
    momentum(without, viscosity, a_without);
    add_momentum_wall_reactions(with, viscosity, reaction);
    Vec2 on_fluid = Vec2::Zero(), on_walls = Vec2::Zero();
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (p.type[i] == ParticleType::Fluid) on_fluid += mass * (a_with[i] - a_without[i]);
      on_walls += reaction[i];
    }
    INFO("model " << static_cast<int>(model) << ": on the fluid " << on_fluid.transpose() << " N/m, on the walls "
                  << on_walls.transpose());
    CHECK(on_fluid.norm() > 100.0);
    CHECK((on_fluid + on_walls).norm() < 1e-8);
  }
}

TEST_CASE("wall sample loads: wcsph sample pair terms are equal and opposite to what the fluid receives",
          "[wcsph][loads]") {
  // Fluid side: momentum() with each model's wall samples and with none, gravity 0; wall side:
  // add_momentum_sample_reactions, whose obstacles' loads and tank force must add up to minus the
  // difference. Both viscosity models; tolerance as above.
  for (const WallTreatmentInfo* model : sample_models()) {
    const double l0 = 0.025;
    const SphKernel kernel(SphKernelKind::WendlandC2, 3.0 * l0);
    const double mass = 1000.0 * l0 * l0;
    const SampleState state = sample_state(*model, kernel.support());
    const ParticleSet& p = state.particles;
    std::vector<double> density(p.size());
    for (std::size_t i = 0; i < p.size(); ++i) density[i] = 1000.0 + 2.0 * std::sin(17.0 * p.position[i].x());
    const WallSampleList none;
    const TaitEquation eos;
    for (const Viscosity viscous : {Viscosity::Artificial, Viscosity::Laminar}) {
      const ViscositySettings viscosity = test_viscosity(viscous, l0, eos);
      const FluidState with{p,          state.neighbours, state.samples, kernel,       mass, density,
                            p.velocity, p.pressure,       eos,           Vec2::Zero(), true};
      const FluidState without{p,          state.neighbours, none, kernel,       mass, density,
                               p.velocity, p.pressure,       eos,  Vec2::Zero(), true};
      std::vector<Vec2> a_with, a_without, scratch;
      momentum(with, viscosity, a_with);
      momentum(without, viscosity, a_without);
      WallSampleLoads loads;
      loads.reset(2);
      add_momentum_sample_reactions(with, viscosity, scratch, loads);
      const Vec2 on_fluid = fluid_total(p, a_with, mass) - fluid_total(p, a_without, mass);
      CHECK(loads.force[0].norm() > 10.0);  // the box is pushed
      check_equal_and_opposite(model->name + ", viscosity " + std::to_string(static_cast<int>(viscous)), on_fluid,
                               loads, 10.0);
    }
  }
}
