// Rigid bodies (core/bodies/, docs/bodies.md): mass properties against closed forms, the scene's
// one-line errors for bad body input, rigid motion of a body's wall particles, the disc on a
// slope against theory (sliding and rolling; issue 15 item 4), the driver's bodies equal to the
// bodies alone when the fluid load is zero, and resume bit for bit with a body.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <memory>

#include "core/base/error.hpp"
#include "core/bodies/mass_properties.hpp"
#include "core/bodies/rigid_bodies.hpp"
#include "core/io/geometry.hpp"
#include "core/run/driver.hpp"
#include "core/run/stability.hpp"
#include "core/walls/obstacle_membership.hpp"
#include "core/walls/wall_geometry.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;
namespace fs = std::filesystem;

namespace {

constexpr double kPi = 3.141592653589793;
// A scene needs fluid unless it has a rigid body: the disc scene with its obstacles replaced by
// fixed or moving ones gets this pool, 8 particles in the right corner.
const std::string kSmallPool = "fluid_blocks=[{\"min\": [1.9, 0.0], \"max\": [1.99, 0.05]}]";

// The disc scene's error with its obstacles replaced by `obstacles` (JSON).
std::string obstacle_error(const std::string& obstacles) {
  return scene_error("disc_on_slope.json", {"walls.obstacles=" + obstacles});
}

// Least-squares fit of s(t) = c0 + c1 t + c2 t^2 / 2; returns c2 (the acceleration).
double fitted_acceleration(const std::vector<double>& t, const std::vector<double>& s) {
  // Normal equations of the basis 1, t, t^2/2 (3x3, solved by Cramer's rule).
  double m[3][3] = {}, r[3] = {};
  for (std::size_t i = 0; i < t.size(); ++i) {
    const double basis[3] = {1.0, t[i], 0.5 * t[i] * t[i]};
    for (int a = 0; a < 3; ++a) {
      r[a] += basis[a] * s[i];
      for (int b = 0; b < 3; ++b) m[a][b] += basis[a] * basis[b];
    }
  }
  const auto det = [](double q[3][3]) {
    return q[0][0] * (q[1][1] * q[2][2] - q[1][2] * q[2][1]) - q[0][1] * (q[1][0] * q[2][2] - q[1][2] * q[2][0]) +
           q[0][2] * (q[1][0] * q[2][1] - q[1][1] * q[2][0]);
  };
  double replaced[3][3];
  for (int a = 0; a < 3; ++a) {
    for (int b = 0; b < 3; ++b) replaced[a][b] = b == 2 ? r[a] : m[a][b];
  }
  return det(replaced) / det(m);
}

struct SlopeRun {
  double theta = 0.0;         // the slope's angle, rad
  double acceleration = 0.0;  // fitted along the slope, m/s^2
  double speed = 0.0;         // along the slope at the end, m/s
  double omega = 0.0;         // at the end, rad/s
  double radius = 0.0;        // m
  double slip_start = 0.0;    // u - omega r (down-slope positive) at the fit's start, m/s
  double slip_end = 0.0;      // the same at the end, m/s
};

// The disc of scenes/disc_on_slope.json with friction mu, the bodies alone (no fluid: zero
// loads), 0.6 s at the scene's step; the centre's distance along the slope fitted over
// [0.1, 0.6] s, after the contact has settled (the normal oscillation's period is
// 2 pi sqrt(m_eff / k) = 0.035 s and zeta = 0.3 damps it by exp(-zeta omega_n t) = e^-5 in 0.1 s).
SlopeRun run_disc(double mu, double stiffness = 1.0e6) {
  const Scene scene = load("disc_on_slope.json", {"contact.friction=" + std::to_string(mu),
                                                  "contact.stiffness=" + std::to_string(stiffness)});
  const auto& slope = scene.walls.polygons[0];
  // The slope edge: from the top vertex (0.01, 0.6615) down to the toe (1.8, 0.01).
  Vec2 top = slope[0], toe = slope[0];
  for (const Vec2& v : slope) {
    if (v.y() > top.y()) top = v;
    if (v.x() > toe.x()) toe = v;
  }
  const Vec2 down = (toe - top).normalized();
  RigidBodies bodies(scene);
  REQUIRE(bodies.size() == 1);
  SlopeRun run;
  run.theta = std::atan2(-down.y(), down.x());
  run.radius = scene.walls.circles[1].radius;
  const double dt = scene.time.time_step;
  std::vector<double> times, distances;
  const ObstacleLoads no_fluid;
  for (int step = 1; step <= 1200; ++step) {
    bodies.advance(dt, no_fluid);
    const double t = step * dt;
    const BodyState& s = bodies.state(0);
    if (t < 0.1 - 1e-12) continue;
    if (times.empty()) run.slip_start = s.velocity.dot(down) + s.angular_velocity * run.radius;
    times.push_back(t);
    distances.push_back((s.position - top).dot(down));
  }
  run.acceleration = fitted_acceleration(times, distances);
  run.speed = bodies.state(0).velocity.dot(down);
  run.omega = bodies.state(0).angular_velocity;
  run.slip_end = run.speed + run.omega * run.radius;  // omega < 0 (clockwise) when rolling down to the right
  return run;
}

}  // namespace

