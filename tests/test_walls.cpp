// Walls as a plugin axis (docs/walls.md): the wall geometry of a scene, obstacles, the choice
// of one boundary model, the wall samples every boundary model of samples produces, a
// boundary model registered from this file only, and the MPS method with each boundary model
// on still water and on the dam break. The ISPH and DFSPH counterparts are in
// tests/test_isph_walls.cpp and tests/test_dfsph_walls.cpp.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <vector>

#include "core/io/geometry.hpp"
#include "core/run/driver.hpp"
#include "core/walls/wall_geometry.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

namespace {

const std::vector<std::string> kSampleModels = {"dummy_layers", "mirror_particles", "distance_function"};

std::string with_boundary(const std::string& method, const std::string& model, const std::string& extra = "") {
  return "methods." + method + ".wall_treatments={\"" + model + "\":{}" + extra + "}";
}

// The three measures of spec §6 that act at walls, switched off (the fourth, particle
// collision, acts between all particle pairs; docs/walls.md explains why it stays).
const std::string kWallMeasuresOff =
    ",\"cfl_velocity_clamp\":{\"enabled\":false},\"wall_repulsion\":{\"enabled\":false},"
    "\"wall_position_clamp\":{\"enabled\":false}";

}  // namespace

TEST_CASE("wall geometry: the surfaces lie half a spacing from the first wall layer", "[walls]") {
  const Scene scene = load("dambreak.json");
  const WallGeometry geometry(scene);
  REQUIRE(geometry.segments().size() == 3);  // bottom, left, right; the top is open
  CHECK(geometry.surface_offset() == Approx(0.0125));
  CHECK(geometry.distance(Vec2(0.025, 0.3)) == Approx(0.0125));    // first fluid column
  CHECK(geometry.depth_inside(Vec2(0.0, 0.3)) == Approx(0.0125));  // first wall layer
  CHECK(geometry.depth_inside(Vec2(0.5, 0.5)) == 0.0);
  CHECK_FALSE(geometry.inside_solid(Vec2(0.5, 0.7)));  // above the open top
  CHECK(geometry.inside_solid(Vec2(-0.01, 0.3)));

  const Scene obstacle = load("dambreak_obstacle.json");
  const WallGeometry with_box(obstacle);
  // Three tank sides and the box's top, left and right faces (its bottom is inside the bed).
  CHECK(with_box.segments().size() == 6);
  CHECK(with_box.depth_inside(Vec2(0.5125, 0.05)) == Approx(0.025));
  CHECK(with_box.distance(Vec2(0.5125, 0.1)) == Approx(0.0125));  // above the box's surface at 0.0875
}

TEST_CASE("obstacles: wall layers inside the box - no fluid in it - lattice corners required", "[walls]") {
  const Scene scene = load("dambreak_obstacle.json");
  const ParticleSet particles = build_particles(scene);
  CHECK(particles.count(ParticleType::Fluid) == 171);
  CHECK(particles.count(ParticleType::Wall) == 273 + 6);  // 2 x 4 box points, 2 of them already bed
  CHECK(build_particles(scene, false).count(ParticleType::Wall) == 0);
  // A water block over the box keeps its fluid outside the box only.
  const Scene flooded = load("dambreak_obstacle.json", {"fluid_blocks=[{\"min\":[0.0,0.0],\"max\":[0.6,0.2]}]"});
  const ParticleSet p = build_particles(flooded);
  std::size_t in_box = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec2& x = p.position[i];
    if (p.type[i] == ParticleType::Fluid && x.x() > 0.49 && x.x() < 0.535 && x.y() < 0.085) ++in_box;
  }
  CHECK(in_box == 0);
  CHECK_THROWS_WITH(load("dambreak_obstacle.json", {"walls.obstacles=[{\"min\":[0.51,0.0],\"max\":[0.525,0.075]}]"}),
                    Catch::Contains("walls.obstacles[0].min: got [0.51,0.0], expected a lattice point"));
  CHECK_THROWS_WITH(load("dambreak_obstacle.json", {"walls.obstacles=[{\"min\":[0.5,0.0],\"max\":[1.5,0.075]}]"}),
                    Catch::Contains("walls.obstacles[0].max: got [1.5,0.075], expected a point inside the domain"));
  CHECK_THROWS_WITH(load("dambreak_obstacle.json", {"walls.obstacles=[{\"min\":[0.5,0.0]}]"}),
                    Catch::Contains("walls.obstacles[0].max"));
}

