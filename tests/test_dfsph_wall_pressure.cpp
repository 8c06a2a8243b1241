// DFSPH's wall pressure (issue 14 item 4; docs/methods/dfsph.md "At the walls"):
// methods.dfsph.wall_pressure = extrapolated gives the boundary particles a pressure of their own,
// p_b = sum_f [p_f + rho_f g.(x_b - x_f)] W_bf / sum_f W_bf (Adami, Hu & Adams 2012 eq. (27)),
// in the symmetric force -Psi_b (p_i/rho_i^2 + p_b/rho0^2) grad W_ib (Band et al. 2018).
// Hand-computed sums on a bed, one solver iteration against its formula, the explicit
// hydrostatic part, and the parameter's bad input.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "core/io/scene.hpp"
#include "core/run/driver.hpp"
#include "core/search/neighbour_search.hpp"
#include "methods/dfsph/dfsph_operators.hpp"
#include "methods/dfsph/dfsph_solvers.hpp"
#include "still_water_sensors.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::dfsph;
using namespace mps_lab::testing;

namespace {

constexpr double kL0 = 0.025;     // m
constexpr double kRho0 = 1000.0;  // kg/m^3
constexpr double kG = 9.81;       // m/s^2
const double kMass = kRho0 * kL0 * kL0;

struct Bed {
  ParticleSet particles;
  NeighbourList neighbours;
  KernelCache cache;
  std::vector<double> boundary_mass;
  std::vector<double> density;
  SphKernel kernel{SphKernelKind::CubicSpline, 2.0 * kL0};
  WallPressureStencil stencil;

  // Wall particles (layer 1) at `walls` and fluid at `fluid` (in l0); every fluid density `rho`.
  Bed(const std::vector<Vec2>& walls, const std::vector<Vec2>& fluid, double rho) {
    for (const Vec2& w : walls) particles.add(kL0 * w, Vec2::Zero(), ParticleType::Wall, 1);
    for (const Vec2& f : fluid) particles.add(kL0 * f, Vec2::Zero(), ParticleType::Fluid);
    neighbours = find_neighbours(particles.position, particles.type, kernel.support());
    compute_kernel_cache(particles, neighbours, kernel, cache);
    compute_boundary_masses(particles, neighbours, cache, 1, kRho0, BoundaryVolume::Lattice, kL0 * kL0, boundary_mass);
    compute_kernel_cache(particles, neighbours, kernel, kMass, boundary_mass, cache);
    density.assign(particles.size(), 0.0);
    for (std::size_t i = walls.size(); i < particles.size(); ++i) density[i] = rho;
  }
  SphSystem system(bool extrapolated) const {
    SphSystem s{neighbours, cache, boundary_mass, kMass, kRho0};
    s.wall_pressure = extrapolated ? &stencil : nullptr;
    return s;
  }
  void extrapolate() {
    compute_wall_pressure_stencil(particles, system(true), kernel, density, Vec2(0.0, -kG), stencil);
  }
};

}  // namespace

