// Spec §2 and §3 item by item: the weight and R_MIN, the number density, the Laplacian and
// gradient models with their coefficients, n0 and lambda on the lattice, re = 2.1 l0, and
// every default value of the spec's parameter table as the scene loader and the mps method
// declare it. Hand-built sets of 2-3 particles; each expected value is derived in a comment.
// Tolerances: the expected values are exact up to a few roundings of double arithmetic, so
// 1e-12 relative unless stated.
#include <catch2/catch.hpp>

#include "methods/mps/mps_kernels.hpp"
#include "methods/mps/mps_operators.hpp"
#include "test_mps_spec_support.hpp"

using namespace mps_lab;
using namespace mps_lab::mps;
using namespace mps_lab::spec_testing;

namespace {

constexpr double kRe = 2.1 * kSpacing;     // m
constexpr double kRMin = 0.01 * kSpacing;  // m
constexpr double kDensity = 1000.0;        // kg/m^3
const Vec2 kOrigin(0.5, 0.3);              // m, away from everything

NeighbourList neighbours_of(const ParticleSet& particles, double radius) {
  return find_neighbours(particles.position, particles.type, radius);
}

}  // namespace

TEST_CASE("spec 2: the weight is re/r - 1 inside re and 0 outside with r clamped at R_MIN", "[mps][spec]") {
  // w(l0) = 2.1 - 1 = 1.1; w(2 l0) = 1.05 - 1 = 0.05; w(re) = 0 (r >= re); w beyond re = 0.
  CHECK(mps_weight(kSpacing, kRe, kRMin) == Approx(1.1).epsilon(1e-12));
  CHECK(mps_weight(2.0 * kSpacing, kRe, kRMin) == Approx(0.05).epsilon(1e-12));
  CHECK(mps_weight(kRe, kRe, kRMin) == 0.0);
  CHECK(mps_weight(1.001 * kRe, kRe, kRMin) == 0.0);
  // Below R_MIN = 0.01 l0 the distance is R_MIN: w = re / R_MIN - 1 = 210 - 1 = 209.
  CHECK(mps_weight(0.5 * kRMin, kRe, kRMin) == Approx(209.0).epsilon(1e-12));
  CHECK(mps_weight(0.0, kRe, kRMin) == Approx(209.0).epsilon(1e-12));
}

TEST_CASE("spec 2: n0 and lambda are measured on the lattice for re = 2.1 l0", "[mps][spec]") {
  // hand_n0 = 4 (1.1) + 4 (2.1/sqrt 2 - 1) + 4 (0.05) = 6.53970; lambda = 1.38835 l0^2
  // (test_mps_spec_support.hpp).
  const MpsLatticeConstants lattice = mps_lattice_constants(kSpacing, kRe, kRMin);
  CHECK(lattice.number_density == Approx(hand_n0()).epsilon(1e-12));
  CHECK(lattice.number_density == Approx(6.5397).margin(5e-5));
  CHECK(lattice.lambda == Approx(hand_lambda(kSpacing)).epsilon(1e-12));
  CHECK(lattice.lambda / (kSpacing * kSpacing) == Approx(1.38835).margin(5e-6));
}

TEST_CASE("spec 2: the mps method uses R_MIN = 0.01 l0 and re = 2.1 l0 by default", "[mps][spec]") {
  // Two fluid particles 0.001 l0 apart (below R_MIN): each sees w = re/R_MIN - 1 = 209, which
  // the method writes to the number_density field at initialisation.
  const Scene scene = defaults_scene();
  ParticleSet particles = mps_particles();
  particles.add(kOrigin, Vec2::Zero(), ParticleType::Fluid);
  particles.add(kOrigin + Vec2(0.001 * kSpacing, 0.0), Vec2::Zero(), ParticleType::Fluid);
  auto method = make_mps(scene);
  method->initialise(particles);
  CHECK(particles.field("number_density")[0] == Approx(209.0).epsilon(1e-12));
  CHECK(particles.field("number_density")[1] == Approx(209.0).epsilon(1e-12));
  // Each operator's radius is 2.1 l0 with the lattice constants of that radius.
  const auto summary = method->summary();
  for (const char* radius : {"number_density_radius", "gradient_radius", "laplacian_radius"}) {
    INFO(radius);
    CHECK(summary[radius]["re_over_l0"].get<double>() == Approx(2.1).epsilon(1e-12));
    CHECK(summary[radius]["n0"].get<double>() == Approx(hand_n0()).epsilon(1e-12));
    CHECK(summary[radius]["lambda_over_l0_squared"].get<double>() ==
          Approx(hand_lambda(kSpacing) / (kSpacing * kSpacing)).epsilon(1e-12));
  }
}

