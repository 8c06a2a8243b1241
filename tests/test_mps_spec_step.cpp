// Spec §4, §5, §7 and §8 item by item: the lattice, each explicit and implicit sub-step of
// one mps step (seen by a recording wall treatment at the four hooks), the free-surface rule,
// the pressure Poisson equation and its solve, the wall layers that carry pressure, and the
// ghost rule. Hand-built sets of 2-20 particles unless the lattice itself is the subject.
#include <catch2/catch.hpp>

#include <limits>

#include "core/io/geometry.hpp"
#include "core/io/output.hpp"
#include "methods/mps/mps_pressure.hpp"
#include "test_mps_spec_support.hpp"

using namespace mps_lab;
using namespace mps_lab::mps;
using namespace mps_lab::spec_testing;

namespace {

const Vec2 kGravity(0.0, -9.81);  // m/s^2

// What the recording treatment saw at one hook.
struct Snapshot {
  std::string hook;
  std::vector<Vec2> position, velocity;
  std::vector<std::vector<std::uint32_t>> neighbours;  // by particle
};

// A measure that records the particles at every hook. It runs last at each hook (order 1000).
// At the search hook it also gives wall particle `disturbed` a velocity, as a measure acting
// on walls might, to see that the step fixes the walls again afterwards (spec §5.2-9).
class Recorder final : public WallTreatment {
 public:
  Recorder(std::vector<Snapshot>* log, long disturbed) : log_(log), disturbed_(disturbed) {}
  void after_explicit_velocity(WallContext& c) override { record("after_explicit_velocity", c); }
  void after_explicit_position(WallContext& c) override { record("after_explicit_position", c); }
  void after_neighbour_search(WallContext& c) override {
    record("after_neighbour_search", c);
    if (disturbed_ >= 0) c.particles.velocity[static_cast<std::size_t>(disturbed_)] = Vec2(1.0, 0.0);
  }
  void after_correction(WallContext& c) override { record("after_correction", c); }

 private:
  void record(const std::string& hook, const WallContext& c) {
    Snapshot s{hook, c.particles.position, c.particles.velocity, {}};
    if (c.neighbours != nullptr && c.neighbours->particle_count() == c.particles.size()) {
      for (std::size_t i = 0; i < c.particles.size(); ++i) {
        s.neighbours.emplace_back(c.neighbours->indices.begin() + c.neighbours->begin(i),
                                  c.neighbours->indices.begin() + c.neighbours->end(i));
      }
    }
    log_->push_back(std::move(s));
  }
  std::vector<Snapshot>* log_;
  long disturbed_;
};

struct RecordedRun {
  std::vector<Snapshot> log;
  WallTreatmentInfo info;
  std::unique_ptr<Method> method;
  StepReport report;
};

// One mps step of `particles` with the scene's treatments and the recorder.
void step_with_recorder(const Scene& scene, ParticleSet& particles, RecordedRun& run, long disturbed = -1) {
  run.info.name = "recorder";
  run.info.order = 1000;
  run.info.create = [&run, disturbed](const WallTreatmentSetup&) {
    return std::make_unique<Recorder>(&run.log, disturbed);
  };
  WallTreatmentChoice choice;
  choice.info = &run.info;
  choice.enabled = true;
  run.method = make_mps(scene, {choice});
  run.method->initialise(particles);
  run.report = run.method->step(particles, scene.time.time_step);
}

const Snapshot& at(const RecordedRun& run, const std::string& hook) {
  for (const auto& s : run.log) {
    if (s.hook == hook) return s;
  }
  FAIL("hook " << hook << " was not called");
  return run.log.front();
}

bool has_neighbour(const Snapshot& s, std::size_t i, std::uint32_t j) {
  return std::find(s.neighbours[i].begin(), s.neighbours[i].end(), j) != s.neighbours[i].end();
}

// A fluid particle at `centre` with its lattice neighbours inside re = 2.1 l0 at spacing
// `spacing`, leaving out the offsets listed in `skip`. Particle 0 is the centre.
ParticleSet cluster(const Vec2& centre, double spacing, const std::vector<std::pair<int, int>>& skip = {}) {
  ParticleSet particles = mps_particles();
  particles.add(centre, Vec2::Zero(), ParticleType::Fluid);
  for (int j = -2; j <= 2; ++j) {
    for (int i = -2; i <= 2; ++i) {
      if ((i == 0 && j == 0) || i * i + j * j > 4) continue;
      if (std::find(skip.begin(), skip.end(), std::make_pair(i, j)) != skip.end()) continue;
      particles.add(centre + spacing * Vec2(i, j), Vec2::Zero(), ParticleType::Fluid);
    }
  }
  return particles;
}

}  // namespace