TEST_CASE("mass properties: a box and a triangle and a circle against closed forms", "[bodies]") {
  // Closed forms: box w x h: m = rho w h, I = m (w^2 + h^2) / 12 about the centre; right
  // triangle with legs a (x) and b (y) at the origin: A = ab/2, C = (a/3, b/3), I_C = m (a^2 +
  // b^2) / 18; disc: m = rho pi r^2, I = m r^2 / 2. 1e-12 relative: rounding of sums of a few
  // O(1) products (the polygon formulas are exact).
  const double rho = 800.0;
  const MassProperties box = polygon_mass_properties({{1.0, 2.0}, {1.4, 2.0}, {1.4, 2.3}, {1.0, 2.3}}, rho);
  const double m_box = rho * 0.4 * 0.3;
  CHECK(box.area == Approx(0.12).epsilon(1e-12));
  CHECK(box.mass == Approx(m_box).epsilon(1e-12));
  CHECK(box.centroid.x() == Approx(1.2).epsilon(1e-12));
  CHECK(box.centroid.y() == Approx(2.15).epsilon(1e-12));
  CHECK(box.inertia == Approx(m_box * (0.16 + 0.09) / 12.0).epsilon(1e-12));
  // The same box clockwise: the same properties.
  const MassProperties clockwise = polygon_mass_properties({{1.0, 2.0}, {1.0, 2.3}, {1.4, 2.3}, {1.4, 2.0}}, rho);
  CHECK(clockwise.mass == Approx(m_box).epsilon(1e-12));
  CHECK(clockwise.inertia == Approx(box.inertia).epsilon(1e-12));
  const double a = 0.6, b = 0.3;
  const MassProperties triangle = polygon_mass_properties({{0.0, 0.0}, {a, 0.0}, {0.0, b}}, rho);
  const double m_triangle = rho * a * b / 2.0;
  CHECK(triangle.mass == Approx(m_triangle).epsilon(1e-12));
  CHECK(triangle.centroid.x() == Approx(a / 3.0).epsilon(1e-12));
  CHECK(triangle.centroid.y() == Approx(b / 3.0).epsilon(1e-12));
  CHECK(triangle.inertia == Approx(m_triangle * (a * a + b * b) / 18.0).epsilon(1e-12));
  const MassProperties disc = circle_mass_properties(Vec2(0.3, 0.4), 0.1, rho);
  CHECK(disc.mass == Approx(rho * kPi * 0.01).epsilon(1e-12));
  CHECK(disc.inertia == Approx(0.5 * disc.mass * 0.01).epsilon(1e-12));
  // The circle's wall polygon: max(16, ceil(2 pi r / l0)) sides; the 32-gon of r = 0.1 m at
  // l0 = 0.02 m has 2.6 % less area than the disc (1 - sin(2 pi/n) n / (2 pi)): why the body's
  // mass and contact use the exact circle.
  CHECK(circle_sides(0.1, 0.02) == 32);
  CHECK(circle_sides(0.01, 0.02) == 16);
  const MassProperties polygon = polygon_mass_properties(circle_polygon(Vec2(0.3, 0.4), 0.1, 32), rho);
  CHECK(polygon.area == Approx(0.5 * 32 * 0.01 * std::sin(2.0 * kPi / 32)).epsilon(1e-12));
  CHECK((polygon.centroid - Vec2(0.3, 0.4)).norm() < 1e-12);
}

TEST_CASE("bodies: a box body's mass is that of its surface - the box grown by l0/2", "[bodies]") {
  // A box obstacle's wall surface is the box grown by l0/2 (core/walls/wall_geometry.hpp):
  // [0.5, 0.7] x [0.6, 0.7] at l0 = 0.02 is 0.22 x 0.12 m.
  const Scene scene = load("disc_on_slope.json", {"walls.obstacles=[{\"min\": [0.5, 0.6], \"max\": [0.7, 0.7], "
                                                  "\"body\": {\"density\": 500}}]"});
  const RigidBodies bodies(scene);
  REQUIRE(bodies.size() == 1);
  CHECK(bodies.mass(0).mass == Approx(500.0 * 0.22 * 0.12).epsilon(1e-12));
  CHECK(bodies.mass(0).inertia == Approx(500.0 * 0.22 * 0.12 * (0.22 * 0.22 + 0.12 * 0.12) / 12.0).epsilon(1e-12));
  CHECK((bodies.state(0).position - Vec2(0.6, 0.65)).norm() < 1e-12);
}