TEST_CASE("spec 2: the number density sums w over the neighbours within re", "[mps][spec]") {
  // Three particles in a row l0 apart: the middle one has w(l0) twice = 2.2; an end one
  // w(l0) + w(2 l0) = 1.1 + 0.05 = 1.15.
  ParticleSet particles;
  for (int k = 0; k < 3; ++k) particles.add(kOrigin + Vec2(k * kSpacing, 0.0), Vec2::Zero(), ParticleType::Fluid);
  const OperatorRadius radius = make_operator_radius(kSpacing, kRe, kRMin);
  std::vector<double> n;
  number_density(particles, neighbours_of(particles, 3.0 * kSpacing), WallSampleList{}, radius, n);
  CHECK(n[0] == Approx(1.15).epsilon(1e-12));
  CHECK(n[1] == Approx(2.2).epsilon(1e-12));
  CHECK(n[2] == Approx(1.15).epsilon(1e-12));
}

TEST_CASE("spec 2: the Laplacian is 2d/(n0 lambda) sum (u_j - u_i) w_ij", "[mps][spec]") {
  // Two fluid particles l0 apart, u_0 = (1, 0), u_1 = (3, 2), nu = 1 m^2/s:
  // a_0 = (2 * 2 / (n0 lambda)) (u_1 - u_0) w(l0) = (4 / (n0 lambda)) (2, 2) 1.1.
  ParticleSet particles;
  particles.add(kOrigin, Vec2(1.0, 0.0), ParticleType::Fluid);
  particles.add(kOrigin + Vec2(kSpacing, 0.0), Vec2(3.0, 2.0), ParticleType::Fluid);
  const OperatorRadius radius = make_operator_radius(kSpacing, kRe, kRMin);
  std::vector<Vec2> acceleration(2, Vec2::Zero());
  add_viscous_acceleration(particles, neighbours_of(particles, kRe), WallSampleList{}, radius, 1.0, acceleration);
  const double coefficient = 4.0 / (hand_n0() * hand_lambda(kSpacing));  // 1/m^2
  CHECK(acceleration[0].x() == Approx(coefficient * 2.0 * 1.1).epsilon(1e-12));
  CHECK(acceleration[0].y() == Approx(coefficient * 2.0 * 1.1).epsilon(1e-12));
  CHECK(acceleration[1].x() == Approx(-coefficient * 2.0 * 1.1).epsilon(1e-12));
  // A uniform velocity has zero Laplacian.
  particles.velocity[1] = particles.velocity[0];
  std::fill(acceleration.begin(), acceleration.end(), Vec2::Zero());
  add_viscous_acceleration(particles, neighbours_of(particles, kRe), WallSampleList{}, radius, 1.0, acceleration);
  CHECK(acceleration[0].norm() == 0.0);
}

