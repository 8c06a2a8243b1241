// Moving walls with the boundary models of wall samples (core/walls/wall_sample_model.hpp:
// dummy_layers, mirror_particles, distance_function; docs/walls.md "Moving walls"): the
// samples of a moved gate lie where its pose puts it and carry its motion
// (u_w = M u_s + (I - M) u_wall, a_w in p_w = p_s + rho0 (g - a_w) . (x_w - x_s)), its foot at the
// bed's surface once lifted, and a resumed run gives the bits of an uninterrupted one (a law that
// does not move gives the bits of a fixed obstacle, and the gated dam break its front, with every
// boundary model: tests/test_moving_walls.cpp). The models and
// methods come from their declarations (WallTreatmentInfo::moving_walls, MethodInfo::moving_walls,
// wall_treatment_supports): a new model of wall samples is tested here without editing this file.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>

#include "core/io/geometry.hpp"
#include "core/run/driver.hpp"
#include "core/search/neighbour_search.hpp"
#include "core/walls/wall_geometry.hpp"
#include "core/walls/wall_treatment.hpp"
#include "lab/compare.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;
namespace fs = std::filesystem;

namespace {

// The boundary models of wall samples that move walls.
std::vector<const WallTreatmentInfo*> moving_sample_models() {
  std::vector<const WallTreatmentInfo*> models;
  for (const WallTreatmentInfo* info : registries().walls.all()) {
    if (info->role == WallTreatmentRole::Boundary && !info->wall_particles && info->moving_walls) {
      models.push_back(info);
    }
  }
  return models;
}

// The methods that use a wall's velocity and may use `model`.
std::vector<const MethodInfo*> methods_for(const WallTreatmentInfo& model) {
  std::vector<const MethodInfo*> methods;
  for (const MethodInfo* info : registries().methods.all()) {
    if (info->moving_walls && wall_treatment_supports(model, *info)) methods.push_back(info);
  }
  return methods;
}

Scene scene_with_model(const std::string& file, const std::string& method, const std::string& model,
                       std::vector<std::string> extra = {}) {
  std::vector<std::string> overrides = boundary_model_overrides(file, method, model);
  overrides.insert(overrides.end(), extra.begin(), extra.end());
  return load(file, overrides);
}

}  // namespace

TEST_CASE("moving wall samples: every built-in model of wall samples moves walls", "[walls][moving]") {
  // dummy_layers, mirror_particles and distance_function (the three of docs/walls.md).
  CHECK(moving_sample_models().size() >= 3);
  for (const WallTreatmentInfo* model : moving_sample_models()) {
    INFO(model->name);
    CHECK(!methods_for(*model).empty());
  }
}

TEST_CASE("moving wall samples: the moved gate's foot is the bed's surface lifted by d, its faces follow the pose",
          "[walls][moving]") {
  // scenes/dambreak_gate.json, l0 = 0.025 m: the gate x = 0.25 ... 0.275 m, y = 0 ... 0.55 m; its
  // surface the box grown by l0/2. At rest the geometry is the fixed obstacle's (its bottom face
  // buried in the bed, no segment); lifted by d its box is cut at the bed's surface first, so its
  // bottom face lies at y = l0/2 + d (where its lowest wall-particle row, y = l0, puts it: the
  // bed keeps the row at y = 0), and the gap under it is d.
  const Scene scene = load("dambreak_gate.json");
  const double l0 = scene.particle_spacing;
  WallGeometry geometry(scene, MovingObstacles::Included);
  REQUIRE(geometry.has_moving_obstacles());
  const auto faces_of_gate = [&](const WallGeometry& g) {
    std::vector<WallSegment> faces;
    for (const WallSegment& segment : g.segments()) {
      if (segment.body == 0) faces.push_back(segment);
    }
    return faces;
  };
  for (const WallSegment& face : faces_of_gate(geometry)) CHECK(face.normal.y() != -1.0);  // no bottom face at rest
  std::vector<RigidPose> poses(1);
  poses[0].displacement = Vec2(0.0, 0.1);
  poses[0].velocity = Vec2(0.0, 2.0);
  geometry.move_obstacles(poses);
  std::size_t bottom = 0, sides = 0;
  for (const WallSegment& face : faces_of_gate(geometry)) {
    if (face.normal.y() == -1.0) {
      ++bottom;
      CHECK(face.a.y() == Approx(0.5 * l0 + 0.1).margin(1e-12));
      CHECK(std::min(face.a.x(), face.b.x()) == Approx(0.25 - 0.5 * l0).margin(1e-12));
      CHECK(std::max(face.a.x(), face.b.x()) == Approx(0.275 + 0.5 * l0).margin(1e-12));
    }
    if (std::fabs(face.normal.x()) == 1.0) {
      ++sides;
      CHECK(std::min(face.a.y(), face.b.y()) == Approx(0.5 * l0 + 0.1).margin(1e-12));
      CHECK(std::max(face.a.y(), face.b.y()) == Approx(0.55 + 0.5 * l0 + 0.1).margin(1e-12));
    }
    CHECK(geometry.wall_velocity(face, 0.5 * (face.a + face.b)) == Vec2(0.0, 2.0));
  }
  CHECK(bottom == 1);
  CHECK(sides == 2);
  // Inside the gap (under the lifted gate) is fluid space; inside the gate is solid.
  CHECK(!geometry.inside_solid(Vec2(0.2625, 0.5 * l0 + 0.05)));
  CHECK(geometry.inside_solid(Vec2(0.2625, 0.5 * l0 + 0.15)));
}

