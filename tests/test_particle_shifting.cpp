// Particle shifting (core/walls/particle_shifting.cpp) term by term, on hand-built lattices run
// through WallTreatmentSet at after_correction with the mps method's support 2.1 l0. The expected
// shift is recomputed here from the published formula (Lind et al. 2012; Skillen et al. 2013):
//   dr_i = -(A |u_i| dt + B h) h s_i grad C_i,  grad C_i = V sum_j grad_i W_ij,  h = support / 2,
// Wendland C2, V = 1 / (lattice kernel sum), s_i the free-surface ramp. Tolerances 1e-9 relative
// (the same sums in another order).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#include "core/kernels/sph_kernels.hpp"
#include "test_mps_spec_support.hpp"

using namespace mps_lab;
using namespace mps_lab::spec_testing;

namespace {

constexpr double kSupport = 2.1 * kSpacing;  // the mps method's operator support, m

Scene shifting_scene(const std::string& settings = "{}") {
  return defaults_scene({"methods.mps.wall_treatments.particle_shifting=" + settings});
}

// `columns` x `rows` fluid particles at spacing l0 from (0.2, 0.2), each with velocity u(x).
template <class Velocity>
ParticleSet fluid_lattice(int columns, int rows, Velocity velocity) {
  ParticleSet particles;
  for (int a = 0; a < columns; ++a) {
    for (int b = 0; b < rows; ++b) {
      const Vec2 x(0.2 + a * kSpacing, 0.2 + b * kSpacing);
      particles.add(x, velocity(x), ParticleType::Fluid);
    }
  }
  return particles;
}
std::size_t lattice_index(int a, int b, int rows) { return static_cast<std::size_t>(a * rows + b); }

void shift(const Scene& scene, ParticleSet& particles) {
  WallTreatmentSet set = only_treatments(scene, {"particle_shifting"});
  WallContext context{particles, nullptr, kTimeStep, scene};  // the shifting searches itself
  context.support = kSupport;
  set.after_correction(context);
}

// The published sums for particle i of `particles` (before the shift), every other particle a
// neighbour when closer than the support.
struct Expected {
  Vec2 gradient = Vec2::Zero();  // grad C, 1/m
  double divergence = 0.0;       // div r
  Mat2 velocity_gradient = Mat2::Zero();
};
Expected expected_sums(const ParticleSet& particles, std::size_t i) {
  const SphKernel kernel(SphKernelKind::WendlandC2, kSupport);
  const double volume = 1.0 / lattice_kernel_sum(kernel, kSpacing);
  Expected sums;
  for (std::size_t j = 0; j < particles.size(); ++j) {
    if (j == i) continue;
    const Vec2 r_ij = particles.position[i] - particles.position[j];
    const Vec2 grad_w = kernel.gradient(r_ij);
    sums.gradient += volume * grad_w;
    sums.divergence -= volume * r_ij.dot(grad_w);
    sums.velocity_gradient += volume * (particles.velocity[j] - particles.velocity[i]) * grad_w.transpose();
  }
  return sums;
}

// div r inside the square lattice (the ramp's full end): 1.8986 at 2.1 l0, where the continuous
// integral gives 2.
double inside_divergence() {
  ParticleSet lattice = fluid_lattice(11, 11, [](const Vec2&) { return Vec2::Zero(); });
  return expected_sums(lattice, lattice_index(5, 5, 11)).divergence;
}
const double kInsideDivergence = inside_divergence();

// dr = -(A |u| dt + B h) h s grad C.
Vec2 expected_shift(const Expected& sums, double coefficient, double speed, double threshold = 1.5,
                    double fixed_coefficient = 0.0) {
  const double ramp = std::clamp((sums.divergence - threshold) / (kInsideDivergence - threshold), 0.0, 1.0);
  const double h = 0.5 * kSupport;
  return -(coefficient * speed * kTimeStep + fixed_coefficient * h) * h * ramp * sums.gradient;
}

}  // namespace

TEST_CASE("particle shifting: on the square lattice nothing moves", "[walls][shifting]") {
  // grad C = 0 by symmetry at every particle with a full support, and the particles near the
  // block's edges have div r < 1.5 or a ramp times a gradient: only the edges could move, and
  // the particles two spacings in (full support at 2.1 l0) must not.
  const Scene scene = shifting_scene();
  ParticleSet particles = fluid_lattice(9, 9, [](const Vec2&) { return Vec2(1.0, 0.0); });
  const ParticleSet before = particles;
  shift(scene, particles);
  for (int a = 2; a < 7; ++a) {
    for (int b = 2; b < 7; ++b) {
      const std::size_t i = lattice_index(a, b, 9);
      CHECK((particles.position[i] - before.position[i]).norm() < 1e-15);
    }
  }
}