TEST_CASE("spec 2: the gradient is d/n0 sum (P_j - P_min) r_ij w_ij / r^2 with P_min over i and its neighbours",
          "[mps][spec]") {
  // i at the origin, j at (l0, 0), k at (0, l0); w = 1.1 for both, r^2 = l0^2.
  // a_i = -(1/rho) (2/n0) sum_j (P_j - P_min) (r_ij / l0^2) 1.1.
  ParticleSet particles;
  particles.add(kOrigin, Vec2::Zero(), ParticleType::Fluid);
  particles.add(kOrigin + Vec2(kSpacing, 0.0), Vec2::Zero(), ParticleType::Fluid);
  particles.add(kOrigin + Vec2(0.0, kSpacing), Vec2::Zero(), ParticleType::Fluid);
  const OperatorRadius radius = make_operator_radius(kSpacing, kRe, kRMin);
  const NeighbourList list = neighbours_of(particles, kRe);
  const std::vector<char> carries(3, 1);
  std::vector<Vec2> acceleration(3, Vec2::Zero());
  const double factor = 2.0 / hand_n0() / kDensity * 1.1 / kSpacing;  // (1/rho)(d/n0) w / l0, m^2/kg... per Pa

  SECTION("P_min is the lowest neighbour") {
    // P_i = 100, P_j = 50, P_k = 200 Pa: P_min = 50; the j term vanishes, the k term is 150.
    particles.pressure = {100.0, 50.0, 200.0};
    pressure_acceleration(particles, list, WallSampleList{}, radius, carries, kDensity, Vec2(0.0, -9.81), true,
                          acceleration, DryWallRule{});
    CHECK(acceleration[0].x() == Approx(0.0).margin(1e-12));
    CHECK(acceleration[0].y() == Approx(-factor * 150.0).epsilon(1e-12));
  }
  SECTION("P_min includes particle i itself") {
    // P_i = 10 is the lowest: P_min = 10, terms (50 - 10) along x and (200 - 10) along y.
    particles.pressure = {10.0, 50.0, 200.0};
    pressure_acceleration(particles, list, WallSampleList{}, radius, carries, kDensity, Vec2(0.0, -9.81), true,
                          acceleration, DryWallRule{});
    CHECK(acceleration[0].x() == Approx(-factor * 40.0).epsilon(1e-12));
    CHECK(acceleration[0].y() == Approx(-factor * 190.0).epsilon(1e-12));
  }
}

TEST_CASE("spec 3: the defaults of the parameter table", "[mps][spec]") {
  // Every value of spec §3 as declared by the scene loader, the mps method and the four
  // measures (a scene that sets none of them). Exact: these are literals.
  const Scene scene = defaults_scene();
  CHECK(scene.particle_spacing == 0.025);
  CHECK(scene.walls.layers == 3);
  CHECK(scene.physics.density == 1000.0);
  CHECK(scene.physics.kinematic_viscosity == 1.0e-6);
  CHECK(scene.physics.gravity == Vec2(0.0, -9.81));
  CHECK(scene.time.time_step == 5.0e-4);
  CHECK(scene.time.end_time == 2.0);
  CHECK(scene.output.frame_every_steps == 100);
  CHECK(scene.walls.bottom);
  CHECK(scene.walls.left);
  CHECK(scene.walls.right);
  CHECK_FALSE(scene.walls.top);

  const ParameterValues& mps = scene.method_config("mps").parameters;
  CHECK(mps.number("re_number_density") == 2.1);
  CHECK(mps.number("re_gradient") == 2.1);
  CHECK(mps.number("re_laplacian") == 2.1);
  CHECK(mps.number("r_min") == 0.01);
  CHECK(mps.number("free_surface_threshold") == 0.97);
  CHECK(mps.number("relaxation") == 0.2);
  CHECK(mps.integer("cg_max_iterations") == 10000);
  CHECK(mps.number("cg_tolerance") == 1.0e-8);
  CHECK(mps.boolean("min_pressure_includes_self"));
  CHECK(mps.boolean("clamp_negative_pressure"));

  std::map<std::string, const WallTreatmentChoice*> walls;
  for (const auto& choice : scene.method_config("mps").wall_treatments) walls[choice.info->name] = &choice;
  for (const char* name :
       {"spec_wall_particles", "cfl_velocity_clamp", "wall_repulsion", "wall_position_clamp", "particle_collision"}) {
    INFO(name);
    REQUIRE(walls.count(name) == 1);
    CHECK(walls[name]->enabled);
  }
  CHECK(walls["spec_wall_particles"]->parameters.integer("pressure_layers") == 1);
  CHECK(walls["cfl_velocity_clamp"]->parameters.number("cfl") == 0.2);
  CHECK(walls["wall_repulsion"]->parameters.number("distance") == 1.0);
  CHECK(walls["wall_repulsion"]->parameters.number("coefficient_factor") == 0.5);
  CHECK(walls["wall_position_clamp"]->parameters.number("offset") == 0.5);
  CHECK(walls["wall_position_clamp"]->parameters.number("restitution") == 0.2);
  CHECK(walls["particle_collision"]->parameters.number("distance") == 0.5);
  CHECK(walls["particle_collision"]->parameters.number("restitution") == 0.2);
}
