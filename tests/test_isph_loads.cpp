// The fluid's reaction on wall particles in ISPH (methods/isph/isph_operators.hpp; docs/walls.md
// "Loads on obstacles"): the wall side of the pressure and viscous pair terms is exactly minus
// what the operators that move the fluid give it from the wall particles.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "core/io/geometry.hpp"
#include "methods/isph/isph_operators.hpp"
#include "still_water_obstacles.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::isph;
using namespace mps_lab::testing;

namespace {

// scenes/hydrostatic.json with a submerged box and a plate at the right wall (as tests/test_obstacle_loads.cpp).
const char* const kObstacles =
    "walls.obstacles=[{\"min\": [0.2, 0.1], \"max\": [0.3, 0.15]}, {\"min\": [0.45, 0.025], \"max\": [0.475, 0.5]}]";

Vec2 total(const std::vector<Vec2>& values) {
  Vec2 sum = Vec2::Zero();
  for (const Vec2& v : values) sum += v;
  return sum;
}

}  // namespace

TEST_CASE("obstacle loads: isph wall pair terms are equal and opposite to what the fluid receives", "[isph][loads]") {
  // Fluid side: pressure_acceleration / add_viscous_acceleration with the wall particles and with
  // them turned into ghosts (which every sum skips); wall side: the reaction passes. ~1e3 pair
  // terms of at most ~1e2 N/m and totals ~1e3 N/m: rounding ~1e-10 N/m; 1e-8 N/m leaves 100x.
  const Scene scene = load("hydrostatic.json", {kObstacles});
  const double l0 = scene.particle_spacing;
  const SphKernel kernel(SphKernelKind::WendlandC2, 2.0 * 1.3 * l0);
  const double mass = 1000.0 / lattice_kernel_sum(kernel, l0);
  ParticleSet p = build_particles(scene, true);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec2& x = p.position[i];
    p.pressure[i] = 9810.0 * (0.2875 - x.y()) + 50.0 * std::cos(30.0 * x.x() + 7.0 * x.y());
    p.velocity[i] = Vec2(std::sin(11.0 * x.y()), std::cos(13.0 * x.x()));
  }
  const NeighbourList neighbours = find_neighbours(p.position, p.type, kernel.support());
  ParticleSet no_walls = p;
  for (auto& type : no_walls.type) type = type == ParticleType::Wall ? ParticleType::Ghost : type;
  std::vector<double> density(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) density[i] = 1000.0 + 3.0 * std::sin(17.0 * p.position[i].x());
  const std::vector<double> interior(p.size(), 0.0);
  std::vector<Vec2> with_walls, without, reaction;
  std::vector<Eigen::Matrix2d> renormalisation;
  // With dry_wall_points "excluded" the wall particles above the water (p <= 0 there: the field is
  // hydrostatic under y = 0.2875 m) drop out of both sides; the totals then differ from the clamped
  // rule's by their push (measured 0.38 N/m, far above the rounding), and still cancel.
  for (const PressureGradientForm form : {PressureGradientForm::Symmetric, PressureGradientForm::Difference}) {
    Vec2 on_fluid_by_rule[2];
    for (const bool exclude_dry : {false, true}) {
      const SamplePressure rule{1000.0, Vec2(0.0, -9.81), true, exclude_dry};
      pressure_acceleration(no_walls, neighbours, kernel, mass, density, interior, form, without);
      pressure_acceleration(p, neighbours, no_wall_samples(), rule, kernel, mass, density, interior, form, with_walls,
                            &renormalisation);
      const Vec2 on_fluid = fluid_total(p, with_walls, mass) - fluid_total(p, without, mass);
      reaction.assign(p.size(), Vec2::Zero());
      add_pressure_wall_reactions(p, neighbours, kernel, mass, density, interior, form, renormalisation, reaction,
                                  rule);
      INFO("form " << static_cast<int>(form) << ", dry excluded " << exclude_dry << ": on the fluid "
                   << on_fluid.transpose() << " N/m, on the walls " << total(reaction).transpose());
      CHECK(on_fluid.norm() > 100.0);
      CHECK((on_fluid + total(reaction)).norm() < 1e-8);
      on_fluid_by_rule[exclude_dry ? 1 : 0] = on_fluid;
    }
    CHECK((on_fluid_by_rule[1] - on_fluid_by_rule[0]).norm() > 0.1);  // the setup has dry wall particles
  }
  const double nu = 1e-3, eta2 = 0.01 * (1.3 * l0) * (1.3 * l0);
  with_walls.assign(p.size(), Vec2::Zero());
  without.assign(p.size(), Vec2::Zero());
  add_viscous_acceleration(p, neighbours, no_wall_samples(), kernel, mass, density, 1000.0, nu, eta2, with_walls);
  add_viscous_acceleration(no_walls, neighbours, no_wall_samples(), kernel, mass, density, 1000.0, nu, eta2, without);
  const Vec2 on_fluid = fluid_total(p, with_walls, mass) - fluid_total(p, without, mass);
  reaction.assign(p.size(), Vec2::Zero());
  add_viscous_wall_reactions(p, neighbours, kernel, mass, density, nu, eta2, reaction);
  INFO("viscous: on the fluid " << on_fluid.transpose() << " N/m, on the walls " << total(reaction).transpose());
  CHECK(on_fluid.norm() > 1e-3);
  CHECK((on_fluid + total(reaction)).norm() < 1e-8);
}