TEST_CASE("spec 4: the dam-break lattice has 171 fluid and 273 wall particles and a first wall layer of 87",
          "[mps][spec][geometry]") {
  // Spec §4 note: fluid (i l0, j l0), i = 1..9, j = 1..19; walls 45 x 3 + 23 x 3 x 2 = 273.
  // Layer 1 (facing the fluid, spec §8 decision): the bottom row x = 0..1.0 (41) and the two
  // inner side columns y = l0..0.575 (23 each): 87.
  const Scene scene = defaults_scene();
  const ParticleSet particles = build_particles(scene);
  CHECK(particles.count(ParticleType::Fluid) == 171);
  CHECK(particles.count(ParticleType::Wall) == 273);
  std::size_t first_layer = 0;
  double fluid_max_x = 0.0, fluid_max_y = 0.0, wall_max_y = 0.0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] == ParticleType::Wall) {
      if (particles.wall_layer[i] == 1) ++first_layer;
      wall_max_y = std::max(wall_max_y, particles.position[i].y());
    } else {
      fluid_max_x = std::max(fluid_max_x, particles.position[i].x());
      fluid_max_y = std::max(fluid_max_y, particles.position[i].y());
    }
  }
  CHECK(first_layer == 87);
  CHECK(fluid_max_x == Approx(9 * kSpacing).epsilon(1e-12));
  CHECK(fluid_max_y == Approx(19 * kSpacing).epsilon(1e-12));
  CHECK(wall_max_y == Approx(0.575).epsilon(1e-12));
}

TEST_CASE(
    "spec 5.1: the explicit step is g plus viscosity then ux then the CFL hook then rx then walls fixed then the clamp "
    "hook",
    "[mps][spec]") {
  // nu = 0.01 m^2/s so that the viscous term is large enough to see (the default 1e-6 is
  // checked in the parameter table test). Particles far from the walls:
  //   0, 1: fluid l0 apart, u = (0.1, 0) and (-0.1, 0); each other's only neighbour.
  //   2, 3: fluid 2.25 l0 apart (not neighbours at t = 0), approaching at 5 m/s each: after
  //         the explicit step 2.25 l0 - 2 * 5 * dt = 2.05 l0 apart, inside re.
  //   4:    a wall particle given u = (1, 0), alone.
  const Scene scene = defaults_scene({"physics.kinematic_viscosity=0.01"});
  const double dt = scene.time.time_step, nu = 0.01;
  ParticleSet particles = mps_particles();
  particles.add(Vec2(0.5, 0.3), Vec2(0.1, 0.0), ParticleType::Fluid);
  particles.add(Vec2(0.5 + kSpacing, 0.3), Vec2(-0.1, 0.0), ParticleType::Fluid);
  particles.add(Vec2(0.2, 0.3), Vec2(5.0, 0.0), ParticleType::Fluid);
  particles.add(Vec2(0.2 + 2.25 * kSpacing, 0.3), Vec2(-5.0, 0.0), ParticleType::Fluid);
  particles.add(Vec2(0.8, 0.1), Vec2(1.0, 0.0), ParticleType::Wall, 1);
  const ParticleSet initial = particles;
  RecordedRun run;
  step_with_recorder(scene, particles, run, 4);

  // The four hooks, once each, in the order of spec §5.
  REQUIRE(run.log.size() == 4);
  CHECK(run.log[0].hook == "after_explicit_velocity");
  CHECK(run.log[1].hook == "after_explicit_position");
  CHECK(run.log[2].hook == "after_neighbour_search");
  CHECK(run.log[3].hook == "after_correction");

  // 5.1-1..3: u* = u + dt (g + nu (2d/(n0 lambda)) (u_1 - u_0) w(l0)), w(l0) = 1.1.
  const Snapshot& velocity = at(run, "after_explicit_velocity");
  const double laplacian = 4.0 / (hand_n0() * hand_lambda(kSpacing)) * (-0.2) * 1.1;  // 1/s^2 * m/s along x
  CHECK(velocity.velocity[0].x() == Approx(0.1 + dt * nu * laplacian).epsilon(1e-12));
  CHECK(velocity.velocity[0].y() == Approx(dt * kGravity.y()).epsilon(1e-12));
  CHECK(velocity.velocity[1].x() == Approx(-0.1 - dt * nu * laplacian).epsilon(1e-12));
  CHECK(velocity.velocity[2].x() == 5.0);  // no neighbour: gravity only
  CHECK(velocity.velocity[2].y() == Approx(dt * kGravity.y()).epsilon(1e-12));
  CHECK(velocity.position[0] == initial.position[0]);  // positions move after this hook

  // 5.1-5, 5.1-6: r* = r + dt u*; the wall particle's velocity is zero, its position kept.
  const Snapshot& position = at(run, "after_explicit_position");
  for (std::size_t i = 0; i < 4; ++i) {
    INFO("particle " << i);
    CHECK(position.position[i].x() == Approx(initial.position[i].x() + dt * velocity.velocity[i].x()).epsilon(1e-14));
    CHECK(position.position[i].y() == Approx(initial.position[i].y() + dt * velocity.velocity[i].y()).epsilon(1e-14));
  }
  CHECK(position.velocity[4] == Vec2::Zero());
  CHECK(position.position[4] == initial.position[4]);

  // 5.2-1: the search at r* finds 2 and 3, 2.05 l0 apart; the list of t = 0 did not have them.
  const Snapshot& search = at(run, "after_neighbour_search");
  CHECK(has_neighbour(search, 2, 3));
  CHECK(has_neighbour(search, 0, 1));
  // 5.2-4: n* at r*: particle 2 sees w(2.05 l0) = 2.1/2.05 - 1 = 0.0243902.
  const double r23 = (search.position[3] - search.position[2]).norm();
  CHECK(r23 == Approx(2.05 * kSpacing).epsilon(1e-9));
  CHECK(particles.field("number_density")[2] == Approx(2.1 * kSpacing / r23 - 1.0).epsilon(1e-12));
  CHECK(particles.field("number_density")[2] == Approx(0.0243902).epsilon(1e-5));

  // 5.2-9: the wall particle disturbed at the search hook is fixed again before the clamp hook.
  CHECK(at(run, "after_correction").velocity[4] == Vec2::Zero());
  CHECK(particles.velocity[4] == Vec2::Zero());
}

