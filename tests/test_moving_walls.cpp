// Moving walls (core/walls/wall_motion.hpp, core/walls/moving_walls.hpp; docs/walls.md "Moving
// walls"): each motion law against its formula, the scene's errors for bad motion input, the
// wall particles of a moving obstacle where the law puts them for every boundary model of wall
// particles, a law that does not move costing nothing (bit-identical results), resume bit for
// bit with a moving gate, and the released gate's front against Martin & Moyce.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <optional>

#include "core/base/error.hpp"
#include "core/io/geometry.hpp"
#include "core/run/driver.hpp"
#include "lab/compare.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;
namespace fs = std::filesystem;

namespace {

constexpr double kPi = 3.141592653589793;

// The gate scene's error for a motion block given as JSON.
std::string motion_error(const std::string& motion_json) {
  return scene_error("dambreak_gate.json", {"walls.obstacles=[{\"min\": [0.25, 0.0], \"max\": [0.275, 0.55], "
                                            "\"motion\": " +
                                            motion_json + "}]"});
}

// The indices of the wall particles inside the gate's box at t = 0 (not the bed's row).
std::vector<std::size_t> gate_particles(const ParticleSet& particles) {
  std::vector<std::size_t> gate;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const Vec2& x = particles.position[i];
    if (particles.type[i] == ParticleType::Wall && x.x() > 0.249 && x.x() < 0.276 && x.y() > 0.001) gate.push_back(i);
  }
  return gate;
}

// Bit equality of two vectors (a NaN equals itself).
bool same_bits(const Vec2& a, const Vec2& b) { return std::memcmp(a.data(), b.data(), 2 * sizeof(double)) == 0; }

// Every method that moves walls (MethodInfo::moving_walls) with every boundary model it may use
// that moves walls (WallTreatmentInfo::moving_walls), from their declarations.
std::vector<std::pair<const MethodInfo*, const WallTreatmentInfo*>> moving_wall_pairs() {
  std::vector<std::pair<const MethodInfo*, const WallTreatmentInfo*>> pairs;
  for (const MethodInfo* info : registries().methods.all()) {
    if (!info->moving_walls) continue;
    for (const WallTreatmentInfo* model : registries().walls.all()) {
      if (model->role == WallTreatmentRole::Boundary && model->moving_walls && wall_treatment_supports(*model, *info)) {
        pairs.emplace_back(info, model);
      }
    }
  }
  return pairs;
}

}  // namespace