TEST_CASE("moving wall samples: crossing a moving face - reflected, the velocity into it relative to it removed",
          "[walls][moving]") {
  // The gate lifted by 0.1 m and moving right at 1 m/s (its left face x = 0.2375 m, normal -x).
  // Three fluid particles 1 mm behind the face at y = 0.3 m: moving right at 0.5 m/s (slower than
  // the face: leaving it, relative normal speed +0.5, kept), at 1.5 m/s (into it at 0.5 m/s
  // relative: the normal part becomes the face's, 1 m/s), and at rest (the face moves away from
  // it: kept at 0; a rule on the absolute velocity would stop the first two, u_n -> 0). Each is
  // reflected to 1 mm in front of the face; the tangential speed stays.
  const Scene scene = load("dambreak_gate.json");
  WallGeometry geometry(scene, MovingObstacles::Included);
  std::vector<RigidPose> poses(1);
  poses[0].displacement = Vec2(0.0, 0.1);
  poses[0].velocity = Vec2(1.0, 0.0);
  geometry.move_obstacles(poses);
  const double face = 0.25 - 0.5 * scene.particle_spacing;  // m
  ParticleSet particles;
  for (const double u : {0.5, 1.5, 0.0}) particles.add(Vec2(face + 1e-3, 0.3), Vec2(u, 0.2), ParticleType::Fluid);
  CHECK(reflect_crossed_particles(particles, geometry) == 3);
  const double expected[] = {0.5, 1.0, 0.0};
  for (std::size_t i = 0; i < 3; ++i) {
    INFO("particle " << i);
    CHECK(particles.position[i].x() == Approx(face - 1e-3).margin(1e-12));
    CHECK(particles.velocity[i].x() == Approx(expected[i]).margin(1e-12));
    CHECK(particles.velocity[i].y() == 0.2);
  }
}