TEST_CASE("spec 5.2-8: the correction is u = ux + dt a_p and r = rx + dt^2 a_p with a_p the gradient model",
          "[mps][spec]") {
  // A compressed cluster: a centre and its 12 lattice neighbours within 2.1 spacings, at
  // 0.9 l0. n*_centre = 4 (2.1/0.9 - 1) + 4 (2.1/(0.9 sqrt 2) - 1) + 4 (2.1/1.8 - 1) = 8.600
  // > n0: the centre and its four nearest neighbours are unknowns with P > 0, the outer
  // particles are surface (n* < 0.97 n0). a_p is the gradient model (spec §2) at r* with the
  // solved pressures, which the test evaluates with the method's own operator.
  const Scene scene = defaults_scene();
  const double dt = scene.time.time_step;
  ParticleSet particles = cluster(Vec2(0.5, 0.3), 0.9 * kSpacing);
  RecordedRun run;
  step_with_recorder(scene, particles, run);
  CHECK(particles.pressure[0] > 1.0e3);  // Pa; the solved centre pressure (compressed)
  CHECK(run.report.extra.at(2) == 5.0);  // ppe_unknowns
  CHECK(run.report.extra.at(1) == 8.0);  // free_surface_particles

  // a_p from the gradient model at r* (positions and velocities the search hook saw).
  const Snapshot& search = at(run, "after_neighbour_search");
  ParticleSet at_search = particles;
  at_search.position = search.position;
  const OperatorRadius radius = make_operator_radius(kSpacing, 2.1 * kSpacing, 0.01 * kSpacing);
  const NeighbourList list = find_neighbours(at_search.position, at_search.type, radius.re);
  std::vector<Vec2> a_p(particles.size(), Vec2::Zero());
  pressure_acceleration(at_search, list, WallSampleList{}, radius, std::vector<char>(particles.size(), 1),
                        scene.physics.density, kGravity, true, a_p, DryWallRule{});
  double largest = 0.0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    INFO("particle " << i);
    largest = std::max(largest, a_p[i].norm());
    // Velocity changes by dt a_p (|a_p| up to ~1e3 m/s^2: tolerance 1e-9 m/s, round-off).
    CHECK((particles.velocity[i] - search.velocity[i] - dt * a_p[i]).norm() < 1e-9);
    // Position changes by dt^2 a_p (not dt u^{n+1}).
    CHECK((particles.position[i] - search.position[i] - dt * dt * a_p[i]).norm() < 1e-12);
  }
  CHECK(largest > 10.0);  // m/s^2: the correction is not trivially zero
  // The centre's neighbours are symmetric: it feels no net pressure force.
  CHECK(a_p[0].norm() < 1e-6 * largest);
}