TEST_CASE("motion laws: displacement and velocity against their formulas", "[walls][moving]") {
  // Exact formulas of core/walls/wall_motion.hpp; 1e-12 is rounding of O(1) numbers.
  WallMotion v;
  v.law = MotionLaw::ConstantVelocity;
  v.velocity = Vec2(0.3, -0.1);
  v.start_time = 0.5;
  CHECK(v.displacement(0.2).norm() == 0.0);  // at rest before t_s
  CHECK(v.velocity_at(0.2).norm() == 0.0);
  CHECK((v.displacement(1.5) - Vec2(0.3, -0.1)).norm() < 1e-12);
  CHECK((v.velocity_at(1.5) - Vec2(0.3, -0.1)).norm() < 1e-12);

  WallMotion a;
  a.law = MotionLaw::ConstantAcceleration;
  a.acceleration = Vec2(0.0, 9.81);
  a.max_speed = 3.5;  // reached at tau = 3.5 / 9.81 = 0.3568 s
  CHECK((a.displacement(0.2) - Vec2(0.0, 0.5 * 9.81 * 0.04)).norm() < 1e-12);
  CHECK((a.velocity_at(0.2) - Vec2(0.0, 9.81 * 0.2)).norm() < 1e-12);
  CHECK((a.acceleration_at(0.2) - Vec2(0.0, 9.81)).norm() < 1e-12);
  const double tc = 3.5 / 9.81;
  CHECK(a.displacement(1.0).y() == Approx(0.5 * 9.81 * tc * tc + 3.5 * (1.0 - tc)).epsilon(1e-12));
  CHECK(a.velocity_at(1.0).y() == Approx(3.5).epsilon(1e-12));
  CHECK(a.acceleration_at(1.0).norm() == 0.0);

  WallMotion s;
  s.law = MotionLaw::Sinusoid;
  s.amplitude = Vec2(0.02, 0.01);
  s.period = 0.8;
  s.phase = 0.3;
  const double t = 0.37, w = 2.0 * kPi / 0.8;
  CHECK(s.displacement(0.0).norm() == 0.0);  // starts at the scene position
  CHECK((s.displacement(t) - (std::sin(w * t + 0.3) - std::sin(0.3)) * Vec2(0.02, 0.01)).norm() < 1e-12);
  CHECK((s.velocity_at(t) - w * std::cos(w * t + 0.3) * Vec2(0.02, 0.01)).norm() < 1e-12);
  // Velocity is the derivative of the displacement: central difference, error O(h^2 w^3 A) < 1e-8.
  const double h = 1e-5;
  CHECK(((s.displacement(t + h) - s.displacement(t - h)) / (2 * h) - s.velocity_at(t)).norm() < 1e-8);

  WallMotion table;
  table.law = MotionLaw::Table;
  table.times = {0.0, 0.1, 0.3};
  table.offsets = {Vec2(1.0, 1.0), Vec2(1.0, 1.2), Vec2(1.1, 1.2)};
  CHECK(table.displacement(0.0).norm() == 0.0);  // relative to the first row
  CHECK((table.displacement(0.05) - Vec2(0.0, 0.1)).norm() < 1e-12);
  CHECK((table.velocity_at(0.05) - Vec2(0.0, 2.0)).norm() < 1e-12);  // slope 0.2 m / 0.1 s
  CHECK((table.displacement(0.2) - Vec2(0.05, 0.2)).norm() < 1e-12);
  CHECK((table.velocity_at(0.2) - Vec2(0.5, 0.0)).norm() < 1e-12);
  CHECK((table.displacement(1.0) - Vec2(0.1, 0.2)).norm() < 1e-12);  // held after the last row
  CHECK(table.velocity_at(1.0).norm() == 0.0);
}

TEST_CASE("moving walls: bad motion input is a one-line error naming the file and the key", "[walls][moving]") {
  const auto dir = fresh_directory("moving_walls_tables");
  write_text(dir / "backwards.csv", "t,x,y\n0,0,0\n0.2,0,0.1\n0.1,0,0.2\n");
  write_text(dir / "short.csv", "t,x,y\n0,0,0\n");
  write_text(dir / "broken.csv", "t,x,y\n0,0,0\n0.1,zero,0\n");
  const std::string gate = read_text(scene_path("dambreak_gate.json"));
  const auto error_with_table = [&](const std::string& file) {
    write_text(dir / "scene.json", gate);
    try {
      load_scene((dir / "scene.json").string(),
                 {"walls.obstacles=[{\"min\": [0.25, 0.0], \"max\": [0.275, 0.55], \"motion\": {\"law\": \"table\", "
                  "\"file\": \"" +
                  file + "\"}}]"},
                 registries().methods, registries().walls);
    } catch (const InputError& error) {
      return std::string(error.what());
    }
    return std::string();
  };
  const std::string key = "walls.obstacles[0].motion";
  struct Case {
    std::string message;
    std::string expected;
  };
  const std::vector<Case> cases = {
      {error_with_table("backwards.csv"), key + ".file"},
      {error_with_table("backwards.csv"), "strictly increasing"},
      {error_with_table("missing.csv"), "cannot read the motion table"},
      {error_with_table("short.csv"), "expected at least two"},
      {error_with_table("broken.csv"), "line 3"},
      {motion_error(R"({"law": "sinusoid", "amplitude": [0, 0.1], "period": -1})"), key + ".period"},
      {motion_error(R"({"law": "sinusoid", "amplitude": [0, 0.1]})"), key + ".period"},
      {motion_error(R"({"law": "sinusoid", "period": 1, "velocity": [0, 1]})"), key + ".velocity"},
      {motion_error(R"({"law": "spin"})"), key + ".law"},
      {motion_error(R"({"law": "constant_velocity", "speed": 1})"), key + ".speed"},
      {motion_error(R"({"law": "constant_acceleration", "max_speed": -1})"), key + ".max_speed"},
  };
  for (const Case& test : cases) {
    INFO(test.message);
    CHECK_THAT(test.message, Catch::Contains(test.expected));
    CHECK(test.message.find('\n') == std::string::npos);
  }
  CHECK_THAT(error_with_table("backwards.csv"), Catch::Contains("scene.json"));
  // A boundary model that does not move walls (WallTreatmentInfo::moving_walls false: here a copy
  // of dummy_layers without the declaration) refuses a moving obstacle when the run starts.
  WallTreatmentRegistry walls = builtin_wall_treatments();
  WallTreatmentInfo fixed_layers = *walls.find("dummy_layers");
  fixed_layers.name = "fixed_dummy_layers";
  fixed_layers.moving_walls = false;
  walls.add(fixed_layers);
  const MethodInfo* isph = registries().methods.find("isph");
  if (isph != nullptr) {
    const Scene samples = load_scene(scene_path("dambreak_gate.json"),
                                     {"methods.isph.wall_treatments.fixed_dummy_layers.enabled=true",
                                      "methods.isph.wall_treatments.adami_wall_particles.enabled=false"},
                                     registries().methods, walls);
    CHECK_THROWS_WITH(Simulation(samples, *isph), Catch::Contains("walls.obstacles[0].motion") &&
                                                      Catch::Contains("fixed_dummy_layers does not move walls"));
  }
  // A method whose operators ignore the walls' velocity refuses one too (MethodInfo::moving_walls).
  for (const MethodInfo* info : registries().methods.all()) {
    if (info->moving_walls) continue;
    INFO(info->name);
    const Scene gated = load("dambreak_gate.json", {"method=" + info->name});
    CHECK_THROWS_WITH(Simulation(gated, *info), Catch::Contains("walls.obstacles[0].motion") &&
                                                    Catch::Contains("does not use a wall's velocity"));
  }
}