TEST_CASE("bodies: bad body input is a one-line error naming the file and the key", "[bodies][input]") {
  const auto check = [](const std::string& message, const std::string& key, const std::string& what) {
    INFO(message);
    CHECK(message.find("disc_on_slope.json") != std::string::npos);
    CHECK(message.find(key) != std::string::npos);
    CHECK(message.find(what) != std::string::npos);
    CHECK(message.find('\n') == std::string::npos);
  };
  const std::string circle = R"({"circle": {"centre": [0.5, 0.8], "radius": 0.1}, )";
  check(obstacle_error("[" + circle + R"("body": {"density": 0}}])"), "walls.obstacles[0].body.density", "0");
  check(obstacle_error("[" + circle + R"("body": {"density": -5}}])"), "walls.obstacles[0].body.density", "-5");
  check(obstacle_error(R"([{"circle": {"centre": [0.5, 0.8], "radius": 0}}])"), "walls.obstacles[0].circle.radius",
        "0");
  check(obstacle_error(R"([{"circle": {"centre": [0.5, 0.95], "radius": 0.1}, "body": {"density": 900}}])"),
        "walls.obstacles[0].circle", "inside the domain");
  check(obstacle_error(R"([{"polygon": [[1.9, 0.5], [2.1, 0.5], [2.0, 0.7]], "body": {"density": 900}}])"),
        "walls.obstacles[0].polygon", "inside the domain");
  check(obstacle_error(R"([{"min": [1.9, 0.5], "max": [2.2, 0.6], "body": {"density": 900}}])"),
        "walls.obstacles[0].max", "inside the domain");
  check(obstacle_error("[" + circle +
                       R"("body": {"density": 900}, "motion": {"law": "constant_velocity", "velocity": [1, 0]}}])"),
        "walls.obstacles[0].body", "motion");
  check(obstacle_error("[" + circle + R"("body": {"density": 900, "mass": 3}}])"), "walls.obstacles[0].body.mass", "");
  check(scene_error("disc_on_slope.json", {"contact.stiffness=0"}), "contact.stiffness", "0");
  check(scene_error("disc_on_slope.json", {"contact.friction=-0.1"}), "contact.friction", "-0.1");
}

TEST_CASE("disc on a slope: slides below and rolls above mu_c = tan(theta)/3 - accelerations within 1 percent",
          "[bodies][validation]") {
  // Theory (2-D disc, I = m r^2 / 2, slope angle theta = 20 deg, mu_c = tan(theta) / 3 = 0.121):
  // sliding a = g (sin theta - mu cos theta), omega r growing slower than u; rolling
  // a = (2/3) g sin theta, omega = -u / r (clockwise). The 1 % of the issue: the contact's
  // normal oscillation has settled by 0.1 s (see run_disc), and symplectic Euler integrates a
  // constant force exactly up to an O(dt) offset of the velocity, which the fit's linear term absorbs.
  const double g = 9.81;
  const SlopeRun sliding = run_disc(0.06);
  const double theta = sliding.theta;
  REQUIRE(std::tan(theta) / 3.0 == Approx(0.1213).epsilon(1e-3));
  const double a_sliding = g * (std::sin(theta) - 0.06 * std::cos(theta));
  INFO("sliding: fitted a = " << sliding.acceleration << " m/s^2, theory " << a_sliding << "; slip "
                              << sliding.slip_start << " -> " << sliding.slip_end << " m/s");
  CHECK(sliding.acceleration == Approx(a_sliding).epsilon(0.01));
  // Sliding: the slip u - omega r grows (theory: d(slip)/dt = g (sin - 3 mu cos) = 1.69 m/s^2,
  // 0.84 m/s over the 0.5 s of the fit); at least half of it.
  CHECK(sliding.slip_end - sliding.slip_start > 0.42);

  for (const double mu : {0.2, 0.5}) {
    const SlopeRun rolling = run_disc(mu);
    const double a_rolling = 2.0 / 3.0 * g * std::sin(theta);
    INFO("mu = " << mu << ": fitted a = " << rolling.acceleration << " m/s^2, theory " << a_rolling
                 << "; u = " << rolling.speed << " m/s, omega r = " << rolling.omega * rolling.radius << " m/s");
    CHECK(rolling.acceleration == Approx(a_rolling).epsilon(0.01));
    CHECK(-rolling.omega * rolling.radius == Approx(rolling.speed).epsilon(0.01));
  }
  // The rolling deviation (-0.19 %) is the overlap delta = m g cos(theta) / k_n: the disc rolls
  // about a point r - delta from its centre, a = g sin / (1 + I / (m (r - delta)^2)). Ten times
  // stiffer (5 sub-steps per fluid step: T_c = 2 pi sqrt((m/3) / k_n) = 2.0 ms over 20), the
  // deviation is ten times smaller: 0.019 % predicted, asserted below 0.05 %.
  const SlopeRun stiff = run_disc(0.5, 1.0e7);
  const Scene stiff_scene = load("disc_on_slope.json", {"contact.stiffness=1e8"});
  CHECK(RigidBodies(stiff_scene).sub_steps(5e-4) == 5);  // k_n = 1e8: h_c = 2 pi sqrt(10.47 / 1e8) / 20 = 0.10 ms
  const double delta = 1000.0 * kPi * 0.01 * g * std::cos(theta) / 1.0e7;
  const double predicted = g * std::sin(theta) / (1.0 + 0.5 * 0.01 / ((0.1 - delta) * (0.1 - delta)));
  INFO("k_n = 1e7: fitted a = " << stiff.acceleration << " m/s^2, predicted " << predicted);
  CHECK(stiff.acceleration == Approx(2.0 / 3.0 * g * std::sin(theta)).epsilon(5e-4));
  CHECK(stiff.acceleration == Approx(predicted).epsilon(1e-4));
}