TEST_CASE("spec 5.2-5 and 5.2-7: beta = 0.97 decides the surface and negative pressure is clamped", "[mps][spec]") {
  // The centre of a lattice cluster (spacing l0) without the two neighbours at (2, 0) and
  // (0, 2) has n* = n0 - 2 * 0.05 = 6.4397: n*/n0 = 0.98471, above beta = 0.97 (and below
  // 0.99), so it is an unknown; its source (n* - n0)/n0 < 0 gives a negative pressure, which
  // is clamped to 0. Every other particle has n*/n0 < 0.97: surface.
  const Scene scene = defaults_scene();
  ParticleSet particles = cluster(Vec2(0.5, 0.3), kSpacing, {{2, 0}, {0, 2}});
  RecordedRun run;
  step_with_recorder(scene, particles, run);
  CHECK(particles.field("number_density")[0] == Approx(hand_n0() - 0.1).epsilon(1e-9));
  CHECK(particles.field("free_surface")[0] == 0.0);
  for (std::size_t i = 1; i < particles.size(); ++i) CHECK(particles.field("free_surface")[i] == 1.0);
  CHECK(run.report.extra.at(2) == 1.0);  // one unknown
  CHECK(particles.pressure[0] == 0.0);   // solved negative, clamped
}

TEST_CASE("spec 8: the PPE rows are 2d/(n0 lambda) w_ij with source 0.2 rho/dt^2 (nx - n0)/n0",
          "[mps][spec][pressure]") {
  // Three particles in a row l0 apart with given n*: 0.9 n0 (surface, P = 0), 1.05 n0 and
  // exactly 0.97 n0 (not < beta: an unknown). With c = 2d/(n0 lambda) (hand values):
  // row of 1: A_11 = c (1.1 + 1.1), A_12 = -c 1.1; row of 2: A_22 = c (1.1 + 0.05), A_21 = -c 1.1;
  // b_1 = 0.2 (1000 / dt^2) 0.05, b_2 = 0.2 (1000 / dt^2) (0.97 - 1).
  ParticleSet particles;
  for (int k = 0; k < 3; ++k) particles.add(Vec2(0.5 + k * kSpacing, 0.3), Vec2::Zero(), ParticleType::Fluid);
  particles.pressure = {55.0, 0.0, 0.0};
  const OperatorRadius radius = make_operator_radius(kSpacing, 2.1 * kSpacing, 0.01 * kSpacing);
  const double n0 = radius.n0;
  const std::vector<double> n_star = {0.9 * n0, 1.05 * n0, 0.97 * n0};
  const NeighbourList list = find_neighbours(particles.position, particles.type, radius.re);
  PressureSolveSettings settings;
  settings.free_surface_threshold = 0.97;
  settings.relaxation = 0.2;
  PressurePoissonSolver solver;
  std::vector<double> surface;
  const PressureSolveResult result = solver.assemble(particles, list, WallSampleList{}, n_star, std::vector<char>(3, 1),
                                                     radius, n0, kTimeStep, settings, surface);
  CHECK(surface == std::vector<double>{1.0, 0.0, 0.0});
  CHECK(particles.pressure[0] == 0.0);  // surface: P = 0
  REQUIRE(result.unknowns == 2);
  const double c = 4.0 / (hand_n0() * hand_lambda(kSpacing));  // 1/m^2
  const auto A = solver.matrix();
  CHECK(A.coeff(0, 0) == Approx(c * 2.2).epsilon(1e-12));
  CHECK(A.coeff(0, 1) == Approx(-c * 1.1).epsilon(1e-12));
  CHECK(A.coeff(1, 1) == Approx(c * 1.15).epsilon(1e-12));
  CHECK(A.coeff(1, 0) == Approx(-c * 1.1).epsilon(1e-12));
  const double source = 0.2 * 1000.0 / (kTimeStep * kTimeStep);  // Pa/m^2 per unit (n* - n0)/n0
  CHECK(solver.rhs()[0] == Approx(source * 0.05).epsilon(1e-9));
  CHECK(solver.rhs()[1] == Approx(source * -0.03).epsilon(1e-9));
}

