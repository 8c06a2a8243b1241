// Scene loading and the lattice of spec §4.
#include <algorithm>
#include <set>

#include <catch2/catch.hpp>

#include "core/base/error.hpp"
#include "core/io/geometry.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

TEST_CASE("the dam-break scene yields the spec's 171 / 273 / 444 particles at their coordinates", "[scene][geometry]") {
  const Scene scene = load("dambreak.json");
  const ParticleSet particles = build_particles(scene);
  CHECK(particles.count(ParticleType::Fluid) == 171);
  CHECK(particles.count(ParticleType::Wall) == 273);
  CHECK(particles.size() == 444);

  const double l0 = 0.025;
  std::set<std::pair<long, long>> fluid, wall;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const long ix = std::lround(particles.position[i].x() / l0);
    const long iy = std::lround(particles.position[i].y() / l0);
    // Every particle sits exactly on the lattice (to rounding of i * l0).
    CHECK(std::fabs(particles.position[i].x() - static_cast<double>(ix) * l0) < 1e-12);
    CHECK(std::fabs(particles.position[i].y() - static_cast<double>(iy) * l0) < 1e-12);
    (particles.type[i] == ParticleType::Fluid ? fluid : wall).insert({ix, iy});
  }
  // Spec §4 note: fluid at (i l0, j l0), i = 1..9, j = 1..19.
  std::set<std::pair<long, long>> expected_fluid, expected_wall;
  for (long i = 1; i <= 9; ++i)
    for (long j = 1; j <= 19; ++j) expected_fluid.insert({i, j});
  // Bottom rows y = 0, -l0, -2l0 for x = -2l0 .. 1.0 + 2l0; sides x = 0, -l0, -2l0 and
  // 1.0, 1.0 + l0, 1.0 + 2l0 for y = l0 .. 0.575.
  for (long k = 0; k < 3; ++k) {
    for (long i = -2; i <= 42; ++i) expected_wall.insert({i, -k});
    for (long j = 1; j <= 23; ++j) {
      expected_wall.insert({-k, j});
      expected_wall.insert({40 + k, j});
    }
  }
  CHECK(fluid == expected_fluid);
  CHECK(wall == expected_wall);
  CHECK(expected_wall.size() == 273);

  // Wall layers: 1 for the row/column facing the fluid (x = 0, x = 1, y = 0 inside the
  // tank), outer layers 2 and 3; the corner blocks belong to the outer layers.
  std::size_t first_layer = 0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] != ParticleType::Wall) continue;
    const long ix = std::lround(particles.position[i].x() / l0);
    const long iy = std::lround(particles.position[i].y() / l0);
    const long outside = std::max({-ix, ix - 40, -iy, 0L});
    CHECK(particles.wall_layer[i] == 1 + outside);
    if (particles.wall_layer[i] == 1) ++first_layer;
  }
  CHECK(first_layer == 41 + 2 * 23);  // bottom x = 0..1.0 plus the two side columns
}

TEST_CASE("other spacings keep the lattice rule", "[scene][geometry]") {
  const Scene scene = load("dambreak.json", {"particle_spacing=0.0125"});
  const ParticleSet particles = build_particles(scene);
  // Fluid i = 1..19 (19 l0 = 0.2375 < 0.25), j = 1..39: 741; walls 3 * 85 + 2 * 3 * 47 = 537.
  CHECK(particles.count(ParticleType::Fluid) == 19 * 39);
  CHECK(particles.count(ParticleType::Wall) == 3 * 85 + 6 * 47);
  // A spacing that does not divide the tank is refused, naming the key.
  CHECK_THROWS_WITH(build_particles(load("dambreak.json", {"particle_spacing=0.03"})),
                    Catch::Contains("particle_spacing") && Catch::Contains("whole number"));
}

TEST_CASE("still water's pressure per fluid block: rho0 g (top particle + offset - y) by hand", "[scene][geometry]") {
  // Two blocks in the dam-break tank: a column i = 1..7, j = 1..11 (top particle centre 0.275 m)
  // and a pool i = 25..39, j = 1..3 (top 0.075 m); each is hydrostatic below its own top.
  const Scene scene = load("dambreak.json", {"fluid_blocks=[{\"min\":[0.0,0.0],\"max\":[0.2,0.3]},"
                                             "{\"min\":[0.6,0.0],\"max\":[1.0,0.1]}]"});
  const ParticleSet particles = build_particles(scene);
  const double offset = 0.0125;  // m, l0/2: the water surface above the top particle centres
  const std::vector<double> pressure = hydrostatic_block_pressure(scene, particles, offset);
  REQUIRE(pressure.size() == particles.size());
  std::size_t checked = 0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const Vec2& x = particles.position[i];
    if (particles.type[i] != ParticleType::Fluid) {
      CHECK(pressure[i] == 0.0);  // walls start at 0 (each method gives them their own pressure)
      continue;
    }
    const double top = x.x() < 0.5 ? 0.275 : 0.075;  // m
    CHECK(pressure[i] == Approx(1000.0 * 9.81 * (top + offset - x.y())).epsilon(1e-12));
    ++checked;
  }
  CHECK(checked == 7 * 11 + 15 * 3);
  // The bed row of the column, by hand: 1000 * 9.81 * (0.2875 - 0.025) = 2575.125 Pa.
  CHECK(*std::max_element(pressure.begin(), pressure.end()) == Approx(2575.125).epsilon(1e-12));
  // With no offset the top row of each block carries p = 0: the centres are the surface.
  const std::vector<double> at_centres = hydrostatic_block_pressure(scene, particles, 0.0);
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const double y = particles.position[i].y();
    const bool top_row =
        particles.type[i] == ParticleType::Fluid &&
        (std::fabs(y - 0.275) < 1e-9 || (particles.position[i].x() > 0.5 && std::fabs(y - 0.075) < 1e-9));
    if (top_row) CHECK(at_centres[i] == 0.0);
  }
}

