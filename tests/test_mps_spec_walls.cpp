// Spec §6 item by item: the four wall-penetration measures as the mps method gets them (the
// scene's resolved choices, defaults, run through WallTreatmentSet at their hooks), on
// hand-built sets of 2-10 particles. dt = 5e-4 s, l0 = 0.025 m. Each expected value is derived
// in a comment; tolerances 1e-12 relative (a few roundings) unless stated.
#include <catch2/catch.hpp>

#include "test_mps_spec_support.hpp"

using namespace mps_lab;
using namespace mps_lab::spec_testing;

namespace {

// Runs `hook` of the scene's named treatments on `particles` with a fresh neighbour list.
enum class Hook { ExplicitVelocity, ExplicitPosition, NeighbourSearch, Correction };

void run_hook(const Scene& scene, const std::vector<std::string>& names, Hook hook, ParticleSet& particles) {
  WallTreatmentSet set = only_treatments(scene, names);
  const NeighbourList list = find_neighbours(particles.position, particles.type, 2.1 * kSpacing);
  WallContext context{particles, &list, kTimeStep, scene};
  switch (hook) {
    case Hook::ExplicitVelocity:
      set.after_explicit_velocity(context);
      break;
    case Hook::ExplicitPosition:
      set.after_explicit_position(context);
      break;
    case Hook::NeighbourSearch:
      set.after_neighbour_search(context);
      break;
    case Hook::Correction:
      set.after_correction(context);
      break;
  }
}

}  // namespace

TEST_CASE("spec 6.1: the CFL clamp caps |v| at 0.2 l0/dt and keeps the direction", "[mps][spec][walls]") {
  // v_max = 0.2 * 0.025 / 5e-4 = 10 m/s. (30, 40) has |v| = 50 -> (6, 8); (12, 16), |v| = 20,
  // -> (6, 8); (6, 8) has |v| = 10, not above v_max: unchanged; (3, -4) unchanged.
  const Scene scene = defaults_scene();
  ParticleSet particles;
  for (const Vec2& v : {Vec2(30.0, 40.0), Vec2(12.0, 16.0), Vec2(6.0, 8.0), Vec2(3.0, -4.0)}) {
    particles.add(Vec2(0.1 + 0.1 * static_cast<double>(particles.size()), 0.3), v, ParticleType::Fluid);
  }
  run_hook(scene, {"cfl_velocity_clamp"}, Hook::ExplicitVelocity, particles);
  CHECK(particles.velocity[0].x() == Approx(6.0).epsilon(1e-12));
  CHECK(particles.velocity[0].y() == Approx(8.0).epsilon(1e-12));
  CHECK(particles.velocity[1].x() == Approx(6.0).epsilon(1e-12));
  CHECK(particles.velocity[1].y() == Approx(8.0).epsilon(1e-12));
  CHECK(particles.velocity[2] == Vec2(6.0, 8.0));
  CHECK(particles.velocity[3] == Vec2(3.0, -4.0));
}