TEST_CASE("moving walls: the gate's wall particles are where the law says for every wall-particle model",
          "[walls][moving]") {
  // mps: spec_wall_particles, isph: adami_wall_particles, dfsph: akinci_boundary (their
  // defaults) and akinci_boundary with Akinci's kernel-sum volume (recomputed as walls move).
  struct Case {
    std::string method;
    std::vector<std::string> overrides;
  };
  const std::vector<Case> cases = {{"mps", {}},
                                   {"isph", {}},
                                   {"dfsph", {}},
                                   {"dfsph", {"methods.dfsph.wall_treatments.akinci_boundary.volume=\"akinci\""}}};
  for (const Case& test : cases) {
    const MethodInfo* info = registries().methods.find(test.method);
    if (info == nullptr) continue;
    INFO(test.method << (test.overrides.empty() ? "" : " " + test.overrides[0]));
    const Scene scene = load("dambreak_gate.json", test.overrides);
    const ParticleSet initial = build_particles(scene, true);
    const std::vector<std::size_t> gate = gate_particles(initial);
    REQUIRE(gate.size() == 2 * 22);  // two columns, y = 0.025 ... 0.55 (the bed row stays with the tank)
    Simulation simulation(scene, *info);
    for (int step = 0; step < 40; ++step) simulation.advance();
    const double t = simulation.time();
    const WallMotion& law = scene.walls.motions[0];
    const ParticleSet& now = simulation.particles();
    double worst_position = 0.0, worst_velocity = 0.0;
    for (const std::size_t i : gate) {
      worst_position = std::max(worst_position, (now.position[i] - initial.position[i] - law.displacement(t)).norm());
      worst_velocity = std::max(worst_velocity, (now.velocity[i] - law.velocity_at(t)).norm());
    }
    // Positions are recomputed x(0) + d(t): only the rounding of one addition (1e-15 m).
    CHECK(worst_position < 1e-14);
    CHECK(worst_velocity < 1e-14);
    CHECK(law.displacement(t).y() == Approx(0.5 * 9.81 * t * t).epsilon(1e-12));  // a = g, 40 steps of 5e-4 s
    // The tank does not move: the bed's first row under the gate stays at y = 0.
    for (std::size_t i = 0; i < now.size(); ++i) {
      if (now.type[i] == ParticleType::Wall && initial.position[i].y() == 0.0) CHECK(now.position[i].y() == 0.0);
    }
  }
}