TEST_CASE("a run has exactly one boundary model - and it must suit the method", "[walls]") {
  // Naming a boundary model replaces the method's default one.
  const Scene mirror = load("dambreak.json", {with_boundary("mps", "mirror_particles")});
  const WallTreatmentChoice* chosen = boundary_choice(mirror.method_config("mps").wall_treatments);
  REQUIRE(chosen != nullptr);
  CHECK(chosen->info->name == "mirror_particles");
  CHECK_THROWS_WITH(
      load("dambreak.json", {"methods.mps.wall_treatments={\"mirror_particles\":{},\"spec_wall_particles\":{}}"}),
      Catch::Contains(
          "methods.mps.wall_treatments: got 2 boundary models (mirror_particles, spec_wall_particles), "
          "expected exactly one of: distance_function, dummy_layers, mirror_particles, spec_wall_particles"));
  CHECK_THROWS_WITH(load("dambreak.json", {"methods.mps.wall_treatments.spec_wall_particles.enabled=false"}),
                    Catch::Contains("got 0 boundary models"));
  CHECK_THROWS_WITH(load("dambreak.json", {with_boundary("mps", "akinci_boundary")}),
                    Catch::Contains("wall treatment 'akinci_boundary' does not support method 'mps'"));
  CHECK_THROWS_WITH(load("dambreak.json", {"methods.mps.wall_treatments.mirror_particles.velocity=\"sticky\""}),
                    Catch::Contains("methods.mps.wall_treatments.mirror_particles.velocity"));
}

TEST_CASE("every boundary model of samples reproduces the lattice number density at rest", "[walls]") {
  // On the initial lattice the dummy points are the wall particles, the mirror images of the
  // first fluid rows fall on the wall layers and the distance function's virtual rows are
  // aligned with the particle: n_i must equal the spec walls' value for every fluid particle
  // (corners included), to rounding. Mirror particles exist only where there is water to
  // mirror: the two particles at the ends of the column's wall rows (the bed under the air
  // beside the column, the back wall above the water) miss 0.485 of n0 = 6.54 there.
  const Scene reference_scene = load("dambreak.json");
  const MethodInfo& mps = *registries().methods.find("mps");
  const Simulation reference(reference_scene, mps);
  std::vector<double> expected;
  for (std::size_t i = 0; i < reference.particles().size(); ++i) {
    if (reference.particles().type[i] == ParticleType::Fluid) {
      expected.push_back(reference.particles().field("number_density")[i]);
    }
  }
  for (const auto& model : kSampleModels) {
    INFO("boundary model " << model);
    const Scene scene = load("dambreak.json", {with_boundary("mps", model)});
    const Simulation simulation(scene, mps);
    const ParticleSet& particles = simulation.particles();
    CHECK(particles.count(ParticleType::Wall) == 0);
    REQUIRE(particles.count(ParticleType::Fluid) == expected.size());
    double worst = 0.0;
    std::size_t short_of_wall = 0;
    for (std::size_t i = 0; i < particles.size(); ++i) {  // fluid comes first, in the same order
      const double difference = particles.field("number_density")[i] - expected[i];
      if (model == "mirror_particles" && std::fabs(difference + 0.4849242405) < 1e-9) {
        ++short_of_wall;
        continue;
      }
      worst = std::max(worst, std::fabs(difference));
    }
    CHECK(worst < 1e-12);
    CHECK(short_of_wall == (model == "mirror_particles" ? 2u : 0u));
  }
}

// --- A boundary model that lives only in this file --------------------------------------------
// The tutorial of docs/walls.md: fixed wall points on the lattice, built from the scene's wall
// geometry (every lattice point behind a wall surface within `layers` spacings), each fluid
// particle seeing those within the support as samples that carry its own pressure.
namespace {

class LatticeWallPoints final : public WallTreatment {
 public:
  explicit LatticeWallPoints(const WallTreatmentSetup& setup) {
    const Scene& scene = setup.scene;
    const WallGeometry geometry(scene);
    const double l0 = scene.particle_spacing;
    const double depth = static_cast<double>(setup.parameters.integer("layers")) * l0;
    const Vec2 low = scene.domain.min - Vec2(depth, depth), high = scene.domain.max + Vec2(depth, depth);
    for (double y = low.y(); y <= high.y() + 1e-9; y += l0) {
      for (double x = low.x(); x <= high.x() + 1e-9; x += l0) {
        const Vec2 point(x, y);
        const double behind = geometry.depth_inside(point);
        if (behind > 0.0 && behind < depth) points_.push_back(point);
      }
    }
  }

  void build_wall_samples(const WallContext& context, WallSampleList& samples) override {
    const ParticleSet& particles = context.particles;
    samples.offsets.assign(particles.size() + 1, 0);
    samples.samples.clear();
    for (std::size_t i = 0; i < particles.size(); ++i) {
      samples.offsets[i] = static_cast<std::uint32_t>(samples.samples.size());
      if (particles.type[i] != ParticleType::Fluid) continue;
      for (const Vec2& point : points_) {
        if ((point - particles.position[i]).norm() >= context.support) continue;
        WallSample sample;  // at rest, volume 1
        sample.position = point;
        sample.source = static_cast<std::uint32_t>(i);
        samples.samples.push_back(sample);
      }
    }
    samples.offsets[particles.size()] = static_cast<std::uint32_t>(samples.samples.size());
  }