TEST_CASE("particle shifting: a displaced particle moves back by -A h |u| dt grad C", "[walls][shifting]") {
  // The centre of an 11 x 11 block moved by (0.2, 0.1) l0; uniform u = (1, 0) m/s, so the
  // velocity correction adds nothing. Expected: the published formula with A = 2 (the default)
  // and with A = 4 (twice the shift); and the shift points back towards the lattice site.
  const auto uniform = [](const Vec2&) { return Vec2(1.0, 0.0); };
  for (const double coefficient : {2.0, 4.0}) {
    const Scene scene = shifting_scene(R"({"coefficient":)" + std::to_string(coefficient) + "}");
    ParticleSet particles = fluid_lattice(11, 11, uniform);
    const std::size_t centre = lattice_index(5, 5, 11);
    const Vec2 displacement = kSpacing * Vec2(0.2, 0.1);
    particles.position[centre] += displacement;
    const Expected sums = expected_sums(particles, centre);
    const Vec2 start = particles.position[centre];
    shift(scene, particles);
    const Vec2 moved = particles.position[centre] - start;
    const Vec2 expected = expected_shift(sums, coefficient, 1.0);
    // Inside, but the displacement lowers div r to 1.844: s = 0.87 of the full shift.
    CHECK(sums.divergence == Approx(1.844).margin(0.001));
    CHECK(moved.x() == Approx(expected.x()).epsilon(1e-9));
    CHECK(moved.y() == Approx(expected.y()).epsilon(1e-9));
    CHECK(moved.dot(displacement) < 0.0);                 // back towards the site
    CHECK(particles.velocity[centre] == Vec2(1.0, 0.0));  // uniform flow: no correction
  }
}

TEST_CASE("particle shifting: the shift scales with the particle's speed", "[walls][shifting]") {
  // D = A h |u| dt: the same displaced block at |u| = 3 m/s moves three times as far; at rest
  // it does not move (D = 0).
  const Scene scene = shifting_scene();
  Vec2 moved[2];
  int k = 0;
  for (const double speed : {1.0, 3.0}) {
    ParticleSet particles = fluid_lattice(11, 11, [speed](const Vec2&) { return Vec2(0.0, speed); });
    particles.position[lattice_index(5, 5, 11)] += kSpacing * Vec2(0.2, 0.1);
    const Vec2 start = particles.position[lattice_index(5, 5, 11)];
    shift(scene, particles);
    moved[k++] = particles.position[lattice_index(5, 5, 11)] - start;
  }
  CHECK(moved[1].x() == Approx(3.0 * moved[0].x()).epsilon(1e-9));
  CHECK(moved[1].y() == Approx(3.0 * moved[0].y()).epsilon(1e-9));
  ParticleSet still = fluid_lattice(11, 11, [](const Vec2&) { return Vec2::Zero(); });
  still.position[lattice_index(5, 5, 11)] += kSpacing * Vec2(0.2, 0.1);
  const ParticleSet before = still;
  shift(scene, still);
  CHECK(still.position == before.position);
}

TEST_CASE("particle shifting: the fixed part B h^2 orders water at rest", "[walls][shifting]") {
  // D = (A |u| dt + B h) h: with B = 0.05 the displaced centre of a block at rest moves by
  // -0.05 h^2 s grad C (A's part is zero at rest); moving at 1 m/s with A = 2 as well, by the sum.
  const Scene at_rest_scene = shifting_scene(R"({"coefficient":0,"fixed_coefficient":0.05})");
  const Scene both_scene = shifting_scene(R"({"coefficient":2,"fixed_coefficient":0.05})");
  for (const double speed : {0.0, 1.0}) {
    ParticleSet particles = fluid_lattice(11, 11, [speed](const Vec2&) { return Vec2(speed, 0.0); });
    const std::size_t centre = lattice_index(5, 5, 11);
    particles.position[centre] += kSpacing * Vec2(0.2, 0.1);
    const Expected sums = expected_sums(particles, centre);
    const Vec2 start = particles.position[centre];
    shift(speed == 0.0 ? at_rest_scene : both_scene, particles);
    const Vec2 moved = particles.position[centre] - start;
    const Vec2 expected = expected_shift(sums, speed == 0.0 ? 0.0 : 2.0, speed, 1.5, 0.05);
    CHECK(moved.norm() > 0.0);
    CHECK(moved.x() == Approx(expected.x()).epsilon(1e-9));
    CHECK(moved.y() == Approx(expected.y()).epsilon(1e-9));
  }
}

