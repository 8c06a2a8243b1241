#pragma once
// The still-water obstacle case shared by the load tests (test_obstacle_loads, test_mps_loads,
// test_mps_surface_loads): scenes/hydrostatic.json (l0 = 0.025 m, water to y = 0.2875 m) with a
// submerged box and a plate standing on the bed against the right wall.
//   box surface [0.1875, 0.3125] x [0.0875, 0.1625] m: buoyancy rho g A, A = 0.125 x 0.075 m^2;
//   plate surface [0.4375, 0.4875] x [0.0125, 0.5125] m, its right face against the tank's wall
//   (x = 0.5) and its foot on the bed (y = 0): thrust rho g h^2 / 2 with h = 0.275 m.
#include <cmath>
#include <string>
#include <vector>

#include <catch2/catch.hpp>

#include "core/base/types.hpp"
#include "core/io/geometry.hpp"
#include "core/run/driver.hpp"
#include "core/search/neighbour_search.hpp"
#include "core/walls/wall_treatment.hpp"
#include "support.hpp"

namespace mps_lab::testing {

inline constexpr const char* kStillWaterObstacles =
    "walls.obstacles=[{\"min\": [0.2, 0.1], \"max\": [0.3, 0.15]}, {\"min\": [0.45, 0.025], \"max\": [0.475, 0.5]}]";

// The loads on the box (obstacle 0) and the plate (obstacle 1).
struct MeanLoads {
  Vec2 box_force = Vec2::Zero(), plate_force = Vec2::Zero();  // N/m
  double box_torque = 0.0, plate_torque = 0.0;                // N, about each obstacle's area centroid
};

// The loads averaged over every step in [from, to] s of `run`.
inline MeanLoads mean_loads(Simulation& run, double from, double to) {
  MeanLoads mean;
  long long steps = 0;
  run.run_to(from);
  while (run.time() < to) {
    run.advance();
    const ObstacleLoads& loads = run.obstacle_loads();
    mean.box_force += loads.force[0];
    mean.plate_force += loads.force[1];
    mean.box_torque += loads.torque[0];
    mean.plate_torque += loads.torque[1];
    ++steps;
  }
  const double n = static_cast<double>(steps);
  mean.box_force /= n;
  mean.plate_force /= n;
  mean.box_torque /= n;
  mean.plate_torque /= n;
  return mean;
}

// Where still water never comes to rest (MPS's pressure spikes of several rho g h; mirror particles
// and the distance function with several methods) the run is chaotic: a change at the level of
// rounding, here gravity scaled by 1 + k 1e-10, draws another realisation of the same flow, and a
// load averaged over t = 1-2 s has a standard deviation over realisations of up to 0.12 of its
// analytic value (16 realisations, docs/walls.md "Still water"; 0 where the water comes to rest).
// One realisation is what a compiler, FMA contraction or a reordered sum also changes, so a test
// of such a load asserts the mean of `count` realisations (k = 0 .. count - 1) against the mean of
// 16, within 4 standard errors of a `count`-member mean (realisation_tolerance).
struct RealisationStatistics {
  double mean = 0.0;                // of 16 realisations, the quantity's ratio to its analytic value
  double standard_deviation = 0.0;  // of one realisation, over the 16
};

inline double realisation_tolerance(const RealisationStatistics& measured, int count) {
  return 4.0 * measured.standard_deviation / std::sqrt(static_cast<double>(count));
}

// mean_loads over t = 1-2 s of `method` on scenes/hydrostatic.json with kStillWaterObstacles and
// `settings`, averaged over `count` realisations (gravity scaled by 1 + k 1e-10).
inline MeanLoads still_water_realisations(const std::string& method, const std::vector<std::string>& settings,
                                          int count) {
  MeanLoads mean;
  for (int k = 0; k < count; ++k) {
    std::vector<std::string> overrides = {kStillWaterObstacles, "method=" + method};
    overrides.insert(overrides.end(), settings.begin(), settings.end());
    Scene scene = load("hydrostatic.json", overrides);  // the Simulation keeps a reference to it
    scene.physics.gravity *= 1.0 + 1e-10 * k;
    Simulation run(scene, *registries().methods.find(method));
    REQUIRE(run.reports_obstacle_loads());
    const MeanLoads one = mean_loads(run, 1.0, 2.0);
    mean.box_force += one.box_force / count;
    mean.plate_force += one.plate_force / count;
    mean.box_torque += one.box_torque / count;
    mean.plate_torque += one.plate_torque / count;
  }
  return mean;
}

// Wall samples of the same case (tests/test_wall_sample_loads.cpp and the methods' load tests).

// The boundary models of wall samples, from their declarations.
inline std::vector<const WallTreatmentInfo*> sample_models() {
  std::vector<const WallTreatmentInfo*> models;
  for (const WallTreatmentInfo* info : registries().walls.all()) {
    if (info->role == WallTreatmentRole::Boundary && !info->wall_particles) models.push_back(info);
  }
  return models;
}

// The still-water obstacles scene (tests/still_water_obstacles.hpp) with `model` as isph's boundary
// model, its fluid lattice with p = rho g (H - y) plus a wobble, swirling velocities, the neighbours
// within `support` and the samples the model builds there.
struct SampleState {
  Scene scene;
  ParticleSet particles;
  NeighbourList neighbours;
  WallSampleList samples;
};

inline SampleState sample_state(const WallTreatmentInfo& model, double support,
                                const std::vector<std::string>& settings = {}) {
  std::vector<std::string> overrides = boundary_model_overrides("hydrostatic.json", "isph", model.name);
  overrides.push_back(kStillWaterObstacles);
  overrides.insert(overrides.end(), settings.begin(), settings.end());
  SampleState state{load("hydrostatic.json", overrides), {}, {}, {}};
  ParticleSet& p = state.particles = build_particles(state.scene, false);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec2& x = p.position[i];
    p.pressure[i] = 1000.0 * 9.81 * (0.2875 - x.y()) + 50.0 * std::cos(30.0 * x.x() + 7.0 * x.y());
    p.velocity[i] = Vec2(std::sin(11.0 * x.y()), std::cos(13.0 * x.x()));
  }
  state.neighbours = find_neighbours(p.position, p.type, support);
  WallTreatmentSet set(state.scene.method_config("isph").wall_treatments, state.scene);
  WallContext context{p, &state.neighbours, 5e-4, state.scene};
  context.support = support;
  set.build_wall_samples(context, state.samples);
  return state;
}