TEST_CASE("wall sample loads: isph sample pair terms are equal and opposite to what the fluid receives",
          "[isph][loads]") {
  // Fluid side: pressure_acceleration / add_viscous_acceleration with the samples of one solid (the
  // box, the plate, the tank) and with none; wall side: the reaction passes with all the samples,
  // whose per-obstacle totals and tank force must each be minus that solid's part. The symmetric and
  // difference forms are sums of pair terms (no renormalisation), so the parts add up exactly.
  // ~1e3 pair terms of at most ~1e2 N/m, totals ~1e3 N/m: rounding ~1e-10 N/m; 1e-8 N/m leaves 100x.
  const double l0 = 0.025;
  const SphKernel kernel(SphKernelKind::WendlandC2, 2.0 * 1.3 * l0);
  const double mass = 1000.0 / lattice_kernel_sum(kernel, l0);
  // Also with dry_wall_points "excluded": the samples above the water (the field is hydrostatic under
  // y = 0.2875 m) drop out of both sides.
  for (const bool exclude_dry : {false, true})
    for (const WallTreatmentInfo* model : sample_models()) {
      const isph::SamplePressure rule{1000.0, Vec2(0.0, -9.81), true, exclude_dry};
      const SampleState state = sample_state(*model, kernel.support());
      const ParticleSet& p = state.particles;
      std::vector<double> density(p.size());
      for (std::size_t i = 0; i < p.size(); ++i) density[i] = 1000.0 + 3.0 * std::sin(17.0 * p.position[i].x());
      const std::vector<double> interior(p.size(), 0.0);
      const std::vector<Eigen::Matrix2d> identity(p.size(), Eigen::Matrix2d::Identity());
      std::vector<Vec2> with, without, scratch;
      for (const isph::PressureGradientForm form :
           {isph::PressureGradientForm::Symmetric, isph::PressureGradientForm::Difference}) {
        WallSampleLoads loads;
        loads.reset(2);
        isph::add_pressure_sample_reactions(p, state.samples, rule, kernel, mass, density, interior, form, identity,
                                            scratch, loads);
        isph::pressure_acceleration(p, state.neighbours, isph::no_wall_samples(), rule, kernel, mass, density, interior,
                                    form, without);
        const Vec2 reactions[3] = {loads.tank_force, loads.force[0], loads.force[1]};
        for (std::int32_t solid = -1; solid <= 1; ++solid) {
          isph::pressure_acceleration(p, state.neighbours, samples_of(state.samples, solid), rule, kernel, mass,
                                      density, interior, form, with);
          const Vec2 on_fluid = fluid_total(p, with, mass) - fluid_total(p, without, mass);
          INFO(model->name << ", dry excluded " << exclude_dry << ", form " << static_cast<int>(form) << ", solid "
                           << solid << ": on the fluid " << on_fluid.transpose() << " N/m, on the solid "
                           << reactions[solid + 1].transpose());
          CHECK(on_fluid.norm() > 10.0);  // the solid pushes the water: a test of something
          CHECK((on_fluid + reactions[solid + 1]).norm() < 1e-8);
        }
      }
      const double nu = 1e-3, eta2 = 0.01 * (1.3 * l0) * (1.3 * l0);
      WallSampleLoads loads;
      loads.reset(2);
      isph::add_viscous_sample_reactions(p, state.samples, kernel, mass, density, 1000.0, nu, eta2, scratch, loads);
      with.assign(p.size(), Vec2::Zero());
      without.assign(p.size(), Vec2::Zero());
      isph::add_viscous_acceleration(p, state.neighbours, state.samples, kernel, mass, density, 1000.0, nu, eta2, with);
      isph::add_viscous_acceleration(p, state.neighbours, isph::no_wall_samples(), kernel, mass, density, 1000.0, nu,
                                     eta2, without);
      const Vec2 on_fluid = fluid_total(p, with, mass) - fluid_total(p, without, mass);
      check_equal_and_opposite(model->name + " viscous", on_fluid, loads, 1e-3);
    }
}