TEST_CASE("bodies in the driver: the disc's wall particles follow its pose and equal the bodies alone",
          "[bodies][moving]") {
  // With a zero fluid load the driver's bodies are the bodies alone advanced by the same steps:
  // the same bits. The disc's wall particles move rigidly: each keeps its distance to the centre
  // (1e-12 m: rounding of O(1) positions) and moves with u_c + omega x r.
  const Scene scene = load("disc_on_slope.json", {"time.end_time=0.05"});
  const MethodInfo* mps = registries().methods.find("mps");
  if (mps == nullptr) return;
  Simulation simulation(scene, *mps);
  RigidBodies alone(scene);
  REQUIRE(simulation.bodies().size() == 1);
  std::vector<std::size_t> disc;
  std::vector<double> arm;
  const Vec2 centre0 = simulation.bodies().state(0).position;
  const ParticleSet& particles = simulation.particles();
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] == ParticleType::Wall && (particles.position[i] - centre0).norm() < 0.1) {
      disc.push_back(particles.id[i]);
      arm.push_back((particles.position[i] - centre0).norm());
    }
  }
  // 3 layers of the 32-gon: 32 + about 27 + 22 points.
  CHECK(disc.size() > 60);
  const ObstacleLoads no_fluid;
  while (simulation.time() < 0.05 - 1e-9) {
    simulation.advance();
    alone.advance(simulation.last_time_step(), no_fluid);
  }
  const BodyState& s = simulation.bodies().state(0);
  CHECK(s.position == alone.state(0).position);
  CHECK(s.velocity == alone.state(0).velocity);
  CHECK(s.angular_velocity == alone.state(0).angular_velocity);
  CHECK(s.position.y() < centre0.y() - 1e-3);  // it moved: (2/3) g sin(theta) t^2 / 2 = 2.8 mm down the slope
  // The wall particles were placed at the start of the last step with the pose before it,
  // x^n = x^{n+1} - dt u^{n+1} (symplectic Euler).
  const ParticleSet& now = simulation.particles();
  std::vector<std::size_t> index_of(now.size());
  for (std::size_t i = 0; i < now.size(); ++i) index_of[now.id[i]] = i;
  double worst_arm = 0.0;
  const Vec2 c = s.position - simulation.last_time_step() * s.velocity;  // x^n = x^{n+1} - dt u^{n+1}
  for (std::size_t m = 0; m < disc.size(); ++m) {
    const std::size_t i = index_of[disc[m]];
    const Vec2 r = now.position[i] - c;
    worst_arm = std::max(worst_arm, std::fabs(r.norm() - arm[m]));
  }
  CHECK(worst_arm < 1e-12);
}

TEST_CASE("a scene without fluid: every method that moves walls runs the disc alone - the bodies' bits",
          "[bodies][moving]") {
  // scenes/disc_on_slope.json has no fluid (fluid_blocks []): with every method that moves
  // walls, the run completes, has no fluid particle, and its disc is the bodies alone advanced by
  // the same steps, to the bit (no load). A scene without fluid and without a body is an input
  // error (tests/test_scene_geometry.cpp).
  const Scene scene = load("disc_on_slope.json", {"time.end_time=0.02"});
  int runs = 0;
  for (const MethodInfo* method : registries().methods.all()) {
    if (!method->moving_walls) continue;
    Simulation simulation(scene, *method);
    RigidBodies alone(scene);
    const ObstacleLoads no_fluid;
    while (simulation.time() < 0.02 - 1e-9) {
      simulation.advance();
      alone.advance(simulation.last_time_step(), no_fluid);
    }
    INFO(method->name);
    CHECK(simulation.particles().count(ParticleType::Fluid) == 0);
    CHECK(simulation.bodies().state(0).position == alone.state(0).position);
    CHECK(simulation.bodies().state(0).angular_velocity == alone.state(0).angular_velocity);
    // Rolling (mu = 0.3 > mu_c): (2/3) g sin(20 deg) t = 0.0447 m/s at 0.02 s; 5 % for the contact
    // still settling (period 35 ms; the 1 % check is the fitted acceleration over [0.1, 0.6] s).
    CHECK(simulation.bodies().state(0).velocity.norm() ==
          Approx(2.0 / 3.0 * 9.81 * std::sin(20.0 * kPi / 180.0) * 0.02).epsilon(0.05));
    ++runs;
  }
  CHECK(runs >= 1);
}

TEST_CASE("bodies: interrupted and resumed = uninterrupted with a rolling disc - bit for bit", "[bodies][checkpoint]") {
  // The body's state and its contact springs are in the checkpoint: series (body columns
  // included) and frames must be the same bytes. 0.05 s = 100 steps of mps, stopped at 43.
  if (registries().methods.find("mps") == nullptr) return;
  const auto full_dir = fresh_directory("bodies_resume_full");
  const auto part_dir = fresh_directory("bodies_resume_part");
  const auto run = [&](const fs::path& folder, long long stop_after) {
    RunOptions options;
    options.scene_path = scene_path("disc_on_slope.json");
    options.method = "mps";
    options.output_directory = folder.string();
    options.end_time = 0.05;
    options.overrides = {"output.frame_every_steps=20"};
    auto polls = std::make_shared<long long>(0);
    if (stop_after > 0) options.stop_reason = [polls, stop_after] { return ++*polls >= stop_after ? "a test" : ""; };
    return run_simulation(options, registries().methods, registries().walls);
  };
  const RunResult full = run(full_dir, 0);
  REQUIRE(full.status == "completed");
  REQUIRE(run(part_dir, 43).status == "interrupted");
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
  const std::string header = read_text(full_dir / "series.csv").substr(0, 2000);
  for (const char* column : {"body_1_x", "body_1_y", "body_1_theta", "body_1_u", "body_1_v", "body_1_omega",
                             "body_1_fx", "body_1_fy", "body_1_torque"}) {
    CHECK(header.find(column) != std::string::npos);
  }
}