TEST_CASE("particle shifting: none on the free surface, a ramp below it", "[walls][shifting]") {
  // An 11-wide, 6-high block whose top row's middle particle is moved sideways by 0.2 l0: its
  // grad C is not zero, but its div r = 1.27 is below the threshold 1.5, so it stays. The
  // particle below it (div r 1.8976, the lattice's 1.8986 but for the moved one) moves by the
  // formula. With free_surface_threshold 1.2 the top particle is on the ramp, s = (1.27 - 1.2) /
  // (1.8986 - 1.2) = 0.1, and moves by that share of the formula.
  for (const double threshold : {1.5, 1.2}) {
    const Scene scene = shifting_scene(R"({"free_surface_threshold":)" + std::to_string(threshold) + "}");
    ParticleSet particles = fluid_lattice(11, 6, [](const Vec2&) { return Vec2(1.0, 0.0); });
    const std::size_t top = lattice_index(5, 5, 6);
    const std::size_t below = lattice_index(5, 4, 6);
    particles.position[top] += kSpacing * Vec2(0.2, 0.0);
    const Expected top_sums = expected_sums(particles, top);
    const Expected below_sums = expected_sums(particles, below);
    const ParticleSet before = particles;
    shift(scene, particles);
    CHECK(top_sums.divergence > 1.2);
    CHECK(top_sums.divergence < 1.5);
    CHECK(top_sums.gradient.norm() > 1.0);  // 1/m: a gradient it would follow inside the water
    const Vec2 top_moved = particles.position[top] - before.position[top];
    const Vec2 top_expected = expected_shift(top_sums, 2.0, 1.0, threshold);
    if (threshold == 1.5) CHECK(top_moved == Vec2::Zero());
    CHECK(top_moved.x() == Approx(top_expected.x()).epsilon(1e-9).margin(1e-18));
    CHECK(top_moved.y() == Approx(top_expected.y()).epsilon(1e-9).margin(1e-18));
    const Vec2 expected = expected_shift(below_sums, 2.0, 1.0, threshold);
    const Vec2 moved = particles.position[below] - before.position[below];
    CHECK(moved.norm() > 0.0);
    CHECK(moved.x() == Approx(expected.x()).epsilon(1e-9));
    CHECK(moved.y() == Approx(expected.y()).epsilon(1e-9));
  }
}

TEST_CASE("particle shifting: wall particles complete the support", "[walls][shifting]") {
  // A fluid block on three layers of wall particles: the first fluid row has the full lattice
  // around it and does not move; without the wall rows it would be a surface (div r 1.27).
  // A first-row particle moved sideways moves back by the formula with the wall particles in
  // grad C.
  const Scene scene = shifting_scene();
  ParticleSet particles = fluid_lattice(11, 6, [](const Vec2&) { return Vec2(1.0, 0.0); });
  for (int a = -2; a < 13; ++a) {
    for (int layer = 1; layer <= 3; ++layer) {
      particles.add(Vec2(0.2 + a * kSpacing, 0.2 - layer * kSpacing), Vec2::Zero(), ParticleType::Wall,
                    static_cast<std::uint8_t>(layer));
    }
  }
  const std::size_t first_row = lattice_index(5, 0, 6);
  ParticleSet at_rest = particles;
  shift(scene, at_rest);
  CHECK((at_rest.position[first_row] - particles.position[first_row]).norm() < 1e-15);
  particles.position[first_row] += kSpacing * Vec2(0.2, 0.0);
  const Expected sums = expected_sums(particles, first_row);
  const Vec2 start = particles.position[first_row];
  shift(scene, particles);
  const Vec2 moved = particles.position[first_row] - start;
  const Vec2 expected = expected_shift(sums, 2.0, 1.0);
  CHECK(sums.divergence > 1.5);  // not a surface: the wall rows complete its support
  CHECK(moved.x() == Approx(expected.x()).epsilon(1e-9));
  CHECK(moved.x() < 0.0);
  CHECK(std::abs(moved.y()) < 1e-3 * std::abs(moved.x()));  // the wall rows mirror the fluid rows
}