 private:
  std::vector<Vec2> points_;  // m
};

WallTreatmentInfo lattice_wall_points_info() {
  WallTreatmentInfo info;
  info.name = "lattice_wall_points";
  info.description = "test-only: lattice points behind the wall surfaces as wall samples";
  info.parameters = {integer_parameter("layers", 3, "depth of the wall in spacings").at_least(1).at_most(10)};
  info.role = WallTreatmentRole::Boundary;  // of wall samples: no wall_particle_model, no hooks
  info.create = [](const WallTreatmentSetup& setup) { return std::make_unique<LatticeWallPoints>(setup); };
  return info;
}

}  // namespace

TEST_CASE("a boundary model registered from tests/ runs a scene with the mps method", "[walls][plugins]") {
  WallTreatmentRegistry walls = builtin_wall_treatments();
  walls.add(lattice_wall_points_info());
  const MethodRegistry& methods = registries().methods;
  const Scene scene = load_scene(scene_path("hydrostatic.json"),
                                 {with_boundary("mps", "lattice_wall_points"), "time.end_time=0.05"}, methods, walls);
  const Scene builtin = load("hydrostatic.json", {with_boundary("mps", "dummy_layers"), "time.end_time=0.05"});
  Simulation mine(scene, *methods.find("mps"));
  Simulation dummy(builtin, *methods.find("mps"));
  mine.run_to(0.05);
  dummy.run_to(0.05);
  // The same wall points as dummy_layers (which takes them from the particle builder), seen in
  // another order: the runs agree to the rounding of the sums and CG's 1e-8 tolerance
  // (measured: 3e-7 Pa after 100 steps; the position clamp of dummy_layers never acted).
  double worst_pressure = 0.0, worst_position = 0.0;
  for (std::size_t i = 0; i < mine.particles().size(); ++i) {
    worst_pressure = std::max(worst_pressure, std::fabs(mine.particles().pressure[i] - dummy.particles().pressure[i]));
    worst_position = std::max(worst_position, (mine.particles().position[i] - dummy.particles().position[i]).norm());
  }
  CHECK(worst_pressure < 1e-3);  // Pa, of ~2700 Pa at the bed
  CHECK(worst_position < 1e-9);  // m
  CHECK(mine.steps() == 100);
  // Built-in registries do not know it.
  CHECK(builtin_wall_treatments().find("lattice_wall_points") == nullptr);
}

TEST_CASE("MPS with each boundary model of samples: still water keeps rho g H at the bed",
          "[mps][walls][hydrostatic]") {
  // Mean over t in [0.5, 1] s (every 50 steps) of the bed-row pressure over rho g (H - y),
  // H the initial water surface (top row + l0/2). Measured (docs/walls.md): spec walls 1.05,
  // dummy_layers 1.13, mirror_particles 0.98, distance_function 0.98-1.06 in 4 realisations (its
  // corner rule `blended`; 0.83-0.95 before its concave corners took the share by the angle,
  // docs/walls.md "Distance function at corners"; `nearest` 0.92-1.16 in 8); still water in MPS is
  // noisy (tests/test_mps_hydrostatic.cpp), hence the band 0.85-1.20 around 1; no particle may
  // pass the wall surface by more than the first particle line (penetration).
  for (const auto& model : kSampleModels) {
    INFO("boundary model " << model);
    const Scene scene = load("hydrostatic.json", {with_boundary("mps", model), "time.end_time=1.0"});
    Simulation simulation(scene, *registries().methods.find("mps"));
    const double l0 = scene.particle_spacing;
    const double surface = fluid_top(simulation.particles()) + 0.5 * l0;
    const double rho_g = scene.physics.density * 9.81;
    double ratio_sum = 0.0;
    long long samples = 0;
    while (simulation.time() < 1.0 - 1e-9) {
      simulation.advance();
      if (simulation.time() < 0.5 || simulation.steps() % 50 != 0) continue;
      const ParticleSet& p = simulation.particles();
      for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.type[i] != ParticleType::Fluid || p.position[i].y() > 1.5 * l0) continue;
        if (p.position[i].x() < 0.1 || p.position[i].x() > 0.4) continue;
        ratio_sum += p.pressure[i] / (rho_g * (surface - p.position[i].y()));
        ++samples;
      }
    }
    REQUIRE(samples > 0);
    const double ratio = ratio_sum / static_cast<double>(samples);
    CHECK(ratio > 0.85);
    CHECK(ratio < 1.20);
    CHECK(simulation.monitor().count("penetration") == 0);
    CHECK(simulation.particles().count(ParticleType::Ghost) == 0);
  }
}