TEST_CASE("still water's pressure per fluid block: the head along a tilted gravity - none without gravity",
          "[scene][geometry]") {
  // Gravity (3, -4) m/s^2, |g| = 5: the height is x . (-0.6, 0.8); the spec's column's highest
  // particle in that direction is (0.025, 0.475) (x = i l0, y = j l0, i = 1..9, j = 1..19).
  const Scene tilted = load("dambreak.json", {"physics.gravity=[3.0, -4.0]"});
  const ParticleSet particles = build_particles(tilted);
  const std::vector<double> pressure = hydrostatic_block_pressure(tilted, particles, 0.0);
  const double top = -0.6 * 0.025 + 0.8 * 0.475;  // m
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] != ParticleType::Fluid) continue;
    const Vec2& x = particles.position[i];
    CHECK(pressure[i] == Approx(1000.0 * 5.0 * (top - (-0.6 * x.x() + 0.8 * x.y()))).margin(1e-9));
  }
  const Scene weightless = load("dambreak.json", {"physics.gravity=[0.0, 0.0]"});
  for (const double p : hydrostatic_block_pressure(weightless, build_particles(weightless), 0.0125)) CHECK(p == 0.0);
}

TEST_CASE("scene validation names the file and the key", "[scene][input]") {
  const std::string source = scene_path("dambreak.json");
  const auto error_of = [&](const std::vector<std::string>& overrides) -> std::string {
    try {
      load("dambreak.json", overrides);
    } catch (const InputError& error) {
      return error.what();
    }
    return "no error";
  };
  CHECK_THAT(error_of({"physics.densty=1000"}),
             Catch::StartsWith(source + ": physics.densty: unknown key") && Catch::Contains("density"));
  CHECK_THAT(error_of({"colour=1"}), Catch::Contains(": colour: unknown key"));
  CHECK_THAT(error_of({"particle_spacing=-0.1"}), Catch::Contains("particle_spacing: got -0.1, expected a number > 0"));
  CHECK_THAT(error_of({"time.time_step=\"fast\""}), Catch::Contains("time.time_step: got \"fast\""));
  CHECK_THAT(error_of({"methods.mps.relaxation=2"}),
             Catch::Contains("methods.mps.relaxation: got 2, expected a number in (0, 1]"));
  CHECK_THAT(error_of({"methods.mps.cg_max_iterations=10.5"}), Catch::Contains("methods.mps.cg_max_iterations"));
  CHECK_THAT(error_of({"methods.mps.wall_treatments.magic={}"}),
             Catch::Contains("methods.mps.wall_treatments.magic: unknown wall treatment"));
  CHECK_THAT(error_of({"methods.mps.wall_treatments.wall_repulsion.strength=3"}),
             Catch::Contains("methods.mps.wall_treatments.wall_repulsion.strength: unknown key"));
  CHECK_THAT(error_of({"methods.sph={}"}), Catch::Contains("methods.sph: unknown method"));
  CHECK_THAT(error_of({"method=\"sph\""}), Catch::Contains("method: unknown method 'sph'"));
  CHECK_THAT(
      error_of({"fluid_blocks.0.max=[1.5,0.5]"}),
      Catch::Contains("fluid_blocks[0].max: got [1.5,0.5], expected a point inside the domain [0.0,0.0] to [1.0,0.6]"));
  CHECK_THAT(
      error_of({"domain.max=[0,0.6]"}),
      Catch::Contains("domain.max: got [0.0,0.6], expected a point above and to the right of domain.min [0.0,0.0]"));
  CHECK_THAT(error_of({"walls.sides=[\"bottom\",\"front\"]"}), Catch::Contains("walls.sides"));
  CHECK_THAT(error_of({"output.frame_every_steps=0"}), Catch::Contains("output.frame_every_steps: got 0"));
  CHECK_THAT(error_of({"physics.gravity=[0]"}), Catch::Contains("physics.gravity: got [0], expected an array of two"));
  CHECK_THAT(error_of({"time.end_time=1e-5"}), Catch::Contains("time.time_step"));
  CHECK_THAT(error_of({"fluid_blocks=[]"}),
             Catch::Contains(
                 "fluid_blocks: got [], expected a non-empty array of blocks (or [] in a scene with a rigid body"));
}