TEST_CASE("moving walls: a polygon moved by a law - its wall particles at x_b0 + d(t) to the bit", "[bodies][moving]") {
  // A law's pose has theta = 0, so MovingWalls gives x_b0 + d(t) exactly (core/walls/moving_walls.hpp),
  // for a polygon as for a box. The triangle moves at 0.2 m/s to the right; 20 steps of mps.
  const Scene scene =
      load("disc_on_slope.json", {kSmallPool,
                                  "walls.obstacles=[{\"polygon\": [[0.8, 0.4], [1.0, 0.4], [0.9, 0.6]], "
                                  "\"motion\": {\"law\": \"constant_velocity\", \"velocity\": [0.2, "
                                  "0]}}]"});
  const MethodInfo* mps = registries().methods.find("mps");
  if (mps == nullptr) return;
  Simulation simulation(scene, *mps);
  const ParticleSet initial = simulation.particles();
  std::size_t moved = 0;
  for (int step = 0; step < 20; ++step) simulation.advance();
  const ParticleSet& now = simulation.particles();
  const Vec2 d = scene.walls.motions[0].displacement(simulation.time());
  CHECK(d.x() == Approx(0.2 * simulation.time()).epsilon(1e-12));
  for (std::size_t i = 0; i < now.size(); ++i) {
    const std::size_t first = now.id[i];
    const Vec2& x0 = initial.position[first];
    if (initial.type[first] != ParticleType::Wall || !inside_polygon(x0, scene.walls.polygons[0])) continue;
    ++moved;
    CHECK(now.position[i] == x0 + d);
    CHECK(now.wall_velocity[i] == Vec2(0.2, 0.0));
  }
  CHECK(moved > 20);  // 3 layers inside a triangle 0.2 m wide at l0 = 0.02: about 30 points
}

TEST_CASE("contact: two equal discs collide head-on without damping - velocities exchanged", "[bodies][contact]") {
  // Elastic central collision of equal masses (zeta = 0, mu = 0, no gravity): the velocities
  // exchange. The linear spring's impulse is exact up to symplectic Euler's O(h) energy error:
  // the contact lasts pi sqrt(m_eff / k) = 12.4 ms = 25 steps of 0.5 ms; 1 % on the speeds.
  // Momentum is exchanged pairwise (equal and opposite forces): its sum stays 0 to rounding.
  const Scene scene =
      load("disc_on_slope.json", {"walls.obstacles=[{\"circle\": {\"centre\": [0.8, 0.8], \"radius\": 0.1}, \"body\": "
                                  "{\"density\": 500, \"velocity\": [1, 0]}}, {\"circle\": {\"centre\": [1.2, 0.8], "
                                  "\"radius\": 0.1}, \"body\": {\"density\": 500, \"velocity\": [-1, 0]}}]",
                                  "physics.gravity=[0, 0]", "contact.damping_ratio=0", "contact.friction=0"});
  RigidBodies bodies(scene);
  REQUIRE(bodies.size() == 2);
  const ObstacleLoads no_fluid;
  for (int step = 0; step < 600; ++step) bodies.advance(5e-4, no_fluid);  // 0.3 s: met at 0.1 s
  CHECK(bodies.state(0).velocity.x() == Approx(-1.0).epsilon(0.01));
  CHECK(bodies.state(1).velocity.x() == Approx(1.0).epsilon(0.01));
  CHECK(std::fabs(bodies.state(0).velocity.x() + bodies.state(1).velocity.x()) < 1e-12);
  CHECK(std::fabs(bodies.state(0).velocity.y()) < 1e-12);
  CHECK(std::fabs(bodies.state(0).angular_velocity) < 1e-12);  // central: no torque
}

TEST_CASE("contact: a box body dropped on the bed comes to rest on two corner springs", "[bodies][contact]") {
  // The box's surface (0.22 x 0.12 m, density 500: m = 13.2 kg/m) falls 0.18 m onto the bed's
  // surface y = 0.01 m and settles on its two lower corners (polygon vertex against a segment):
  // each carries m g / 2, so the overlap is m g / (2 k_n) = 64.7 um. The two-spring system has
  // zeta_eff = sqrt(2) 0.3 = 0.42 and a period of 16 ms: 1 s leaves it at rest (1e-6 m/s).
  const Scene scene =
      load("disc_on_slope.json",
           {"walls.obstacles=[{\"min\": [0.8, 0.2], \"max\": [1.0, 0.3], \"body\": {\"density\": 500}}]"});
  RigidBodies bodies(scene);
  REQUIRE(bodies.size() == 1);
  const ObstacleLoads no_fluid;
  for (int step = 0; step < 2000; ++step) bodies.advance(5e-4, no_fluid);
  const BodyState& s = bodies.state(0);
  const double m = 500.0 * 0.22 * 0.12;
  const double overlap = m * 9.81 / (2.0 * scene.contact.stiffness);
  INFO("centre " << s.position.transpose() << " velocity " << s.velocity.transpose() << " angle " << s.angle);
  CHECK(s.velocity.norm() < 1e-6);
  CHECK(std::fabs(s.angle) < 1e-9);  // symmetric: no rocking
  CHECK(0.01 + 0.06 - s.position.y() == Approx(overlap).epsilon(0.01));
  CHECK(s.position.x() == Approx(0.9).epsilon(1e-9));
}