TEST_CASE("DFSPH extrapolated wall pressure: Shepard weights and the hydrostatic term by hand",
          "[dfsph][operators][unit]") {
  // Bed particles at (0, 0), (5, 0) and (0, 3) l0 (the last above the fluid); fluid at (-1, 1),
  // (0, 1), (1, 1) and (0, 2) l0, rho_f = 1010 kg/m^3. The support is 2 l0 (W = 0 at 2 l0), so
  // b = (0, 0) sees the three fluid particles of row 1: W(l0) and twice W(sqrt2 l0);
  // (5, 0) sees none; (0, 3) sees (0, 2) at l0 and (+-1, 1)... at sqrt5 l0 > 2 l0: only (0, 2).
  const double rho_f = 1010.0;
  Bed bed({{0, 0}, {5, 0}, {0, 3}}, {{-1, 1}, {0, 1}, {1, 1}, {0, 2}}, rho_f);
  bed.extrapolate();
  const WallPressureStencil& s = bed.stencil;
  REQUIRE(s.boundary.size() == 2);  // (5, 0) has no fluid in reach
  CHECK(s.boundary[0] == 0);
  CHECK(s.boundary[1] == 2);
  REQUIRE(s.offsets[1] - s.offsets[0] == 3);
  const double w1 = bed.kernel.value(kL0), w2 = bed.kernel.value(std::sqrt(2.0) * kL0);
  double weights = 0.0;
  for (std::uint32_t k = s.offsets[0]; k < s.offsets[1]; ++k) {
    const double expected = (bed.particles.position[s.fluid[k]].x() == 0.0 ? w1 : w2) / (w1 + 2.0 * w2);
    CHECK(s.weight[k] == Approx(expected).epsilon(1e-14));
    weights += s.weight[k];
  }
  CHECK(weights == Approx(1.0).epsilon(1e-14));
  // Hydrostatic part of (0, 0): every neighbour is l0 above it, g.(x_b - x_f) = 9.81 l0:
  // rho_f 9.81 l0 / rho0^2 (m^5/(kg s^2)).
  CHECK(s.hydrostatic[0] == Approx(rho_f * kG * kL0 / (kRho0 * kRho0)).epsilon(1e-14));
  // (0, 3) is l0 above its fluid: a negative part, clamped at 0. Not a boundary row: 0.
  CHECK(s.hydrostatic[2] == 0.0);
  CHECK(s.hydrostatic[1] == 0.0);
  // The stiffness part: p_f = 1000 + 200 x/l0 Pa, linear and odd in x about b: Shepard gives
  // p_b = 1000 Pa exactly (the +-200 cancel with equal weights), s_b = p_b / rho0^2.
  std::vector<double> s_f(bed.particles.size(), 0.0);
  for (std::size_t f = 3; f < bed.particles.size(); ++f) {
    s_f[f] = (1000.0 + 200.0 * bed.particles.position[f].x() / kL0) / (rho_f * rho_f);
  }
  CHECK(extrapolated_wall_stiffness(s, 0, s_f.data(), bed.density, kRho0) ==
        Approx(1000.0 / (kRho0 * kRho0)).epsilon(1e-13));
  // (0, 3): its only fluid (0, 2) has p = 1000 Pa.
  CHECK(extrapolated_wall_stiffness(s, 1, s_f.data(), bed.density, kRho0) ==
        Approx(1000.0 / (kRho0 * kRho0)).epsilon(1e-13));
}

TEST_CASE("DFSPH extrapolated wall pressure: a wall sample at rest extrapolates from its owner and its neighbours",
          "[dfsph][operators][unit]") {
  // Fluid at (-1, 1), (0, 1), (1, 1) l0, rho_f = 1010 kg/m^3, no wall particles. Particle (0, 1)
  // has two wall samples: w0 at (0, 0) at rest carrying its own pressure (source = owner,
  // velocity map 0: dummy layers, distance function) and w1 at (0, -0.5) l0, a mirror image
  // (velocity map diag(1, -1)). w0's row: the owner and its fluid neighbours, W(|x_w - x_f|) =
  // W(l0) for the owner and W(sqrt2 l0) for each neighbour; hydrostatic part rho_f g l0 / rho0^2.
  // w1 has no row (its source's stiffness enters through the constraint).
  Bed bed({}, {{-1, 1}, {0, 1}, {1, 1}}, 1010.0);
  WallSampleList samples;
  samples.offsets = {0, 0, 2, 2};
  WallSample rest;
  rest.position = Vec2(0.0, 0.0);
  rest.source = 1;
  WallSample image = rest;
  image.position = Vec2(0.0, -0.5 * kL0);
  image.velocity_map << 1.0, 0.0, 0.0, -1.0;
  samples.samples = {rest, image};
  SampleCache sample_cache;
  compute_sample_cache(bed.particles, samples, bed.kernel, kRho0, kL0 * kL0, sample_cache);
  SphSystem system = bed.system(true);
  system.samples = &samples;
  system.sample_kernel = &sample_cache;
  compute_wall_pressure_stencil(bed.particles, system, bed.kernel, bed.density, Vec2(0.0, -kG), bed.stencil);
  const WallPressureStencil& s = bed.stencil;
  CHECK(s.boundary.empty());
  REQUIRE(s.sample_offsets.size() == 3);
  REQUIRE(s.sample_offsets[1] - s.sample_offsets[0] == 3);
  CHECK(s.sample_offsets[2] == s.sample_offsets[1]);  // the mirror image: no row
  const double w1 = bed.kernel.value(kL0), w2 = bed.kernel.value(std::sqrt(2.0) * kL0);
  CHECK(s.sample_fluid[0] == 1);  // the owner first
  CHECK(s.sample_weight[0] == Approx(w1 / (w1 + 2.0 * w2)).epsilon(1e-14));
  CHECK(s.sample_weight[1] == Approx(w2 / (w1 + 2.0 * w2)).epsilon(1e-14));
  CHECK(s.sample_hydrostatic[0] == Approx(1010.0 * kG * kL0 / (kRho0 * kRho0)).epsilon(1e-14));
  CHECK(s.sample_hydrostatic[1] == 0.0);
  // p_f = 1000 + 200 x/l0 Pa: p_w = 1000 Pa (odd part cancels); the image: 0.
  std::vector<double> s_f(3);
  for (std::size_t f = 0; f < 3; ++f) {
    s_f[f] = (1000.0 + 200.0 * bed.particles.position[f].x() / kL0) / (1010.0 * 1010.0);
  }
  CHECK(extrapolated_sample_stiffness(s, 0, s_f.data(), bed.density, kRho0) ==
        Approx(1000.0 / (kRho0 * kRho0)).epsilon(1e-13));
  CHECK(extrapolated_sample_stiffness(s, 1, s_f.data(), bed.density, kRho0) == 0.0);
  // The explicit hydrostatic part on the owner: -Psi_w s_hyd grad W_iw for w0, and for the
  // image max(0, rho0 g.(x_w - x_s)) / rho0^2 = rho0 g 1.5 l0 / rho0^2.
  std::vector<Vec2> acceleration(3, Vec2::Zero());
  add_wall_hydrostatic_acceleration(bed.particles, system, Vec2(0.0, -kG), acceleration);
  const Vec2 x = bed.particles.position[1];
  const Vec2 expected = -kRho0 * kL0 * kL0 *
                        (s.sample_hydrostatic[0] * bed.kernel.gradient(x - rest.position) +
                         kG * 1.5 * kL0 / kRho0 * bed.kernel.gradient(x - image.position));
  CHECK(acceleration[1].x() == Approx(expected.x()).margin(1e-12));
  CHECK(acceleration[1].y() == Approx(expected.y()).epsilon(1e-12));
  CHECK(acceleration[0] == Vec2::Zero());
}

