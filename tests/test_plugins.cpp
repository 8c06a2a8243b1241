// The plugin interfaces, proved with plugins that live only in this file: a method and a
// wall treatment registered into the test's own registries (no global registry exists).
#include <omp.h>
#include <catch2/catch.hpp>

#include <set>

#include "core/io/geometry.hpp"
#include "core/run/driver.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

namespace {

// A "method" that moves every fluid particle with constant velocity (free streaming).
class FreeStreaming final : public Method {
 public:
  explicit FreeStreaming(const MethodSetup& setup)
      : velocity_(setup.parameters.vector2("velocity")), dt_(setup.scene.time.time_step) {}
  void initialise(ParticleSet& particles) override {
    for (std::size_t i = 0; i < particles.size(); ++i) {
      if (particles.type[i] == ParticleType::Fluid) particles.velocity[i] = velocity_;
    }
  }
  double time_step(const ParticleSet&) const override { return dt_; }
  StepReport step(ParticleSet& particles, double dt) override {
    for (std::size_t i = 0; i < particles.size(); ++i) {
      if (particles.type[i] == ParticleType::Fluid) particles.position[i] += dt * particles.velocity[i];
    }
    StepReport report;
    report.extra = {1.0};
    return report;
  }

 private:
  Vec2 velocity_;
  double dt_;
};

MethodInfo free_streaming_info(bool declare_unused) {
  MethodInfo info;
  info.name = "free_streaming";
  info.description = "test-only: particles move with a constant velocity";
  info.parameters = {vector2_parameter("velocity", Vec2(0.1, 0.0), "m/s", "streaming velocity")};
  if (declare_unused) info.parameters.push_back(number_parameter("unused", 1.0, "", "declared, never read"));
  info.series_columns = {"one"};
  info.create = [](const MethodSetup& setup) { return std::make_unique<FreeStreaming>(setup); };
  return info;
}

// A wall treatment that stops fluid particles below a height after the correction.
class StickyBed final : public WallTreatment {
 public:
  explicit StickyBed(const WallTreatmentSetup& setup) : height_(setup.parameters.number("height")) {}
  void after_correction(WallContext& context) override {
    for (std::size_t i = 0; i < context.particles.size(); ++i) {
      if (context.particles.type[i] == ParticleType::Fluid && context.particles.position[i].y() < height_) {
        context.particles.velocity[i] = Vec2::Zero();
      }
    }
  }

 private:
  double height_;
};

}  // namespace

TEST_CASE("a method registered outside the core runs a scene through the registry", "[plugins]") {
  MethodRegistry methods = builtin_methods();
  methods.add(free_streaming_info(false));
  const WallTreatmentRegistry& walls = registries().walls;
  const Scene scene =
      load_scene(scene_path("dambreak.json"), {"methods.free_streaming.velocity=[0.2,0.0]"}, methods, walls);
  Simulation simulation(scene, *methods.find("free_streaming"));
  const Vec2 before = simulation.particles().position[0];
  simulation.run_to(0.1);
  CHECK(simulation.steps() == 200);
  // Particle 0 by its id: the driver reorders the particles by cell every run.sort_period steps.
  const std::uint32_t first = indices_in_id_order(simulation.particles())[0];
  CHECK((simulation.particles().position[first] - before).x() == Approx(0.02).epsilon(1e-12));
  // Its block is validated like any other.
  CHECK_THROWS_WITH(load_scene(scene_path("dambreak.json"), {"methods.free_streaming.speed=1"}, methods, walls),
                    Catch::Contains("methods.free_streaming.speed: unknown key"));
  // The built-in registry does not know it: no global state was touched.
  CHECK(builtin_methods().find("free_streaming") == nullptr);
}

TEST_CASE("a declared but unread parameter is a start-up error", "[plugins]") {
  MethodRegistry methods = builtin_methods();
  methods.add(free_streaming_info(true));
  const Scene scene = load_scene(scene_path("dambreak.json"), {}, methods, registries().walls);
  CHECK_THROWS_WITH(Simulation(scene, *methods.find("free_streaming")), Catch::Contains("never reads: unused"));
}

TEST_CASE("a wall treatment registered outside the core acts at its hook", "[plugins]") {
  WallTreatmentRegistry walls = builtin_wall_treatments();
  WallTreatmentInfo sticky_bed{"sticky_bed",
                               "test-only: stops fluid below a height",
                               {number_parameter("height", 0.1, "m", "particles below stop").above(0.0)},
                               50,
                               [](const WallTreatmentSetup& setup) { return std::make_unique<StickyBed>(setup); }};
  sticky_bed.hooks = {WallHook::AfterCorrection};  // every built-in method calls it
  walls.add(std::move(sticky_bed));
  const MethodRegistry& methods = registries().methods;
  const Scene scene = load_scene(scene_path("dambreak.json"),
                                 {"methods.mps.wall_treatments.sticky_bed={\"height\": 0.06}"}, methods, walls);
  Simulation simulation(scene, *methods.find("mps"));
  simulation.run_to(0.2);
  // Fluid below 0.06 m had its velocity zeroed at the end of every step.
  const auto& p = simulation.particles();
  std::size_t checked = 0;
  for (std::size_t i = 0; i < p.size(); ++i) {
    if (p.type[i] == ParticleType::Fluid && p.position[i].y() < 0.06) {
      CHECK(p.velocity[i].norm() == 0.0);
      ++checked;
    }
  }
  CHECK(checked > 10);
  // Enabled for a method that does not call its hook (free_streaming declares none): a clear
  // error naming the key.
  MethodRegistry more_methods = builtin_methods();
  more_methods.add(free_streaming_info(false));
  CHECK_THROWS_WITH(load_scene(scene_path("dambreak.json"), {"methods.free_streaming.wall_treatments.sticky_bed={}"},
                               more_methods, walls),
                    Catch::Contains("methods.free_streaming.wall_treatments.sticky_bed: wall treatment 'sticky_bed' "
                                    "does not support method 'free_streaming'"));
}