TEST_CASE("spec 8: CG reaches the relative residual 1e-8 and negative pressures are clamped", "[mps][spec][pressure]") {
  // A row of 20 particles l0 apart; particle 0 is surface (n* = 0.5 n0), the others
  // compressed by 1 % to 19 % (n* = (1 + 0.01 k) n0): b > 0 and A is an M-matrix, so P > 0.
  // Jacobi CG on 19 unknowns needs more than a handful of iterations, so a looser stopping
  // rule would show in the residual recomputed here from the assembled system.
  ParticleSet particles;
  for (int k = 0; k < 20; ++k) particles.add(Vec2(0.3 + k * kSpacing, 0.3), Vec2::Zero(), ParticleType::Fluid);
  const OperatorRadius radius = make_operator_radius(kSpacing, 2.1 * kSpacing, 0.01 * kSpacing);
  std::vector<double> n_star(20);
  for (int k = 0; k < 20; ++k) n_star[k] = k == 0 ? 0.5 * radius.n0 : (1.0 + 0.01 * k) * radius.n0;
  const NeighbourList list = find_neighbours(particles.position, particles.type, radius.re);
  PressureSolveSettings settings;  // tolerance 1e-8 relative (spec §3 note), Jacobi
  settings.warm_start = false;
  PressurePoissonSolver solver;
  std::vector<double> surface;
  const std::vector<char> carries(20, 1);
  const PressureSolveResult result =
      solver.solve(particles, list, WallSampleList{}, n_star, carries, radius, radius.n0, kTimeStep, settings, surface);
  REQUIRE(result.unknowns == 19);
  CHECK(result.converged);
  CHECK(result.iterations > 3);
  Eigen::VectorXd p(19);
  for (int k = 1; k < 20; ++k) p[k - 1] = particles.pressure[k];
  CHECK(p.minCoeff() > 0.0);
  const double relative = (solver.rhs() - solver.matrix() * p).norm() / solver.rhs().norm();
  CHECK(relative < 1e-8);
  // The stopping rule is the relative residual below the tolerance it is given: at 1e-2 ..
  // 1e-8 the residual recomputed here is below each (a looser rule stops early: at 1e-2 a
  // rule 1000x looser stops before the first iteration, with residual 1).
  for (double tolerance : {1e-2, 1e-4, 1e-6, 1e-8}) {
    INFO("tolerance " << tolerance);
    PressureSolveSettings loose = settings;
    loose.tolerance = tolerance;
    const PressureSolveResult solved =
        solver.solve(particles, list, WallSampleList{}, n_star, carries, radius, radius.n0, kTimeStep, loose, surface);
    for (int k = 1; k < 20; ++k) p[k - 1] = particles.pressure[k];
    const double residual = (solver.rhs() - solver.matrix() * p).norm() / solver.rhs().norm();
    CHECK(solved.iterations >= 1);
    CHECK(residual < tolerance);
  }

  // Expanded instead (n* = 0.98 n0): P < 0 everywhere; the solve clamps it to 0, and without
  // the clamp the pressures are negative (the clamp did act).
  for (int k = 1; k < 20; ++k) n_star[k] = 0.98 * radius.n0;
  solver.solve(particles, list, WallSampleList{}, n_star, carries, radius, radius.n0, kTimeStep, settings, surface);
  for (int k = 1; k < 20; ++k) CHECK(particles.pressure[k] == 0.0);
  settings.clamp_negative = false;
  solver.solve(particles, list, WallSampleList{}, n_star, carries, radius, radius.n0, kTimeStep, settings, surface);
  CHECK(particles.pressure[10] < 0.0);
}