TEST_CASE("DFSPH extrapolated wall pressure: a moving wall particle's acceleration enters the hydrostatic term",
          "[dfsph][operators][unit]") {
  // [AHA12] eq. (27) with the wall's acceleration: p_b = sum_f [p_f + rho_f (g - a_b).(x_b - x_f)] W_bf
  // / sum_f W_bf. Bed particle b at (0, 0) under fluid row 1 ((-1, 1), (0, 1), (1, 1) l0), every
  // neighbour l0 above b: (g - a_b).(x_b - x_f) = (|g| + a_y) l0 - 0 for a_b = (a_x, a_y)
  // (x_b - x_f has x parts -+l0 that cancel between (-1, 1) and (1, 1) with equal weights, and 0
  // for (0, 1)). a_b = (3, g/2): s_b,hyd = rho_f 1.5 |g| l0 / rho0^2, 1.5 times the wall at rest;
  // a_b = (0, -2 g) (falling faster than gravity): negative, clamped at 0.
  const double rho_f = 1010.0;
  for (const double a_y : {0.5 * kG, -2.0 * kG}) {
    Bed bed({{0, 0}}, {{-1, 1}, {0, 1}, {1, 1}}, rho_f);
    bed.particles.wall_velocity.assign(bed.particles.size(), Vec2::Zero());
    bed.particles.wall_acceleration.assign(bed.particles.size(), Vec2::Zero());
    bed.particles.wall_acceleration[0] = Vec2(3.0, a_y);
    bed.extrapolate();
    REQUIRE(bed.stencil.boundary.size() == 1);
    const double expected = std::max(0.0, rho_f * (kG + a_y) * kL0) / (kRho0 * kRho0);
    INFO("a_y = " << a_y);
    CHECK(bed.stencil.hydrostatic[0] == Approx(expected).epsilon(1e-12).margin(1e-18));
  }
}