TEST_CASE("MPS dam break to 2 s with each boundary model: no fluid through a wall", "[mps][walls][validation]") {
  // With the spec's measures on (the default), and with the three wall measures off: the
  // boundary model alone keeps the water in (docs/walls.md: measured 0 penetration events for
  // every model; without its kinematic reflection dummy_layers lets 126 through).
  //
  // distance_function without the measures keeps the CFL clamp: without it one particle
  // reaches 149 m/s at t = 1.39 s and the run diverges (a velocity spike of MPS, not a wall
  // leak). That combination sits at the edge of stability: it passed to 2 s before the PPE
  // solver was rewritten, but the old code also diverged with cg_tolerance 1.1e-8 instead of
  // 1e-8 (step 3553), and the new solver, equal to 8e-12 m after 0.3 s, diverges at step 2785.
  // With the clamp it splashes 10 particles over the open top (5.8 % > the monitor's 5 %
  // limit), which is not what this test is about: escapes are allowed up to 20 %.
  const std::string kDistanceFunctionMeasuresOff =
      ",\"wall_repulsion\":{\"enabled\":false},\"wall_position_clamp\":{\"enabled\":false}";
  for (const auto& model : kSampleModels) {
    for (const bool measures : {true, false}) {
      INFO("boundary model " << model << (measures ? " with" : " without") << " the wall measures");
      const bool keep_clamp = !measures && std::string(model) == "distance_function";
      // The distance function's rows with `blended` corners splash 9 particles (5.3 %) over the
      // open top with the measures on (measured 2026-11-28; 3-4 with `nearest`): escapes, not leaks.
      const bool splashes = std::string(model) == "distance_function";
      // The edge-of-stability combination also runs without reordering the particles: reordered
      // by cell every 10 or 50 steps it diverged (t = 1.37 s, 0.80 s; every 25 or 200 steps it
      // completed), as it did with cg_tolerance 1.1e-8; five runs never reordered but changed by
      // one ulp (gravity, density, time step) all completed (measured 2026-11-24). Reordering
      // changes it at rounding level only: 4.4e-14 m against 7.4e-14 m for one ulp of gravity
      // after 380 steps.
      const Scene scene =
          load("dambreak.json", {with_boundary("mps", model,
                                               measures     ? ""
                                               : keep_clamp ? kDistanceFunctionMeasuresOff
                                                            : kWallMeasuresOff),
                                 "stability.max_escaped_fraction=" + std::string(splashes ? "0.2" : "0.05"),
                                 "run.sort_period=" + std::to_string(keep_clamp ? 0 : kDefaultSortPeriod)});
      Simulation simulation(scene, *registries().methods.find("mps"));
      simulation.run_to(2.0);
      CHECK(simulation.monitor().count("penetration") == 0);
      // Splashes may leave over the open top (escaped), never through a wall.
      const WallGeometry geometry(scene);
      for (std::size_t i = 0; i < simulation.particles().size(); ++i) {
        if (simulation.particles().type[i] == ParticleType::Fluid) {
          CHECK(geometry.depth_inside(simulation.particles().position[i]) <= 0.5 * scene.particle_spacing);
        }
      }
    }
  }
}

TEST_CASE("MPS with wall samples: a lone particle whose walls carry its own pressure is a droplet, P = 0",
          "[mps][walls]") {
  // One fluid particle 0.1 l0 from both walls in the bottom-left corner of scenes/hydrostatic.json.
  // Its n* comes from the walls alone and exceeds beta n0, so it is no free-surface particle, but
  // no neighbour carries a pressure: with dummy_layers and distance_function every sample carries
  // its own (a Neumann wall), so its PPE row has no coupling at all. P = 0, exactly. (The row
  // once kept its source with a unit diagonal: P = b_i, here 6.4e7 Pa with dummy_layers and 1.4e8
  // Pa with the distance function; the 104 MPa and 224 MPa sensor peaks of the obstacle dam break
  // with dummy_layers and with corners = lattice, docs/methods/mps.md.)
  for (const std::string model : {"dummy_layers", "distance_function"}) {
    INFO("boundary model " << model);
    const Scene scene = load("hydrostatic.json", {with_boundary("mps", model, kWallMeasuresOff),
                                                  R"(fluid_blocks=[{"min": [0.0, 0.0], "max": [0.05, 0.05]}])"});
    Simulation simulation(scene, *registries().methods.find("mps"));
    REQUIRE(simulation.particles().count(ParticleType::Fluid) == 1);
    const double l0 = scene.particle_spacing;
    simulation.particles().position[0] = Vec2(0.0125 + 0.1 * l0, 0.0125 + 0.1 * l0);
    simulation.advance();
    CHECK(simulation.particles().field("free_surface")[0] == 0.0);  // interior by its n*
    CHECK(simulation.particles().pressure[0] == 0.0);
  }
}