TEST_CASE("particle shifting: the velocity follows the shift by its Taylor expansion", "[walls][shifting]") {
  // u = G x with G = [[0, 2], [1, 0]] 1/s plus (1, 0) m/s (so |u| > 0 everywhere): the
  // correction adds (grad u)_i dr_i with the recomputed SPH gradient; that gradient of a linear
  // field is G times the lattice's -V sum r_ij (x) grad W = 0.949 I (the probe's M_xx), so the
  // change is within 10 % of G dr. velocity_correction false (the default): the velocity stays.
  Mat2 g;
  g << 0.0, 2.0, 1.0, 0.0;
  const auto linear = [&g](const Vec2& x) { return Vec2(Vec2(1.0, 0.0) + g * x); };
  for (const bool correction : {true, false}) {
    const Scene scene = shifting_scene(correction ? R"({"velocity_correction":true})" : "{}");  // off by default
    ParticleSet particles = fluid_lattice(11, 11, linear);
    const std::size_t centre = lattice_index(5, 5, 11);
    particles.position[centre] += kSpacing * Vec2(0.2, 0.1);
    const Expected sums = expected_sums(particles, centre);
    const Vec2 start = particles.position[centre];
    const Vec2 u_before = particles.velocity[centre];
    shift(scene, particles);
    const Vec2 moved = particles.position[centre] - start;
    const Vec2 change = particles.velocity[centre] - u_before;
    if (!correction) {
      CHECK(change == Vec2::Zero());
      continue;
    }
    const Vec2 expected = sums.velocity_gradient * moved;
    CHECK(change.x() == Approx(expected.x()).epsilon(1e-6));
    CHECK(change.y() == Approx(expected.y()).epsilon(1e-6));
    CHECK((change - g * moved).norm() < 0.1 * (g * moved).norm());
  }
}

TEST_CASE("particle shifting: wall samples count as the wall particles they stand for", "[walls][shifting]") {
  // A fluid block on the tank's bed (first row at y = l0, the bed's first wall layer at y = 0):
  // once with the dummy_layers boundary model, whose samples are the bed's three lattice rows
  // (volume 1 each), once with those rows as wall particles and no samples. A first-row
  // particle moved by (0.2, 0.1) l0 moves by the same shift in both (to rounding): a sample
  // enters C and grad C with its volume as a wall particle does.
  const auto uniform = [](const Vec2&) { return Vec2(1.0, 0.0); };
  const auto block_on_bed = [&]() {
    ParticleSet particles;
    for (int a = 0; a < 11; ++a) {
      for (int b = 1; b <= 6; ++b)
        particles.add(Vec2(0.3 + a * kSpacing, b * kSpacing), uniform(Vec2()), ParticleType::Fluid);
    }
    particles.position[lattice_index(5, 0, 6)] += kSpacing * Vec2(0.2, 0.1);
    return particles;
  };
  const std::size_t moved_one = lattice_index(5, 0, 6);
  const Scene scene = defaults_scene({R"(methods.mps.wall_treatments={"dummy_layers":{},"particle_shifting":{}})"});
  ParticleSet with_samples = block_on_bed();
  const Vec2 start = with_samples.position[moved_one];
  {
    WallTreatmentSet set = only_treatments(scene, {"dummy_layers", "particle_shifting"});
    WallContext context{with_samples, nullptr, kTimeStep, scene};
    context.support = kSupport;
    WallSampleList samples;
    set.build_wall_samples(context, samples);
    // Within 2.1 l0 of it (1.1 l0 above the bed's first row, the second row 2.1 l0 away): that
    // row's points at x - x_i = -1.2, -0.2 and 0.8 l0.
    REQUIRE(samples.end(moved_one) - samples.begin(moved_one) == 3);
    context.samples = &samples;
    set.after_correction(context);
  }
  ParticleSet with_particles = block_on_bed();
  for (int a = -4; a < 15; ++a) {
    for (int layer = 1; layer <= 3; ++layer) {
      with_particles.add(Vec2(0.3 + a * kSpacing, -(layer - 1) * kSpacing), Vec2::Zero(), ParticleType::Wall,
                         static_cast<std::uint8_t>(layer));
    }
  }
  shift(shifting_scene(), with_particles);
  const Vec2 by_samples = with_samples.position[moved_one] - start;
  const Vec2 by_particles = with_particles.position[moved_one] - start;
  CHECK(by_samples.norm() > 0.0);
  CHECK(by_samples.x() == Approx(by_particles.x()).epsilon(1e-9));
  CHECK(by_samples.y() == Approx(by_particles.y()).epsilon(1e-9));
}