TEST_CASE("DFSPH extrapolated wall pressure: one density iteration applies the symmetric wall term",
          "[dfsph][solver][unit]") {
  // One fluid particle i at (0, 1) l0 above one boundary particle b at (0, 0), rho_i = 1.01 rho0,
  // at rest: the density solver's first increment is kappa = (rho_i - rho0) / dt^2 alpha_i
  // ([BK17] eq. (12)), s_i = kappa / rho_i, and one correction moves i by
  //   mirrored:     dv = -dt s_i c_ib                              ([AIA12])
  //   extrapolated: dv = -dt (s_i + s_b) c_ib, s_b = rho_i^2 s_i / rho0^2 (b's only fluid is i)
  // so the ratio of the two is 1 + 1.01^2 = 2.0201. The hydrostatic part is not in the solver.
  const double dt = 1e-3;  // s
  SolverSettings settings;
  settings.min_iterations = 1;
  settings.max_iterations = 1;
  settings.warm_start_fraction = 0.0;
  Vec2 dv[2];
  double s_i = 0.0;
  Vec2 c_ib = Vec2::Zero();
  for (const bool extrapolated : {false, true}) {
    Bed bed({{0, 0}}, {{0, 1}}, 1.01 * kRho0);
    bed.extrapolate();
    const SphSystem system = bed.system(extrapolated);
    std::vector<double> alpha, stiffness;
    compute_dfsph_factors(bed.particles, system, bed.density, alpha);
    SolverWorkspace workspace;
    const SolverOutcome outcome =
        correct_density_error(bed.particles, system, bed.density, alpha, dt, settings, stiffness, workspace);
    CHECK(outcome.iterations == 1);
    dv[extrapolated ? 1 : 0] = bed.particles.velocity[1];
    s_i = 0.01 * kRho0 / (dt * dt) * alpha[1] / bed.density[1];
    c_ib = bed.boundary_mass[0] * bed.kernel.gradient(bed.particles.position[1] - bed.particles.position[0]);
  }
  CHECK(dv[0].x() == 0.0);
  CHECK(dv[0].y() > 0.0);  // pushed off the wall
  CHECK(dv[0].y() == Approx((-dt * s_i * c_ib).y()).epsilon(1e-12));
  CHECK(dv[1].y() == Approx((-dt * (1.0 + 1.01 * 1.01) * s_i * c_ib).y()).epsilon(1e-12));
  CHECK(dv[1].y() / dv[0].y() == Approx(2.0201).epsilon(1e-12));
}

TEST_CASE("DFSPH extrapolated wall pressure: the hydrostatic part as an explicit acceleration",
          "[dfsph][operators][unit]") {
  // i at (0, 1) l0, b at (0, 0): s_b,hyd = rho_i g l0 / rho0^2, and
  // a_i = -Psi_b s_b,hyd grad W_ib (upwards; m/s^2). Mirrored (no stencil, no samples): nothing.
  Bed bed({{0, 0}}, {{0, 1}}, 1.01 * kRho0);
  bed.extrapolate();
  std::vector<Vec2> acceleration(2, Vec2::Zero());
  add_wall_hydrostatic_acceleration(bed.particles, bed.system(true), Vec2(0.0, -kG), acceleration);
  const Vec2 grad = bed.kernel.gradient(bed.particles.position[1] - bed.particles.position[0]);
  const double s_hyd = 1.01 * kRho0 * kG * kL0 / (kRho0 * kRho0);
  CHECK(acceleration[1].x() == 0.0);
  CHECK(acceleration[1].y() == Approx(-kRho0 * kL0 * kL0 * s_hyd * grad.y()).epsilon(1e-13));
  CHECK(acceleration[1].y() > 0.0);
  CHECK(acceleration[0] == Vec2::Zero());  // walls get nothing
  std::vector<Vec2> none(2, Vec2::Zero());
  add_wall_hydrostatic_acceleration(bed.particles, bed.system(false), Vec2(0.0, -kG), none);
  CHECK(none[1] == Vec2::Zero());
}

TEST_CASE("DFSPH wall_pressure: bad input is a one-line error naming the key", "[dfsph][input]") {
  const MethodInfo& dfsph = *registries().methods.find("dfsph");
  const auto message = [&](const std::vector<std::string>& overrides) -> std::string {
    try {
      const Scene scene = load("hydrostatic.json", overrides);  // the Simulation keeps a reference to it
      Simulation simulation(scene, dfsph);
    } catch (const std::exception& error) {
      return error.what();
    }
    return "";
  };
  const std::string unknown = message({"methods.dfsph.wall_pressure=\"adami\""});
  INFO(unknown);
  CHECK(unknown.find("methods.dfsph.wall_pressure") != std::string::npos);
  CHECK(unknown.find('\n') == std::string::npos);
  const std::string twice =
      message({"methods.dfsph.wall_pressure=\"extrapolated\"", "methods.dfsph.wall_sample_hydrostatic=true"});
  INFO(twice);
  CHECK(twice.find("methods.dfsph.wall_sample_hydrostatic") != std::string::npos);
  CHECK(twice.find('\n') == std::string::npos);
  const std::string number = message({"methods.dfsph.wall_pressure=2"});
  INFO(number);
  CHECK(number.find("wall_pressure") != std::string::npos);
  // Both values are accepted.
  CHECK(message({"methods.dfsph.wall_pressure=\"extrapolated\""}).empty());
  CHECK(message({"methods.dfsph.wall_pressure=\"mirrored\""}).empty());
}