TEST_CASE("moving wall samples: the samples of a moved gate lie in it and carry its velocity and acceleration",
          "[walls][moving]") {
  // The gate of scenes/dambreak_gate.json (x = 0.25 ... 0.275 m, surface l0/2 beyond) put at
  // d = (0, 0.1) m with u = (0.3, 2) m/s and a = (0, 9.81) m/s^2 (a pose no law of the scene
  // has: the samples must take it from ParticleSet::obstacle_pose). Probe fluid particles
  // 0.6 l0 in front of its left face at y = 0.3 m and in the column. Every sample within the
  // moved gate's solid carries wall_velocity = (I - M) u and wall_acceleration = a; the samples
  // of the tank none; no sample lies where the gate was and no longer is.
  const Vec2 d(0.0, 0.1), u(0.3, 2.0), a(0.0, 9.81);
  for (const WallTreatmentInfo* model : moving_sample_models()) {
    const std::vector<const MethodInfo*> methods = methods_for(*model);
    REQUIRE(!methods.empty());
    INFO(model->name);
    const Scene scene = scene_with_model("dambreak_gate.json", methods.front()->name, model->name);
    const double l0 = scene.particle_spacing;
    ParticleSet particles = build_particles(scene, false);
    particles.add(Vec2(0.25 - 0.5 * l0 - 0.6 * l0, 0.3), Vec2(0.1, -0.2), ParticleType::Fluid);
    particles.add(Vec2(0.25 - 0.5 * l0 - 0.6 * l0, 0.05), Vec2(0.0, 0.0), ParticleType::Fluid);
    particles.obstacle_pose.assign(scene.walls.obstacles.size(), RigidPose{});
    particles.obstacle_pose[0].displacement = d;
    particles.obstacle_pose[0].velocity = u;
    particles.obstacle_pose[0].acceleration = a;
    const double support = 2.1 * l0;
    const NeighbourList neighbours = find_neighbours(particles.position, particles.type, support);
    WallTreatmentSet set(scene.method_config(methods.front()->name).wall_treatments, scene);
    WallContext context{particles, &neighbours, 5e-4, scene};
    context.support = support;
    WallSampleList samples;
    set.build_wall_samples(context, samples);
    REQUIRE(samples.has_samples());
    const Vec2 low = scene.walls.obstacles[0].min + d - Vec2(0.5 * l0, 0.5 * l0);
    const Vec2 high = scene.walls.obstacles[0].max + d + Vec2(0.5 * l0, 0.5 * l0);
    std::size_t in_gate = 0, elsewhere = 0, in_old_gate_only = 0;
    for (const WallSample& sample : samples.samples) {
      const Vec2& x = sample.position;
      const bool gate = x.x() > low.x() && x.x() < high.x() && x.y() > low.y() && x.y() < high.y();
      const bool bed = x.y() < 0.5 * l0;
      if (gate && !bed) {
        ++in_gate;
        const Vec2 expected = (Mat2::Identity() - sample.velocity_map) * u;
        CHECK((sample.wall_velocity - expected).norm() < 1e-12);
        CHECK((sample.wall_acceleration - a).norm() < 1e-12);
        // p_w - p_s = rho0 (g - a) . (x_w - x_s): with a = -g the head doubles
        const double head = sample_pressure(sample, particles.pressure, particles.position, 1000.0, Vec2(0.0, -9.81));
        const double expected_head = 1000.0 * Vec2(0.0, -19.62).dot(x - particles.position[sample.source]);
        CHECK(head - particles.pressure[sample.source] == Approx(expected_head).margin(1e-9));
      } else {
        ++elsewhere;
        if (x.x() > low.x() && x.x() < high.x() && x.y() < low.y() && !bed) ++in_old_gate_only;
        CHECK(sample.wall_velocity.norm() == 0.0);
        CHECK(sample.wall_acceleration.norm() == 0.0);
      }
    }
    CHECK(in_gate > 0);            // the probe at y = 0.3 m sees the gate's face
    CHECK(elsewhere > 0);          // the column sees the tank
    CHECK(in_old_gate_only == 0);  // the gate's foot, 0.1 m below where it is now, is gone
  }
}

TEST_CASE("moving wall samples: interrupted and resumed = uninterrupted with a moving gate - bit for bit",
          "[walls][moving][checkpoint]") {
  // The gated dam break to 0.03 s (the gate lifted by 4.4 mm, before any model's known failure
  // at the opening, docs/walls.md) with every method and model of wall samples, stopped half-way
  // and resumed: the samples in the checkpoint hold the gate's motion.
  for (const WallTreatmentInfo* model : moving_sample_models()) {
    for (const MethodInfo* info : methods_for(*model)) {
      const std::string& method = info->name;
      INFO(method << " with " << model->name);
      const std::vector<std::string> overrides = boundary_model_overrides("dambreak_gate.json", method, model->name);
      const auto full_dir = fresh_directory("moving_samples_full_" + method + "_" + model->name);
      const auto part_dir = fresh_directory("moving_samples_part_" + method + "_" + model->name);
      const auto run = [&](const fs::path& folder, long long stop_after) {
        RunOptions options;
        options.scene_path = scene_path("dambreak_gate.json");
        options.method = method;
        options.overrides = overrides;
        options.output_directory = folder.string();
        options.end_time = 0.03;
        auto polls = std::make_shared<long long>(0);
        if (stop_after > 0) {
          options.stop_reason = [polls, stop_after] { return ++*polls >= stop_after ? "a test" : ""; };
        }
        return run_simulation(options, registries().methods, registries().walls);
      };
      const RunResult full = run(full_dir, 0);
      REQUIRE(full.status == "completed");
      REQUIRE(full.steps >= 4);
      REQUIRE(run(part_dir, full.steps / 2).status == "interrupted");
      RunOptions resume;
      resume.resume_directory = part_dir;
      const RunResult resumed = run_simulation(resume, registries().methods, registries().walls);
      CHECK(resumed.status == "completed");
      CHECK(resumed.steps == full.steps);
      CHECK(series_rows_without_wall_seconds(part_dir) == series_rows_without_wall_seconds(full_dir));
    }
  }
}

