// The plugin interfaces, proved with plugins that live only in this file: a method and a
// wall treatment registered into the test's own registries (no global registry exists).
#include <catch2/catch.hpp>
#include <omp.h>

#include "core/run/driver.hpp"
#include "core/io/geometry.hpp"
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
  const Scene scene = load_scene(scene_path("dambreak.json"), {"methods.free_streaming.velocity=[0.2,0.0]"}, methods, walls);
  Simulation simulation(scene, *methods.find("free_streaming"));
  const Vec2 before = simulation.particles().position[0];
  simulation.run_to(0.1);
  CHECK(simulation.steps() == 200);
  CHECK((simulation.particles().position[0] - before).x() == Approx(0.02).epsilon(1e-12));
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
  walls.add({"sticky_bed", "test-only: stops fluid below a height", {"mps"},
             {number_parameter("height", 0.1, "m", "particles below stop").above(0.0)}, 50,
             [](const WallTreatmentSetup& setup) { return std::make_unique<StickyBed>(setup); }});
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
  // Enabled for a method it does not list: a clear error naming the key.
  MethodRegistry more_methods = builtin_methods();
  more_methods.add(free_streaming_info(false));
  CHECK_THROWS_WITH(load_scene(scene_path("dambreak.json"), {"methods.free_streaming.wall_treatments.sticky_bed={}"},
                               more_methods, walls),
                    Catch::Contains("methods.free_streaming.wall_treatments.sticky_bed: wall treatment 'sticky_bed' "
                                    "does not support method 'free_streaming'"));
}

TEST_CASE("same scene, different thread counts: bit-identical particles", "[plugins][determinism]") {
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