// The samples of `list` whose obstacle is `obstacle` (-1: the tank's), in the same rows.
inline WallSampleList samples_of(const WallSampleList& list, std::int32_t obstacle) {
  WallSampleList kept;
  kept.offsets.assign(list.offsets.size(), 0);
  for (std::size_t i = 0; i + 1 < list.offsets.size(); ++i) {
    kept.offsets[i] = static_cast<std::uint32_t>(kept.samples.size());
    for (std::uint32_t s = list.begin(i); s < list.end(i); ++s) {
      if (list.samples[s].obstacle == obstacle) kept.samples.push_back(list.samples[s]);
    }
  }
  if (!kept.offsets.empty()) kept.offsets.back() = static_cast<std::uint32_t>(kept.samples.size());
  return kept;
}

// sum_i m a_i over the fluid particles, N/m.
inline Vec2 fluid_total(const ParticleSet& particles, const std::vector<Vec2>& acceleration, double mass) {
  Vec2 sum = Vec2::Zero();
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] == ParticleType::Fluid) sum += mass * acceleration[i];
  }
  return sum;
}

// Equal and opposite: the force the samples gave the fluid (`on_fluid`, N/m, the operator with the
// samples less without) against their reaction on the two obstacles and the tank: their sum within
// 1e-8 N/m (~1e3 pair terms of at most ~1e2 N/m: rounding ~1e-10 N/m), and `on_fluid` above `least`
// (N/m), so that the samples pushed the water: a test of something.
inline void check_equal_and_opposite(const std::string& what, const Vec2& on_fluid, const WallSampleLoads& loads,
                                     double least) {
  const Vec2 on_walls = loads.tank_force + loads.force[0] + loads.force[1];
  INFO(what << ": on the fluid " << on_fluid.transpose() << " N/m, on the walls " << on_walls.transpose());
  CHECK(on_fluid.norm() > least);
  CHECK((on_fluid + on_walls).norm() < 1e-8);
}

}  // namespace mps_lab::testing