TEST_CASE("contact: the fixed walls' convex vertices - a wedge's apex and the open tank's rims only",
          "[bodies][contact]") {
  // The disc scene's tank (bottom, left and right sides, open top at 1.0 m; surfaces 0.01 m
  // inside the domain) with a triangle standing on the bed, apex (0.9, 0.3). Convex: the apex
  // and the two rims (x = 0.01 and 1.99 at the open top). Concave: the tank's lower corners and
  // the triangle's base corners on the bed (more than half of the solid around them).
  const Scene scene = load("disc_on_slope.json",
                           {kSmallPool, "walls.obstacles=[{\"polygon\": [[0.8, 0.01], [1.0, 0.01], [0.9, 0.3]]}]"});
  std::vector<Vec2> apexes = convex_wall_vertices(WallGeometry(scene), scene.particle_spacing);
  std::sort(apexes.begin(), apexes.end(), [](const Vec2& p, const Vec2& q) { return p.x() < q.x(); });
  REQUIRE(apexes.size() == 3);
  CHECK(apexes[0].isApprox(Vec2(0.01, 1.0)));
  CHECK(apexes[1].isApprox(Vec2(0.9, 0.3)));
  CHECK(apexes[2].isApprox(Vec2(1.99, 1.0)));
}

TEST_CASE("contact: a box body dropped on a wedge's apex rests on it - one spring under its centre",
          "[bodies][contact]") {
  // The box of the case above (surface 0.22 x 0.12 m, m = 13.2 kg/m, centre (0.9, 0.45)) falls
  // 0.09 m onto the apex (0.9, 0.3) of a fixed triangle. No vertex of the box meets a wall: only
  // the apex inside its bottom face holds it, a single spring under the centre (no torque), so
  // it rests with its bottom face m g / k_n = 129.5 um below the apex. (Without the apex as a
  // contact partner the box falls through the wedge to the bed.) One spring: period 23 ms, zeta
  // 0.3; 1 s leaves it at rest.
  const Scene scene =
      load("disc_on_slope.json", {"walls.obstacles=[{\"polygon\": [[0.8, 0.01], [1.0, 0.01], [0.9, 0.3]]}, "
                                  "{\"min\": [0.8, 0.4], \"max\": [1.0, 0.5], \"body\": {\"density\": 500}}]"});
  RigidBodies bodies(scene);
  REQUIRE(bodies.size() == 1);
  const ObstacleLoads no_fluid;
  for (int step = 0; step < 2000; ++step) bodies.advance(5e-4, no_fluid);
  const BodyState& s = bodies.state(0);
  const double overlap = 500.0 * 0.22 * 0.12 * 9.81 / scene.contact.stiffness;
  INFO("centre " << s.position.transpose() << " velocity " << s.velocity.transpose() << " angle " << s.angle);
  CHECK(s.velocity.norm() < 1e-6);
  CHECK(std::fabs(s.angle) < 1e-9);
  CHECK(0.3 + 0.06 - s.position.y() == Approx(overlap).epsilon(0.01));
  CHECK(s.position.x() == Approx(0.9).epsilon(1e-9));
}

TEST_CASE("contact: a paddle moved by its law pushes a box body along the bed at the paddle's speed",
          "[bodies][contact][moving]") {
  // A paddle (surface x 0.19 .. 0.27 m, y 0.03 .. 0.21 m: 2 cm above the bed) moved by
  // constant_velocity 0.2 m/s, and the box body of the cases above (surface 0.39 .. 0.61 m on
  // the bed, m = 13.2 kg/m, friction 0.3 with the bed). The paddle is a contact partner of
  // infinite mass: it reaches the box at t = 0.12 / 0.2 = 0.6 s and pushes it against the bed's
  // Coulomb friction, mu m g = 38.8 N/m, on two springs (its corner in the box's face, the box's
  // corner in its face) compressed by mu m g / (2 k_n) = 19 um. Before: the box rests. After
  // 0.9 s of pushing (the contact's period 23 ms, zeta 0.3): it moves at the paddle's speed, its
  // face within 0.1 mm of the paddle's. Without the paddle as a partner it would pass through.
  const Scene scene =
      load("disc_on_slope.json", {"walls.obstacles=[{\"min\": [0.2, 0.04], \"max\": [0.26, 0.2], \"motion\": "
                                  "{\"law\": \"constant_velocity\", \"velocity\": [0.2, 0.0]}}, "
                                  "{\"min\": [0.4, 0.02], \"max\": [0.6, 0.12], \"body\": {\"density\": 500}}]"});
  RigidBodies bodies(scene);
  REQUIRE(bodies.size() == 1);
  const ObstacleLoads no_fluid;
  const double dt = 5e-4;
  for (int step = 0; step < 1000; ++step) bodies.advance(dt, no_fluid);  // to 0.5 s
  CHECK(bodies.state(0).velocity.norm() < 1e-6);
  CHECK(bodies.state(0).position.x() == Approx(0.5).epsilon(1e-9));
  for (int step = 1000; step < 3000; ++step) bodies.advance(dt, no_fluid);  // to 1.5 s
  const BodyState& s = bodies.state(0);
  const double paddle_face = 0.27 + 0.2 * 1.5;  // m
  INFO("centre " << s.position.transpose() << " velocity " << s.velocity.transpose() << " angle " << s.angle);
  CHECK(s.velocity.x() == Approx(0.2).epsilon(1e-3));
  CHECK(std::fabs(s.velocity.y()) < 1e-4);
  const double gap = s.position.x() - 0.11 - paddle_face;  // the box's face behind the paddle's: < 0
  CHECK(gap < 0.0);
  CHECK(gap > -1e-4);
}