namespace {

// scenes/hydrostatic.json with wall_pressure = extrapolated and the given kernel support (in l0):
// the wall sensors of still_water_sensors.hpp with every boundary model dfsph supports.
template <class Check>
void still_water_wall_sensors(double kernel_support, double end_time, Check check, double gravity = 9.81) {
  mps_lab::testing::still_water_wall_sensors("dfsph",
                                             {"methods.dfsph.wall_pressure=\"extrapolated\"",
                                              "methods.dfsph.kernel_support=" + std::to_string(kernel_support)},
                                             end_time, check, gravity);
}

}  // namespace

TEST_CASE("DFSPH extrapolated wall pressure: still water reads rho g h at the wall - every boundary model",
          "[dfsph][validation][sensor]") {
  // The default support, 2 l0, mean over [0.5, 1.5] s. Measured (docs/methods/dfsph.md, "At the
  // walls"), h = 0.225 / 0.15 / 0.075 m: akinci_boundary 1.058 / 1.020 / 1.003, dummy_layers
  // 1.043 / 1.029 / 1.036, mirror_particles 1.032 / 1.007 / 1.003, distance_function 1.029 /
  // 1.015 / 1.017 (the mirrored default: 1.51-1.62 with the three lattice models, 1.01-1.03
  // with mirror particles). Bound: within 0.08 of 1 (the largest measured deviation, 0.058,
  // with margin); the mirrored wall term (1.5-1.6) fails it. At this support the 1 % target
  // is met at 4 of the 12 sensors (the next test case meets it with a wider kernel).
  still_water_wall_sensors(2.0, 1.5, [](const std::string& model, double depth, double ratio) {
    INFO("boundary model " << model << ", h = " << depth << " m: mean / rho g h = " << ratio);
    CHECK(std::fabs(ratio - 1.0) < 0.08);
  });
}

TEST_CASE("DFSPH extrapolated wall pressure with a 2.4 l0 kernel: still water within 1 % of rho g h - every model",
          "[dfsph][validation][sensor]") {
  // At the default support (2 l0: 8 neighbours on the lattice, 20 at 2.4 l0) the settled,
  // disordered particles' SPH gradient is short, -sum_j V (y_i - y_j) dW/dy = 0.98-0.99
  // (docs/methods/dfsph.md), so the pressure that carries the water is steep at every sensor
  // (all 12 read high: 1.010-1.054 over [0.5, 3] s). With 2.4 l0 the bias is gone. Measured, mean over [0.5, 3] s,
  // h = 0.225 / 0.15 / 0.075 m: akinci_boundary 1.0096 / 0.9982 / 0.9940, dummy_layers
  // 1.0077 / 1.0065 / 1.0071, mirror_particles 1.0100 / 1.0086 / 1.0002, distance_function
  // 1.0077 / 1.0008 / 1.0057 (largest deviation 1.00 %; with its blended corners, the default since
  // 2026-11-28, 0.9967 / 0.9965 / 1.0104). Bound: 1.5 %, the 1 % target plus the
  // scatter of the time mean itself: the same sensors averaged over [0.5, 1.5] s and [0.5, 5] s
  // move by up to 0.5 % (sloshing, period 0.8 s), e.g. 1.0071 -> 1.0121 (dummy_layers, h =
  // 0.075 m). The 2 l0 kernel fails it (dummy_layers 1.040 / 1.033 / 1.054).
  const auto within = [](const std::string& model, double depth, double ratio) {
    INFO("boundary model " << model << ", h = " << depth << " m: mean / rho g h = " << ratio);
    CHECK(std::fabs(ratio - 1.0) < 0.015);
    CHECK_NOFAIL(std::fabs(ratio - 1.0) < 0.01);  // the target, reported
  };
  still_water_wall_sensors(2.4, 3.0, within);
  // The tank accelerating upward at a = g/2: in its frame gravity g + a (tests/test_pressure_sensors.cpp),
  // p = rho (g + a) h. Measured: akinci_boundary 1.0053 / 0.9948 / 0.9967, dummy_layers 1.0070 /
  // 1.0071 / 1.0063, mirror_particles 1.0120 / 1.0137 / 1.0101, distance_function 1.0061 / 1.0006 /
  // 1.0004 (9 of 12 within 1 %).
  still_water_wall_sensors(2.4, 3.0, within, 1.5 * 9.81);
}