TEST_CASE("moving walls: a law that does not move costs nothing - bit-identical to a fixed obstacle",
          "[walls][moving]") {
  // Two scenes, each with its obstacle fixed and with a law of zero velocity: the moving-wall
  // path (recomputed positions, prescribed wall velocity 0 in every operator; for wall samples the
  // moving geometry at zero displacement, exact zeros in the samples' motion terms, and the
  // position clamp at the pose) must give the same bits as the fixed walls.
  //   scenes/dambreak_obstacle.json, 60 steps: a box on the bed in the surge's way;
  //   scenes/dambreak_gate.json with its gate standing, 200 steps (0.1 s): the column against the
  //     one-spacing gate, where mps with distance_function needs the position clamp at the gate
  //     (without it the fixed gate lets the column in at step 71, docs/walls.md).
  // Every method that moves walls (MethodInfo::moving_walls) with every boundary model it may use
  // that moves walls (WallTreatmentInfo::moving_walls). Pressure sensors are left out (a sensor
  // does not follow a moving wall), and the monitor records instead of stopping: dfsph with
  // distance_function lets a particle into a thin obstacle and blows up behind the standing gate,
  // fixed or not (docs/walls.md); the bits are compared as bits (a NaN equals itself).
  const std::vector<std::pair<std::string, int>> scenes = {{"dambreak_obstacle.json", 60}, {"dambreak_gate.json", 200}};
  for (const auto& [info, model] : moving_wall_pairs()) {
    for (const auto& [file, steps] : scenes) {
      INFO(info->name << " with " << model->name << " on " << file);
      std::vector<std::string> overrides = boundary_model_overrides(file, info->name, model->name);
      overrides.insert(overrides.end(), {"diagnostics.pressure_sensors=[]", "stability.on_divergence=\"continue\""});
      auto fixed_json = load(file, overrides).document;
      fixed_json["walls"]["obstacles"][0].erase("motion");
      const Scene fixed = parse_scene(fixed_json, scene_path(file), registries().methods, registries().walls);
      auto moving_json = fixed_json;
      moving_json["walls"]["obstacles"][0]["motion"] = {{"law", "constant_velocity"}, {"velocity", {0.0, 0.0}}};
      const Scene moving = parse_scene(moving_json, fixed.source, registries().methods, registries().walls);
      REQUIRE(!fixed.walls.any_moving());
      REQUIRE(moving.walls.any_moving());
      Simulation a(fixed, *info), b(moving, *info);
      for (int step = 0; step < steps; ++step) {
        a.advance();
        b.advance();
      }
      const ParticleSet& pa = a.particles();
      const ParticleSet& pb = b.particles();
      REQUIRE(pa.size() == pb.size());
      std::size_t different = 0;
      for (std::size_t i = 0; i < pa.size(); ++i) {
        if (!same_bits(pa.position[i], pb.position[i]) || !same_bits(pa.velocity[i], pb.velocity[i]) ||
            std::memcmp(&pa.pressure[i], &pb.pressure[i], sizeof(double)) != 0) {
          ++different;
        }
      }
      CHECK(different == 0);
      CHECK(pa.wall_velocity.empty());  // fixed walls allocate nothing
      CHECK(pa.obstacle_pose.empty());  // and carry no poses
      CHECK(pb.obstacle_pose.size() == 1);
    }
  }
}

TEST_CASE("moving walls: interrupted and resumed = uninterrupted with a moving gate - bit for bit",
          "[walls][moving][checkpoint]") {
  // The laws are functions of t, so the resumed run recomputes the gate where the uninterrupted
  // run has it; series and frames must be the same bytes. 0.1 s = 200 fixed steps (mps, isph),
  // stopped at 97; dfsph's CFL steps are longer (about 20 in 0.1 s), stopped at 7.
  struct Case {
    std::string method;
    long long stop;
  };
  for (const Case& test : std::vector<Case>{{"mps", 97}, {"isph", 97}, {"dfsph", 7}}) {
    const std::string& method = test.method;
    if (registries().methods.find(method) == nullptr) continue;
    INFO(method);
    const auto full_dir = fresh_directory("moving_resume_full_" + method);
    const auto part_dir = fresh_directory("moving_resume_part_" + method);
    const auto run = [&](const fs::path& folder, long long stop_after) {
      RunOptions options;
      options.scene_path = scene_path("dambreak_gate.json");
      options.method = method;
      options.output_directory = folder.string();
      options.end_time = 0.1;
      auto polls = std::make_shared<long long>(0);
      if (stop_after > 0) options.stop_reason = [polls, stop_after] { return ++*polls >= stop_after ? "a test" : ""; };
      return run_simulation(options, registries().methods, registries().walls);
    };
    const RunResult full = run(full_dir, 0);
    REQUIRE(full.status == "completed");
    REQUIRE(run(part_dir, test.stop).status == "interrupted");
    RunOptions resume;
    resume.resume_directory = part_dir;
    const RunResult resumed = run_simulation(resume, registries().methods, registries().walls);
    CHECK(resumed.status == "completed");
    CHECK(resumed.steps == full.steps);
    const auto expected = run_folder_files(full_dir);
    const auto actual = run_folder_files(part_dir);
    REQUIRE(expected.size() == actual.size());
    for (const auto& [name, content] : expected) {
      INFO(name);
      CHECK(actual.at(name) == content);
    }
    CHECK(series_rows_without_wall_seconds(part_dir) == series_rows_without_wall_seconds(full_dir));
  }
}