TEST_CASE("a default assignment key?=value sets the key only where nothing gave it", "[scene][loads]") {
  // apply_override (core/io/scene.hpp): "?=" takes the value where the document has none, keeps
  // one the scene or an earlier --set gave, and creates the objects on its way.
  nlohmann::json document = nlohmann::json::parse(R"({"a": {"b": 1}})");
  apply_override(document, "a.b?=2", "test");
  CHECK(document["a"]["b"] == 1);
  apply_override(document, "a.c?=3", "test");
  CHECK(document["a"]["c"] == 3);
  apply_override(document, "x.y.z?={\"k\": true}", "test");
  CHECK(document["x"]["y"]["z"]["k"] == true);
  apply_override(document, "a.b=4", "test");  // the plain form still replaces
  CHECK(document["a"]["b"] == 4);
  CHECK_THROWS_WITH(apply_override(document, "?=1", "test"), Catch::Contains("expected key=value"));
  // A method's load-setting defaults (MethodInfo::load_setting) survive a --set that replaces the
  // whole wall_treatments block to name the boundary model, and yield to one that gives the key.
  for (const auto* method : registries().methods.all()) {
    for (const auto& [key, value] : method->load_setting.defaults) {
      INFO("methods." << method->name << "." << key);
      const std::string block = "methods." + method->name;
      std::string path = "/methods/" + method->name + "/" + key;
      std::replace(path.begin(), path.end(), '.', '/');
      const nlohmann::json::json_pointer pointer(path);
      nlohmann::json named = nlohmann::json::parse(read_text(scene_path("hydrostatic.json")));
      for (const auto& assignment : with_load_setting(*method, {block + ".wall_treatments={\"dummy_layers\":{}}"})) {
        apply_override(named, assignment, "test");
      }
      CHECK(named.at(pointer) == nlohmann::json::parse(value));
      CHECK(named["methods"][method->name]["wall_treatments"].contains("dummy_layers"));
      nlohmann::json given = nlohmann::json::parse(read_text(scene_path("hydrostatic.json")));
      for (const auto& assignment : with_load_setting(*method, {block + "." + key + "=0.123"})) {
        apply_override(given, assignment, "test");
      }
      CHECK(given.at(pointer) == 0.123);
    }
  }
}

TEST_CASE("overrides set nested keys and defaults come from the spec", "[scene]") {
  const Scene scene =
      load("dambreak.json", {"time.end_time=0.5", "methods.mps.relaxation=0.3", "output.directory=runs/x"});
  CHECK(scene.time.end_time == 0.5);
  CHECK(scene.output.directory == "runs/x");
  CHECK(scene.method_config("mps").parameters.number("relaxation") == 0.3);
  // A minimal scene: everything but domain and fluid comes from the spec's defaults (§3).
  const Scene minimal = parse(R"({"domain": {"min": [0, 0], "max": [1.0, 0.6]},
                                  "fluid_blocks": [{"min": [0, 0], "max": [0.25, 0.5]}]})");
  CHECK(minimal.particle_spacing == 0.025);
  CHECK(minimal.physics.density == 1000.0);
  CHECK(minimal.physics.kinematic_viscosity == 1.0e-6);
  CHECK(minimal.physics.gravity.y() == -9.81);
  CHECK(minimal.time.time_step == 5.0e-4);
  CHECK(minimal.time.end_time == 2.0);
  CHECK(minimal.output.frame_every_steps == 100);
  const auto& mps = minimal.method_config("mps");
  CHECK(mps.parameters.number("re_number_density") == 2.1);
  CHECK(mps.parameters.number("free_surface_threshold") == 0.97);
  CHECK(mps.parameters.number("relaxation") == 0.2);
  CHECK(mps.parameters.integer("cg_max_iterations") == 10000);
  CHECK(mps.parameters.number("cg_tolerance") == 1.0e-8);
  // The four spec measures are on by default, with the spec's values.
  std::set<std::string> enabled;
  for (const auto& choice : mps.wall_treatments) {
    if (choice.enabled) enabled.insert(choice.info->name);
  }
  CHECK(enabled == std::set<std::string>{"spec_wall_particles", "cfl_velocity_clamp", "wall_repulsion",
                                         "wall_position_clamp", "particle_collision"});
  // And each can be switched off.
  const Scene off = load("dambreak.json", {"methods.mps.wall_treatments.particle_collision.enabled=false"});
  for (const auto& choice : off.method_config("mps").wall_treatments) {
    if (choice.info->name == "particle_collision") CHECK_FALSE(choice.enabled);
  }
  // Missing required keys.
  CHECK_THROWS_WITH(parse(R"({"fluid_blocks": [{"min": [0, 0], "max": [0.25, 0.5]}]})"),
                    Catch::Contains("domain: missing"));
  CHECK_THROWS_WITH(parse(R"({"domain": {"min": [0, 0]}, "fluid_blocks": []})"),
                    Catch::Contains("domain.max: missing"));
}