TEST_CASE("spec 6.2: wall repulsion pushes fluid closer than l0 by dt 196.2 (1 - r/l0)^2", "[mps][spec][walls]") {
  // C = 0.5 |g| / l0 = 0.5 * 9.81 / 0.025 = 196.2 m/s^2.
  const Scene scene = defaults_scene();
  ParticleSet particles;
  // 0, 1: wall and fluid 0.5 l0 apart: overlap 0.5, dv = dt C 0.25 = 0.024525 m/s along +x.
  particles.add(Vec2(0.2, 0.3), Vec2::Zero(), ParticleType::Wall, 1);
  particles.add(Vec2(0.2 + 0.5 * kSpacing, 0.3), Vec2::Zero(), ParticleType::Fluid);
  // 2, 3: wall and fluid 1.2 l0 apart: beyond l0, no push.
  particles.add(Vec2(0.5, 0.3), Vec2::Zero(), ParticleType::Wall, 1);
  particles.add(Vec2(0.5 + 1.2 * kSpacing, 0.3), Vec2::Zero(), ParticleType::Fluid);
  // 4, 5: two fluid particles 0.5 l0 apart at rest: fluid does not repel fluid.
  particles.add(Vec2(0.8, 0.3), Vec2::Zero(), ParticleType::Fluid);
  particles.add(Vec2(0.8 + 0.5 * kSpacing, 0.3), Vec2::Zero(), ParticleType::Fluid);
  // 6, 7: two wall particles 0.5 l0 apart: one-way, wall particles are never pushed.
  particles.add(Vec2(0.5, 0.1), Vec2::Zero(), ParticleType::Wall, 1);
  particles.add(Vec2(0.5 + 0.5 * kSpacing, 0.1), Vec2::Zero(), ParticleType::Wall, 1);
  run_hook(scene, {"wall_repulsion"}, Hook::NeighbourSearch, particles);
  CHECK(particles.velocity[1].x() == Approx(kTimeStep * 196.2 * 0.25).epsilon(1e-12));
  CHECK(particles.velocity[1].y() == 0.0);
  CHECK(particles.velocity[0] == Vec2::Zero());
  CHECK(particles.velocity[3] == Vec2::Zero());
  CHECK(particles.velocity[4] == Vec2::Zero());
  CHECK(particles.velocity[5] == Vec2::Zero());
  CHECK(particles.velocity[6] == Vec2::Zero());
  CHECK(particles.velocity[7] == Vec2::Zero());
}

TEST_CASE("spec 6.3: the position clamp puts particles on the bounds l0/2 inside the walls with v_n reversed times 0.2",
          "[mps][spec][walls]") {
  // Bounds x >= 0.0125, x <= 0.9875, y >= 0.0125, no top bound. A particle past a bound moving
  // into the wall: on the bound, v_n -> -0.2 v_n, tangential velocity kept.
  const Scene scene = defaults_scene();
  for (Hook hook : {Hook::ExplicitPosition, Hook::Correction}) {
    INFO("hook " << static_cast<int>(hook));
    ParticleSet particles;
    particles.add(Vec2(0.005, 0.3), Vec2(-1.0, 0.5), ParticleType::Fluid);  // left
    particles.add(Vec2(0.999, 0.3), Vec2(2.0, 0.1), ParticleType::Fluid);   // right
    particles.add(Vec2(0.5, 0.001), Vec2(0.3, -3.0), ParticleType::Fluid);  // bottom
    particles.add(Vec2(0.5, 0.65), Vec2(0.0, 1.0), ParticleType::Fluid);    // above the open top
    particles.add(Vec2(0.5, 0.3), Vec2(1.0, 1.0), ParticleType::Fluid);     // inside
    run_hook(scene, {"wall_position_clamp"}, hook, particles);
    CHECK(particles.position[0].x() == Approx(0.0125).epsilon(1e-12));
    CHECK(particles.velocity[0].x() == Approx(0.2).epsilon(1e-12));  // -0.2 * -1
    CHECK(particles.velocity[0].y() == 0.5);
    CHECK(particles.position[1].x() == Approx(0.9875).epsilon(1e-12));
    CHECK(particles.velocity[1].x() == Approx(-0.4).epsilon(1e-12));  // -0.2 * 2
    CHECK(particles.velocity[1].y() == 0.1);
    CHECK(particles.position[2].y() == Approx(0.0125).epsilon(1e-12));
    CHECK(particles.velocity[2].y() == Approx(0.6).epsilon(1e-12));  // -0.2 * -3
    CHECK(particles.velocity[2].x() == 0.3);
    CHECK(particles.position[3] == Vec2(0.5, 0.65));
    CHECK(particles.velocity[3] == Vec2(0.0, 1.0));
    CHECK(particles.position[4] == Vec2(0.5, 0.3));
    CHECK(particles.velocity[4] == Vec2(1.0, 1.0));
  }
}