TEST_CASE("spec 8: the first wall layer carries pressure and the outer layers do not", "[mps][spec]") {
  // One step of the spec's dam break from rest: every pressure carrier is an unknown or a
  // surface particle, so unknowns + surface = 171 fluid + 87 first-layer wall particles.
  const Scene scene = defaults_scene();
  ParticleSet particles = build_particles(scene);
  for (const auto& field : testing::registries().methods.find("mps")->fields) particles.add_field(field.name);
  auto method = make_mps(scene);
  method->initialise(particles);
  const StepReport report = method->step(particles, scene.time.time_step);
  CHECK(report.extra.at(1) + report.extra.at(2) == 171.0 + 87.0);
}

TEST_CASE("spec 7: a fluid particle beyond l0 (layers + 1) outside the domain or with a NaN coordinate becomes a ghost",
          "[mps][spec]") {
  // Margin 0.025 * (3 + 1) = 0.1 m: bounds x in [-0.1, 1.1], y in [-0.1, 0.7]; exactly on a
  // bound is still inside.
  const Scene scene = defaults_scene();
  CHECK(escape_margin(scene) == Approx(0.1).epsilon(1e-12));
  const double top = scene.domain.max.y() + escape_margin(scene);
  const double left = scene.domain.min.x() - escape_margin(scene);
  ParticleSet particles;
  particles.add(Vec2(0.5, top), Vec2(0.0, 1.0), ParticleType::Fluid);         // 0: on the bound
  particles.add(Vec2(0.5, top + 1e-6), Vec2(0.0, 1.0), ParticleType::Fluid);  // 1: beyond
  particles.add(Vec2(0.5, 0.69), Vec2(0.0, 1.0), ParticleType::Fluid);        // 2: inside the margin
  particles.add(Vec2(left - 1e-6, 0.3), Vec2::Zero(), ParticleType::Fluid);   // 3: beyond the left
  particles.add(Vec2(left + 1e-6, 0.3), Vec2::Zero(), ParticleType::Fluid);   // 4: inside
  particles.add(Vec2(0.5, std::numeric_limits<double>::quiet_NaN()), Vec2::Zero(), ParticleType::Fluid);  // 5
  particles.add(Vec2(0.5, 0.9), Vec2::Zero(), ParticleType::Wall, 1);  // 6: walls never
  CHECK(mark_escaped_as_ghosts(particles, scene) == 3);
  CHECK(particles.type[0] == ParticleType::Fluid);
  CHECK(particles.type[1] == ParticleType::Ghost);
  CHECK(particles.type[2] == ParticleType::Fluid);
  CHECK(particles.type[3] == ParticleType::Ghost);
  CHECK(particles.type[4] == ParticleType::Fluid);
  CHECK(particles.type[5] == ParticleType::Ghost);
  CHECK(particles.type[6] == ParticleType::Wall);

  // 5.2-11: the mps step applies it: a lone particle at y = 0.75 (beyond 0.7) is a ghost after
  // one step; one at 0.65 is not.
  ParticleSet lone = mps_particles();
  lone.add(Vec2(0.5, 0.75), Vec2::Zero(), ParticleType::Fluid);
  lone.add(Vec2(0.3, 0.65), Vec2::Zero(), ParticleType::Fluid);
  auto method = make_mps(scene);
  method->initialise(lone);
  method->step(lone, scene.time.time_step);
  CHECK(lone.type[0] == ParticleType::Ghost);
  CHECK(lone.type[1] == ParticleType::Fluid);
}

TEST_CASE("spec 3: dt is the scene's time.time_step, the same at rest and in fast flow", "[mps][spec]") {
  // The spec fixes dt (§3: 5.0e-4 s); a scene may set another. With the default rule ("fixed")
  // the method returns it whatever the flow: at rest, and with a fluid particle at 20 m/s, where
  // the optional CFL rule would shorten it to 0.16 l0 / 20 = 2e-4 s (and at rest would take its
  // upper bound, 5e-4 s, for the scene's 2.5e-4 s).
  for (const double dt : {kTimeStep, 2.5e-4}) {
    INFO("time.time_step = " << dt);
    const Scene scene = defaults_scene({"time.time_step=" + format_double(dt)});
    const std::unique_ptr<Method> method = make_mps(scene);
    ParticleSet particles = cluster(Vec2(0.5, 0.3), kSpacing);
    CHECK(method->time_step(particles) == dt);
    particles.velocity[0] = Vec2(20.0, 0.0);
    CHECK(method->time_step(particles) == dt);
  }
}