TEST_CASE("which wall treatments a method gets is computed from its declarations alone", "[plugins][walls]") {
  // A test-only method that sums over wall samples, implements no wall-particle model and
  // calls only two hooks, registered in a test registry: the built-in treatments it may use
  // follow from what both sides declare, with no name of either anywhere.
  MethodRegistry methods;
  MethodInfo info = free_streaming_info(false);
  info.wall_samples = true;
  info.wall_hooks = {WallHook::AfterNeighbourSearch, WallHook::AfterCorrection};
  methods.add(info);
  const MethodInfo& method = *methods.find("free_streaming");
  const WallTreatmentRegistry& walls = registries().walls;
  std::set<std::string> supported;
  for (const auto* wall : walls.all()) {
    if (wall_treatment_supports(*wall, method)) supported.insert(wall->name);
    // Every treatment either fits or says why in one phrase.
    CHECK(wall_treatment_supports(*wall, method) == wall_treatment_support_gap(*wall, method).empty());
  }
  // Wall-sample models: yes (they act after the correction; after the explicit position update
  // only where a method makes one). Measures at called hooks: yes (repulsion and collision
  // after the neighbour search; the position clamp and the shifting after the correction).
  // Wall-particle models: no. The CFL clamp acts after the explicit velocity update: no.
  CHECK(supported == std::set<std::string>{"distance_function", "dummy_layers", "mirror_particles",
                                           "particle_collision", "particle_shifting", "wall_position_clamp",
                                           "wall_repulsion"});
  CHECK_THAT(wall_treatment_support_gap(*walls.find("cfl_velocity_clamp"), method),
             Catch::Equals("it acts at after_explicit_velocity, which 'free_streaming' does not call"));
  CHECK_THAT(wall_treatment_support_gap(*walls.find("akinci_boundary"), method),
             Catch::Equals("its wall particles need the wall-particle model akinci_mirrored, which 'free_streaming' "
                           "does not implement"));

  // Declaring a wall-particle model gives the boundary models that are that model, and no other.
  info.name = "free_streaming_ppe";
  info.wall_samples = false;
  info.wall_particle_models = {WallParticlePressure::SolvedInPpe};
  methods.add(info);
  std::set<std::string> boundaries;
  for (const auto* wall : walls.all()) {
    if (wall->role == WallTreatmentRole::Boundary && wall_treatment_supports(*wall, *methods.find(info.name))) {
      boundaries.insert(wall->name);
    }
  }
  CHECK(boundaries == std::set<std::string>{"spec_wall_particles"});

  // The scene loader refuses an unsupported treatment in one line naming the key and the reason.
  MethodRegistry with_builtins = builtin_methods();
  with_builtins.add(free_streaming_info(false));
  CHECK_THROWS_WITH(load_scene(scene_path("dambreak.json"),
                               {"methods.free_streaming.wall_treatments.cfl_velocity_clamp={}"}, with_builtins, walls),
                    Catch::Contains("methods.free_streaming.wall_treatments.cfl_velocity_clamp: wall treatment "
                                    "'cfl_velocity_clamp' does not support method 'free_streaming' (it acts at "
                                    "after_explicit_velocity, which 'free_streaming' does not call)"));
}

TEST_CASE("a hook the method does not declare cannot run a treatment", "[plugins][walls]") {
  // A WallTreatmentSet knows the hooks its method declares: a treatment that needs another
  // one is refused when the set is built, and a call of an undeclared hook is refused.
  const Scene scene = load("dambreak.json");
  const auto& mps_choices = scene.method_config("mps").wall_treatments;  // cfl clamp: after_explicit_velocity
  CHECK_THROWS_WITH(
      WallTreatmentSet(mps_choices, scene, nullptr, {WallHook::AfterNeighbourSearch, WallHook::AfterCorrection}),
      Catch::Contains("acts at after_explicit_velocity, which the method does not call"));
  WallTreatmentSet set({}, scene, nullptr, {WallHook::AfterCorrection});
  ParticleSet particles = build_particles(scene);
  WallContext context{particles, nullptr, 1e-3, scene};
  CHECK_NOTHROW(set.after_correction(context));
  CHECK_THROWS_WITH(set.after_neighbour_search(context),
                    Catch::Contains("called the wall hook after_neighbour_search it does not declare"));
}

TEST_CASE("same scene - different thread counts: bit-identical particles", "[plugins][determinism]") {
  const Scene scene = load("dambreak.json");
  const int threads = omp_get_max_threads();
  std::vector<Vec2> result[2];
  for (int run = 0; run < 2; ++run) {
    omp_set_num_threads(run == 0 ? 1 : 2);
    Simulation simulation(scene, *registries().methods.find("mps"));
    simulation.run_to(0.25);
    result[run] = simulation.particles().position;
  }
  omp_set_num_threads(threads);
  REQUIRE(result[0].size() == result[1].size());
  std::size_t different = 0;
  for (std::size_t i = 0; i < result[0].size(); ++i) different += result[0][i] != result[1][i];
  CHECK(different == 0);
}