TEST_CASE("moving walls: a rotating pose moves a body's wall particles rigidly - x u and a by hand",
          "[bodies][moving]") {
  // MovingWalls with a pose (d, theta, u_c, omega, a_c, alpha): each member of the box body at
  // x_c + R(theta) r0, with u_c + omega x r and a_c + alpha x r - omega^2 r (core/walls/moving_walls.hpp).
  // 1e-12 m: rounding of O(1) numbers.
  const Scene scene =
      load("disc_on_slope.json",
           {"walls.obstacles=[{\"min\": [0.8, 0.4], \"max\": [1.0, 0.5], \"body\": {\"density\": 500}}]"});
  ParticleSet particles = build_particles(scene, true);
  const ParticleSet initial = particles;
  const MovingWalls walls(scene, particles);
  const Vec2 c0 = obstacle_rest_centroid(scene, 0);
  CHECK((c0 - Vec2(0.9, 0.45)).norm() < 1e-12);
  std::vector<RigidPose> poses(1);
  RigidPose& pose = poses[0];
  pose.displacement = Vec2(0.05, -0.02);
  pose.angle = 0.3;
  pose.velocity = Vec2(0.4, 0.1);
  pose.angular_velocity = -1.5;
  pose.acceleration = Vec2(0.0, -2.0);
  pose.angular_acceleration = 3.0;
  walls.apply(particles, poses);
  std::size_t members = 0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const Vec2& x0 = initial.position[i];
    const bool in_box = x0.x() > 0.79 && x0.x() < 1.01 && x0.y() > 0.39 && x0.y() < 0.51;
    if (initial.type[i] != ParticleType::Wall || !in_box) continue;
    ++members;
    const Vec2 r0 = x0 - c0;
    const Vec2 r(std::cos(0.3) * r0.x() - std::sin(0.3) * r0.y(), std::sin(0.3) * r0.x() + std::cos(0.3) * r0.y());
    CHECK((particles.position[i] - (c0 + pose.displacement + r)).norm() < 1e-12);
    CHECK((particles.wall_velocity[i] - (pose.velocity - 1.5 * Vec2(-r.y(), r.x()))).norm() < 1e-12);
    CHECK((particles.wall_acceleration[i] - (pose.acceleration + 3.0 * Vec2(-r.y(), r.x()) - 2.25 * r)).norm() < 1e-12);
  }
  CHECK(members == walls.count(0));
  CHECK(members == 11 * 6);  // the box's lattice points: 11 x 6, all within 3 layers of its sides
}

TEST_CASE("contact: a disc dropped on a box body on the bed - the stack comes to rest on its springs",
          "[bodies][contact]") {
  // Circle-polygon between bodies and polygon-segment with the bed: the disc (m_d = 500 pi 0.01
  // = 15.7 kg/m) on the box's top face (m_b = 13.2 kg/m) carries m_d g on one spring, the box
  // (m_b + m_d) g on its two lower corners. Overlaps m_d g / k_n = 154 um and (m_b + m_d) g /
  // (2 k_n) = 142 um; 1 % (the stack is at rest after 2 s: its slowest mode has a period of
  // 2 pi sqrt(m / k) ~ 25 ms and zeta >= 0.3).
  const Scene scene =
      load("disc_on_slope.json", {"walls.obstacles=[{\"min\": [0.8, 0.2], \"max\": [1.0, 0.3], \"body\": "
                                  "{\"density\": 500}}, {\"circle\": {\"centre\": [0.9, 0.5], "
                                  "\"radius\": 0.1}, \"body\": {\"density\": 500}}]"});
  RigidBodies bodies(scene);
  REQUIRE(bodies.size() == 2);
  const ObstacleLoads no_fluid;
  for (int step = 0; step < 4000; ++step) bodies.advance(5e-4, no_fluid);
  const double g = 9.81, k = scene.contact.stiffness;
  const double m_b = 500.0 * 0.22 * 0.12, m_d = 500.0 * kPi * 0.01;
  const BodyState &box = bodies.state(0), &disc = bodies.state(1);
  INFO("box " << box.position.transpose() << " disc " << disc.position.transpose());
  CHECK(box.velocity.norm() < 1e-6);
  CHECK(disc.velocity.norm() < 1e-6);
  CHECK(0.07 - box.position.y() == Approx((m_b + m_d) * g / (2.0 * k)).epsilon(0.01));
  CHECK(box.position.y() + 0.06 + 0.1 - disc.position.y() == Approx(m_d * g / k).epsilon(0.01));
  CHECK(disc.position.x() == Approx(0.9).epsilon(1e-9));
}