TEST_CASE("spec 6.4: collision of approaching particles closer than 0.5 l0 with e = 0.2 and impulse factor 0.5",
          "[mps][spec][walls]") {
  const Scene scene = defaults_scene();
  ParticleSet particles;
  // 0, 1: 0.4 l0 apart along x, approaching at 1 m/s each. Normal from 0 to 1 is +x,
  // v_n = (v_0 - v_1).n = 2; dv_0 = -(1 + 0.2) 2 0.5 (+x) = -1.2 -> v_0 = -0.2; v_1 = +0.2.
  // The relative normal velocity -0.4 = -0.2 * 2: reversed and damped by e.
  particles.add(Vec2(0.3, 0.3), Vec2(1.0, 0.0), ParticleType::Fluid);
  particles.add(Vec2(0.3 + 0.4 * kSpacing, 0.3), Vec2(-1.0, 0.0), ParticleType::Fluid);
  // 2, 3: 0.4 l0 apart, receding: unchanged.
  particles.add(Vec2(0.5, 0.3), Vec2(-1.0, 0.0), ParticleType::Fluid);
  particles.add(Vec2(0.5 + 0.4 * kSpacing, 0.3), Vec2(1.0, 0.0), ParticleType::Fluid);
  // 4, 5: 0.6 l0 apart, approaching: beyond 0.5 l0, unchanged.
  particles.add(Vec2(0.7, 0.3), Vec2(1.0, 0.0), ParticleType::Fluid);
  particles.add(Vec2(0.7 + 0.6 * kSpacing, 0.3), Vec2(-1.0, 0.0), ParticleType::Fluid);
  run_hook(scene, {"particle_collision"}, Hook::NeighbourSearch, particles);
  CHECK(particles.velocity[0].x() == Approx(-0.2).epsilon(1e-12));
  CHECK(particles.velocity[1].x() == Approx(0.2).epsilon(1e-12));
  CHECK(particles.velocity[2] == Vec2(-1.0, 0.0));
  CHECK(particles.velocity[3] == Vec2(1.0, 0.0));
  CHECK(particles.velocity[4] == Vec2(1.0, 0.0));
  CHECK(particles.velocity[5] == Vec2(-1.0, 0.0));
}

TEST_CASE("spec 5.2-2 and 5.2-3: repulsion acts before collision", "[mps][spec][walls]") {
  // A fluid particle 0.4 l0 from a wall particle, moving into it at 1 m/s.
  // Repulsion first: overlap 0.6, dv = dt 196.2 0.36 = 0.035316 -> v = -0.964684.
  // Collision then: v_n = 0.964684 towards the wall (at rest); dv = 1.2 * 0.5 * 0.964684
  // = 0.5788104 -> v = -0.3858736 m/s. (Collision first would give -0.364684.)
  const Scene scene = defaults_scene();
  ParticleSet particles;
  particles.add(Vec2(0.2, 0.1), Vec2::Zero(), ParticleType::Wall, 1);
  particles.add(Vec2(0.2 + 0.4 * kSpacing, 0.1), Vec2(-1.0, 0.0), ParticleType::Fluid);
  run_hook(scene, {"wall_repulsion", "particle_collision"}, Hook::NeighbourSearch, particles);
  const double repelled = -1.0 + kTimeStep * 196.2 * 0.36;
  CHECK(particles.velocity[1].x() == Approx(repelled - 1.2 * 0.5 * repelled).epsilon(1e-12));
  CHECK(particles.velocity[1].x() == Approx(-0.3858736).epsilon(1e-9));
  CHECK(particles.velocity[0] == Vec2::Zero());
  // The default set of the mps method runs them in that order.
  const WallTreatmentSet defaults(scene.method_config("mps").wall_treatments, scene);
  const auto names = defaults.names();
  const auto at = [&](const std::string& name) { return std::find(names.begin(), names.end(), name) - names.begin(); };
  CHECK(at("wall_repulsion") < at("particle_collision"));
}