TEST_CASE("moving wall samples: mirror images at the corner of a box sliding on the bed carry the mean wall motion",
          "[walls][moving]") {
  // The gate of scenes/dambreak_gate.json moved 0.05 m along the bed at u = (0.8, 0) m/s,
  // a = (2, 0) m/s^2: once moved, its surface box is cut at the bed's surface, so its left face
  // (x = 0.2875 m) meets the bed (y = 0.0125 m) in a concave corner c. A fluid particle at
  // c + (-0.01, 0.01) m has three images: across the bed (at rest: no motion), across the face
  // (free slip, M = I - 2 n n^T: wall_velocity (I - M) u = 2 (n . u) n = (1.6, 0) m/s, a) and
  // through the corner (M = -I: (I - M) u_c = 2 u_c with u_c the surfaces' mean, (0.4, 0): (0.8, 0)
  // m/s; acceleration the mean, (1, 0) m/s^2).
  const std::vector<std::string> overrides = boundary_model_overrides("dambreak_gate.json", "isph", "mirror_particles");
  const MethodInfo* isph = registries().methods.find("isph");
  if (isph == nullptr) return;
  const Scene scene = load("dambreak_gate.json", overrides);
  const Vec2 corner(0.2875, 0.0125), x = corner + Vec2(-0.01, 0.01);
  ParticleSet particles;
  particles.add(x, Vec2::Zero(), ParticleType::Fluid);
  particles.obstacle_pose.assign(1, RigidPose{});
  particles.obstacle_pose[0].displacement = Vec2(0.05, 0.0);
  particles.obstacle_pose[0].velocity = Vec2(0.8, 0.0);
  particles.obstacle_pose[0].acceleration = Vec2(2.0, 0.0);
  const double support = 2.1 * scene.particle_spacing;
  const NeighbourList neighbours = find_neighbours(particles.position, particles.type, support);
  WallTreatmentSet set(scene.method_config("isph").wall_treatments, scene);
  WallContext context{particles, &neighbours, 5e-4, scene};
  context.support = support;
  WallSampleList samples;
  set.build_wall_samples(context, samples);
  const auto find = [&](const Vec2& at) -> const WallSample* {
    for (const WallSample& sample : samples.samples) {
      if ((sample.position - at).norm() < 1e-12) return &sample;
    }
    return nullptr;
  };
  const WallSample* bed = find(Vec2(x.x(), 2.0 * corner.y() - x.y()));
  const WallSample* face = find(Vec2(2.0 * corner.x() - x.x(), x.y()));
  const WallSample* through = find(2.0 * corner - x);
  REQUIRE(bed != nullptr);
  REQUIRE(face != nullptr);
  REQUIRE(through != nullptr);
  CHECK(bed->wall_velocity == Vec2::Zero());
  CHECK((face->wall_velocity - Vec2(1.6, 0.0)).norm() < 1e-12);
  CHECK((face->wall_acceleration - Vec2(2.0, 0.0)).norm() < 1e-12);
  CHECK((through->wall_velocity - Vec2(0.8, 0.0)).norm() < 1e-12);
  CHECK((through->wall_acceleration - Vec2(1.0, 0.0)).norm() < 1e-12);
}