TEST_CASE("released gate: the front against Martin and Moyce at l0 = 0.025 without a time shift",
          "[validation][walls][moving]") {
  // scenes/dambreak_gate.json to 0.4 s (T = 3.9, past the last point of Table 2) with every method
  // that moves walls and every boundary model it may use that does. Measured unshifted front RMS
  // (docs/validation.md, "The released gate"): own walls mps 0.523, isph 0.457, dfsph 0.477 (without
  // the gate 0.126, 0.112, 0.116); wall samples 0.43-0.70, mps with mirror particles 1.59 (the
  // distance function's rows with its corner rule `blended`, the default since 2026-11-28: mps
  // 0.697, isph 0.430, dfsph 0.480; with `nearest` 0.537, 0.472, 0.563: the jet under the gate runs
  // further with blended, 0.88 m against 0.82 at 0.375 s for mps, and breaks off sooner). At
  // this spacing the jet that leaves under the rising gate breaks from the column and the front
  // (the largest connected body, docs/validation.md) falls back to the column: the gate at the
  // Lauber & Hager limit makes the unshifted RMS worse, not better. Tolerance 0.1: Martin & Moyce's
  // own scatter (digitisations differ by up to 0.06 RMS) with a margin for the jet's break-up,
  // which moves with any change of the discretisation; it still tells the gate's 0.46-0.64 from
  // the instantaneous release's 0.11-0.13. A pair not in the table (a new method or model) must
  // complete; its RMS is reported.
  const std::map<std::pair<std::string, std::string>, double> measured = {
      {{"mps", "spec_wall_particles"}, 0.523},   {{"mps", "dummy_layers"}, 0.621},
      {{"mps", "mirror_particles"}, 1.591},      {{"mps", "distance_function"}, 0.697},
      {{"isph", "adami_wall_particles"}, 0.457}, {{"isph", "dummy_layers"}, 0.518},
      {{"isph", "mirror_particles"}, 0.510},     {{"isph", "distance_function"}, 0.430},
      {{"dfsph", "akinci_boundary"}, 0.477},     {{"dfsph", "dummy_layers"}, 0.637},
      {{"dfsph", "mirror_particles"}, 0.474},    {{"dfsph", "distance_function"}, 0.480}};
  for (const auto& [info, model] : moving_wall_pairs()) {
    INFO(info->name << " with " << model->name);
    const auto out = fresh_directory("gate_front_" + info->name + "_" + model->name);
    RunOptions options;
    options.scene_path = scene_path("dambreak_gate.json");
    options.method = info->name;
    options.overrides = boundary_model_overrides("dambreak_gate.json", info->name, model->name);
    options.output_directory = out.string();
    REQUIRE(run_simulation(options, registries().methods, registries().walls).status == "completed");
    const RunEvaluation evaluation = evaluate_run(out);
    INFO("front RMS " << evaluation.front_rms << " best shift " << evaluation.front_shift << " -> "
                      << evaluation.front_rms_shifted);
    CHECK(evaluation.front_points == 15);
    const auto known = measured.find({info->name, model->name});
    if (known != measured.end()) CHECK(evaluation.front_rms == Approx(known->second).margin(0.1));
  }
}