TEST_CASE("two-way coupling: a half-density box floats at its draft and a denser one sinks", "[bodies][coupling]") {
  // scenes/floating_box.json starts the box at its equilibrium draft rho_b / rho_w h = 0.0625 m,
  // centre at the fluid block's top y = 0.3 m; the water's level at rest is 0.2908 m (docs/bodies.md:
  // (W - l0)(eta - l0/2) = N l0^2 + B d; tests/test_floating_bodies.cpp asserts the draft against
  // the rest level). Every method that moves walls and reports the loads of its
  // default boundary model (the capabilities a body needs). Afloat, the mean centre over 0.5-1.5 s
  // stays within 0.02 m of 0.3 (0.8 l0: a free surface of particles is resolved to about l0/2;
  // measured: dfsph 0.289, isph 0.288, mps 0.284 with its
  // default obstacle_load wall_pressure; with pair_reaction mps sinks to the bed). With no fluid load the box would
  // fall to the bed. A box of 4x the density (net weight 3/4 of its weight) sinks by more than its own height (0.125 m)
  // in 1.5 s: its centre ends below 0.15 m (measured: dfsph 0.098 m, isph 0.075, mps 0.085: still settling onto the bed
  // through the water under it).
  int methods = 0;
  for (const MethodInfo* method : registries().methods.all()) {
    if (!method->moving_walls || !method->obstacle_loads) continue;
    if (!reports_obstacle_loads(load("floating_box.json", {"method=" + method->name}), *method)) continue;
    auto mean_height = [&](double density, double* last) {
      const Scene scene = load("floating_box.json",
                               {"method=" + method->name, "walls.obstacles.0.body.density=" + std::to_string(density)});
      Simulation simulation(scene, *method);
      REQUIRE(simulation.reports_obstacle_loads());
      double sum = 0.0;
      long count = 0;
      while (simulation.time() < 1.5 - 1e-9) {
        simulation.advance();
        if (simulation.time() >= 0.5) {
          sum += simulation.bodies().state(0).position.y();
          ++count;
        }
      }
      *last = simulation.bodies().state(0).position.y();
      return sum / static_cast<double>(count);
    };
    double last = 0.0;
    const double afloat = mean_height(500.0, &last);
    INFO(method->name << ": mean centre height afloat " << afloat << " m");
    CHECK(std::fabs(afloat - 0.3) < 0.02);
    mean_height(2000.0, &last);
    INFO(method->name << ": final centre height of the dense box " << last << " m");
    CHECK(last < 0.15);
    ++methods;
  }
  CHECK(methods >= 1);
}

TEST_CASE("two-way coupling with wall samples: the half-density box floats at its level with every such model",
          "[bodies][coupling]") {
  // scenes/floating_box.json with each boundary model of wall samples (no wall particles: the load is
  // the reaction of the method's sample pairs, or for mps the fluid's pressure over the box's surface;
  // docs/walls.md "Loads with wall samples"), for every method that moves walls and reports those
  // loads. The water's level at rest is 0.2908 m (the test above; the box's centre rests at the level,
  // its draft being half its height): the mean centre over 0.5-1.5 s within 0.02 m of it (0.8 l0, as
  // above). Measured: dfsph 0.290 / 0.296 / 0.294 m (dummy_layers / mirror_particles /
  // distance_function), isph 0.292 / 0.289 / 0.290, mps 0.295 / - / 0.299. mps with mirror particles
  // does not keep the water around a box at rest (docs/data/wall_study.md, the box rows): the
  // monitor stops it (a Courant number of 35 at 0.48 s), as it stops that pair in still water.
  const double rest_level = 0.2908;
  int runs = 0;
  for (const MethodInfo* method : registries().methods.all()) {
    if (!method->moving_walls || !method->sample_obstacle_loads) continue;
    for (const WallTreatmentInfo* model : registries().walls.all()) {
      if (model->role != WallTreatmentRole::Boundary || model->wall_particles) continue;
      if (!model->moving_walls || !wall_treatment_supports(*model, *method)) continue;
      const Scene scene =
          load("floating_box.json", boundary_model_overrides("floating_box.json", method->name, model->name));
      Simulation simulation(scene, *method);
      REQUIRE(simulation.reports_obstacle_loads());
      INFO(method->name << " x " << model->name);
      double sum = 0.0;
      long count = 0;
      const bool known_divergence = method->name == "mps" && model->name == "mirror_particles";
      try {
        while (simulation.time() < 1.5 - 1e-9) {
          simulation.advance();
          if (simulation.time() < 0.5) continue;
          sum += simulation.bodies().state(0).position.y();
          ++count;
        }
      } catch (const RunStopped& stopped) {
        INFO(stopped.what());
        CHECK(known_divergence);
        ++runs;
        continue;
      }
      CHECK_FALSE(known_divergence);  // it completes now: measure it and take it off the list
      const double mean = sum / static_cast<double>(count);
      INFO("mean centre " << mean << " m, the level at rest " << rest_level << " m");
      CHECK(std::fabs(mean - rest_level) < 0.02);
      ++runs;
    }
  }
  CHECK(runs >= 9);
}
