// The water surface of the mps method (`free_surface_offset`, methods/mps/mps_pressure.hpp;
// docs/methods/mps.md, "The water surface"): a fluid surface particle with water below it holds
// the hydrostatic head rho |g| delta to a surface delta beyond its centre instead of the spec's
// P = 0, and the rows beside it carry that known value to their right-hand sides. Hand-built
// lattices of spacing l0; the head's value is computed here: 1000 * 9.81 * 0.5 * 0.025 Pa.
#include <catch2/catch.hpp>

#include <cmath>

#include "core/base/error.hpp"
#include "core/run/driver.hpp"
#include "core/search/for_each_neighbour.hpp"
#include "methods/mps/mps_operators.hpp"
#include "methods/mps/mps_pressure.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::mps;
using namespace mps_lab::testing;

namespace {

constexpr double kL0 = 0.025;                    // m
constexpr double kDt = 1.0e-3;                   // s
const double kHead = 1000.0 * 9.81 * 0.5 * kL0;  // Pa: rho |g| delta with delta = l0/2

// A 5 x 5 block of fluid on the lattice (index (i + 2) + 5 (j + 2) for column i, row j in
// [-2, 2]) and three wall particles l0 above its top-left corner's row, at columns -3, -2 and -1.
// The outer ring is the free surface (n* = 0.9 n0), the inner 3 x 3 unknowns at n0 (no source
// under the spec's term); the walls are surface particles too.
struct Block {
  ParticleSet particles;
  std::vector<double> number_density;
  std::size_t wall = 0;  // the first of the three wall particles
  static std::size_t at(int i, int j) { return static_cast<std::size_t>((i + 2) + 5 * (j + 2)); }
};

Block block(double n0) {
  Block b;
  for (int j = -2; j <= 2; ++j) {
    for (int i = -2; i <= 2; ++i) {
      b.particles.add(Vec2(0.3 + i * kL0, 0.2 + j * kL0), Vec2::Zero(), ParticleType::Fluid);
      const bool ring = std::abs(i) == 2 || std::abs(j) == 2;
      b.number_density.push_back(ring ? 0.9 * n0 : n0);
    }
  }
  b.wall = b.particles.size();
  for (int i = -3; i <= -1; ++i) {
    b.particles.add(Vec2(0.3 + i * kL0, 0.2 + 3 * kL0), Vec2::Zero(), ParticleType::Wall);
    b.number_density.push_back(0.5 * n0);  // surface wall particles (spec §3: they carry pressure)
  }
  return b;
}

struct Assembled {
  PressurePoissonSolver solver;
  std::vector<double> surface;
};

// list_radius: the neighbour list's radius when wider than the operator's (a method's list has
// the largest of its radii), 0 for radius.re.
void assemble(Block& b, const OperatorRadius& radius, double offset, Assembled& out,
              const WallSampleList& samples = WallSampleList{}, double list_radius = 0.0) {
  PressureSolveSettings settings;  // rho 1000, g (0, -9.81), beta 0.97, the spec's source
  settings.surface_offset = offset;
  const NeighbourList list =
      find_neighbours(b.particles.position, b.particles.type, list_radius > 0.0 ? list_radius : radius.re);
  out.solver.assemble(b.particles, list, samples, b.number_density, std::vector<char>(b.particles.size(), 1), radius,
                      radius.n0, kDt, settings, out.surface);
}

}  // namespace

TEST_CASE("mps water surface: a surface particle with water below it holds rho |g| delta, others 0", "[mps][surface]") {
  const OperatorRadius radius = make_operator_radius(kL0, 2.1 * kL0, 0.01 * kL0);
  Block b = block(radius.n0);
  Assembled a;
  assemble(b, radius, 0.5 * kL0, a);
  // The top row: its fluid neighbours lie below it.
  for (int i = -2; i <= 2; ++i) CHECK(b.particles.pressure[Block::at(i, 2)] == Approx(kHead).epsilon(1e-12));
  // The full head also at the top corners, whose normal is tilted about 45 degrees (not cos 45
  // of it). The normal counts fluid neighbours only: with the three wall particles above it the
  // top-left corner's would point down (wall terms -1.1 - 2 * 0.343 against fluid +1.49).
  CHECK(b.particles.pressure[Block::at(-2, 2)] == Approx(kHead).epsilon(1e-12));
  CHECK(b.particles.pressure[Block::at(2, 2)] == Approx(kHead).epsilon(1e-12));
  // The bottom row faces down (a jet's underside): no head.
  for (int i = -2; i <= 2; ++i) CHECK(b.particles.pressure[Block::at(i, -2)] == 0.0);
  // A side particle below the middle has more water above than below: no head.
  CHECK(b.particles.pressure[Block::at(-2, -1)] == 0.0);
  // A wall particle on the surface a spacing above the top row is above the water (delta - l0 < 0):
  // it stays at the spec's P = 0, though fluid lies below it.
  for (std::size_t w = b.wall; w < b.wall + 3; ++w) {
    CHECK(a.surface[w] == 1.0);
    CHECK(b.particles.pressure[w] == 0.0);
  }
  CHECK(a.solver.matrix().rows() == 9);  // the inner 3 x 3
}

TEST_CASE("mps water surface: each row beside the surface carries its known heads in b_i", "[mps][surface]") {
  // Under the spec's source the inner particles at n0 have b = 0 (spec §8), so with the offset
  // b_i = sum over surface neighbours j of a_ij P_j, a_ij = 2d/(n0 lambda) w(r_ij) (spec §2).
  const OperatorRadius radius = make_operator_radius(kL0, 2.1 * kL0, 0.01 * kL0);
  Block zero = block(radius.n0);
  Assembled spec;
  assemble(zero, radius, 0.0, spec);
  Block b = block(radius.n0);
  Assembled a;
  assemble(b, radius, 0.5 * kL0, a);
  const double c = 4.0 / (radius.n0 * radius.lambda);  // 1/m^2
  for (Eigen::Index k = 0; k < 9; ++k) CHECK(spec.solver.rhs()[k] == 0.0);
  for (int k = 0; k < 9; ++k) {
    const std::size_t i = Block::at(-1 + k % 3, -1 + k / 3);  // the unknowns in particle order
    double expected = 0.0;
    for (std::size_t j = 0; j < b.particles.size(); ++j) {
      const double r = (b.particles.position[j] - b.particles.position[i]).norm();
      if (a.surface[j] == 1.0 && r < radius.re) expected += c * (radius.re / r - 1.0) * b.particles.pressure[j];
    }
    INFO("unknown " << k);
    CHECK(a.solver.rhs()[k] == Approx(expected).epsilon(1e-12));
  }
  // By hand for (0, 1), unknown 7: the three top-row heads at l0 and sqrt(2) l0, and the two
  // side particles at 2 l0 in its row, which have more water below them than above (their
  // neighbour 2 l0 below tips the normal up: w(2 l0) = 0.05).
  const double weights = (2.1 - 1.0) + 2.0 * (2.1 / std::sqrt(2.0) - 1.0) + 2.0 * (2.1 / 2.0 - 1.0);
  CHECK(b.particles.pressure[Block::at(-2, 1)] == Approx(kHead).epsilon(1e-12));
  CHECK(a.solver.rhs()[7] == Approx(c * kHead * weights).epsilon(1e-12));
}

TEST_CASE(
    "mps water surface: the option reaches the step - the top row of still water and the wall beside it hold the head",
    "[mps][surface][cli]") {
  // scenes/hydrostatic.json (l0 = 0.025 m), one step: every fluid particle of the lattice's top
  // row is on the free surface with water below it, so it holds rho |g| l0/2 = 122.625 Pa; the
  // spec's default holds 0 there.
  for (const double offset : {0.0, 0.5}) {
    RunOptions options;
    options.scene_path = scene_path("hydrostatic.json");
    options.method = "mps";
    options.output_directory = fresh_directory(offset > 0.0 ? "water_surface_offset" : "water_surface_spec").string();
    options.overrides = {"methods.mps.free_surface_offset=" + std::to_string(offset), "time.end_time=0.001",
                         "output.frame_every_steps=1", "output.formats=[\"csv\"]"};
    const RunResult result = run_simulation(options, registries().methods, registries().walls);
    REQUIRE(result.status == "completed");
    const Table frame = read_table(std::filesystem::path(options.output_directory) / "output_000001.csv");
    const std::vector<double> type = frame.column("type"), y = frame.column("y"), p = frame.column("pressure");
    double top = -1.0;
    for (std::size_t i = 0; i < type.size(); ++i) {
      if (type[i] == 0.0) top = std::max(top, y[i]);
    }
    int top_row = 0;
    for (std::size_t i = 0; i < type.size(); ++i) {
      if (type[i] != 0.0 || y[i] < top - 0.1 * kL0) continue;
      ++top_row;
      INFO("offset " << offset << " particle " << i);
      CHECK(p[i] == Approx(offset * 1000.0 * 9.81 * kL0).epsilon(1e-9).margin(1e-9));
    }
    CHECK(top_row == 19);
    // The spec wall particles level with the top row (the pressure layer of each side wall, on the
    // free surface) hold the head of the same water surface ("The water line on the wall"): the
    // PPE sees the provisional positions, where the top row has fallen by |g| dt^2 (u* = g dt,
    // r* = r + dt u*), so rho |g| (delta - |g| dt^2); the spec's default 0.
    const double dt = read_table(std::filesystem::path(options.output_directory) / "series.csv").column("dt")[1];
    int wet_walls_at_water_line = 0;
    for (std::size_t i = 0; i < type.size(); ++i) {
      if (type[i] != 1.0 || std::abs(y[i] - top) > 0.1 * kL0 || p[i] <= 0.0) continue;
      ++wet_walls_at_water_line;
      CHECK(p[i] == Approx(1000.0 * 9.81 * (offset * kL0 - 9.81 * dt * dt)).epsilon(1e-9));
    }
    CHECK(wet_walls_at_water_line == (offset > 0.0 ? 2 : 0));
  }
}

TEST_CASE("mps water surface: an offset outside [0, 1) l0 is a one-line error naming the key", "[mps][surface][cli]") {
  for (const std::string value : {"-0.1", "1.0"}) {
    const std::string assignment = "methods.mps.free_surface_offset=" + value;
    INFO(assignment);
    CHECK_THROWS_AS(load("hydrostatic.json", {assignment}), InputError);
    CHECK_THROWS_WITH(load("hydrostatic.json", {assignment}), Catch::Contains("methods.mps.free_surface_offset"));
  }
}

TEST_CASE("mps water surface: a wall sample whose source is on the surface carries its head", "[mps][surface]") {
  // One sample in the list of (0, 1), unknown 7, at l0 below-left of it, volume 1, source the
  // top-row particle (0, 2) (a mirror image of a surface particle, as mirror_particles makes):
  // b_7 gains a_w (P_s + rho g . (x_w - x_s)), a_w = c w(sqrt(2) l0), P_s the source's head.
  const OperatorRadius radius = make_operator_radius(kL0, 2.1 * kL0, 0.01 * kL0);
  Block plain = block(radius.n0);
  Assembled without;
  assemble(plain, radius, 0.5 * kL0, without);
  Block b = block(radius.n0);
  const std::size_t owner = Block::at(0, 1), source = Block::at(0, 2);
  WallSampleList samples;
  samples.offsets.assign(b.particles.size() + 1, 0);
  for (std::size_t i = owner + 1; i < samples.offsets.size(); ++i) samples.offsets[i] = 1;
  WallSample sample;
  sample.position = b.particles.position[owner] + Vec2(-kL0, -kL0);
  sample.source = static_cast<std::uint32_t>(source);
  samples.samples.push_back(sample);
  Assembled a;
  assemble(b, radius, 0.5 * kL0, a, samples);
  const double c = 4.0 / (radius.n0 * radius.lambda);  // 1/m^2
  const double a_w = c * (2.1 / std::sqrt(2.0) - 1.0);
  const double offset = 1000.0 * -9.81 * (sample.position.y() - b.particles.position[source].y());  // Pa
  CHECK(a.solver.rhs()[7] == Approx(without.solver.rhs()[7] + a_w * (kHead + offset)).epsilon(1e-12));
  CHECK(a.solver.matrix().coeff(7, 7) == Approx(without.solver.matrix().coeff(7, 7) + a_w).epsilon(1e-12));
}

TEST_CASE("mps water line: a wall particle on the surface holds the head of the water beside it", "[mps][surface]") {
  // Wall particles in the column left of the block (column -3), each a surface particle: the head
  // rho |g| max(0, delta - Delta), Delta its height above its highest fluid neighbour within re
  // (here the top row's corner particle (-2, 2), at most sqrt(2) l0 away).
  const OperatorRadius radius = make_operator_radius(kL0, 2.1 * kL0, 0.01 * kL0);
  Block b = block(radius.n0);
  const std::size_t first = b.particles.size();
  const double rows[] = {2.0, 2.25, 2.5, 1.0};  // in l0 from the block's middle row
  for (double row : rows) {
    b.particles.add(Vec2(0.3 - 3 * kL0, 0.2 + row * kL0), Vec2::Zero(), ParticleType::Wall);
    b.number_density.push_back(0.5 * radius.n0);
  }
  b.particles.add(Vec2(0.3 - 8 * kL0, 0.2), Vec2::Zero(), ParticleType::Wall);  // no fluid within re
  b.number_density.push_back(0.5 * radius.n0);
  Assembled a;
  assemble(b, radius, 0.5 * kL0, a);
  const double rho_g = 1000.0 * 9.81;                                                   // Pa/m
  CHECK(b.particles.pressure[first] == Approx(kHead).epsilon(1e-12));                   // level with the top row
  CHECK(b.particles.pressure[first + 1] == Approx(rho_g * 0.25 * kL0).epsilon(1e-12));  // l0/4 above it
  CHECK(b.particles.pressure[first + 2] == Approx(0.0).margin(1e-9));                   // at the water surface
  CHECK(b.particles.pressure[first + 3] == Approx(rho_g * 1.5 * kL0).epsilon(1e-12));   // a row below the top
  CHECK(b.particles.pressure[first + 4] == 0.0);                                        // no fluid beside it
  for (std::size_t w = first; w < first + 5; ++w) CHECK(a.surface[w] == 1.0);
  // Without the offset every wall surface particle holds the spec's 0.
  Block spec = b;
  Assembled s;
  assemble(spec, radius, 0.0, s);
  for (std::size_t w = first; w < first + 5; ++w) CHECK(spec.particles.pressure[w] == 0.0);
  // Only fluid within the Laplacian's radius counts: a fluid particle 2.5 l0 above the wall
  // level with the top row, in a neighbour list of twice that radius, would make it 2.5 l0 deep.
  Block wide = b;
  wide.particles.add(Vec2(0.3 - 3 * kL0, 0.2 + 4.5 * kL0), Vec2::Zero(), ParticleType::Fluid);
  wide.number_density.push_back(0.1 * radius.n0);
  Assembled w;
  assemble(wide, radius, 0.5 * kL0, w, WallSampleList{}, 2.0 * radius.re);
  CHECK(wide.particles.pressure[first] == Approx(kHead).epsilon(1e-12));
}

TEST_CASE("mps water line: the dry-wall rule's level tolerance leaves out wall particles at P <= 0 beside i",
          "[mps][surface]") {
  // DryWallRule::excludes_particle (core/walls/wall_samples.hpp): a wall particle j at P_j <= 0 is
  // dry for fluid particle i when (x_j - x_i) . g < level_tolerance |g|.
  ParticleSet p;
  p.add(Vec2(0.0, 0.0), Vec2::Zero(), ParticleType::Fluid);
  const double heights[] = {0.0, -0.4, -0.6, 1.0};  // in l0 relative to i
  for (double h : heights) p.add(Vec2(kL0, h * kL0), Vec2::Zero(), ParticleType::Wall);
  p.add(Vec2(-kL0, 0.0), Vec2::Zero(), ParticleType::Wall);
  p.pressure.back() = 1.0;                                   // wet: never dry
  p.add(Vec2(0.0, kL0), Vec2::Zero(), ParticleType::Fluid);  // fluid: never dry
  const Vec2 g(0.0, -9.81);
  const DryWallRule spec_rule{true, g, 1000.0};              // tolerance 0: only those above i
  const DryWallRule water_line{true, g, 1000.0, 0.5 * kL0};  // mps with free_surface_offset 0.5
  const bool above_only[] = {false, false, false, true, false, false};
  const bool within_half[] = {true, true, false, true, false, false};
  for (std::size_t j = 1; j < p.size(); ++j) {
    INFO("neighbour " << j);
    CHECK(spec_rule.excludes_particle(p, 0, j) == above_only[j - 1]);
    CHECK(water_line.excludes_particle(p, 0, j) == within_half[j - 1]);
    CHECK_FALSE(DryWallRule{false, g, 1000.0, 0.5 * kL0}.excludes_particle(p, 0, j));
    CHECK_FALSE(DryWallRule{true, Vec2::Zero(), 1000.0, 0.5 * kL0}.excludes_particle(p, 0, j));  // no gravity
  }
}

TEST_CASE("mps water line: the method's dry-wall rule takes the water surface's offset as its level tolerance",
          "[mps][surface]") {
  // dry_wall_rule (methods/mps/mps_pressure.hpp), which the method builds its rule with: with the
  // offset delta a wall particle at P <= 0 0.4 l0 below fluid particle i is dry, with the spec's
  // surface (delta = 0) only one above i.
  ParticleSet p;
  p.add(Vec2(0.0, 0.0), Vec2::Zero(), ParticleType::Fluid);
  p.add(Vec2(kL0, -0.4 * kL0), Vec2::Zero(), ParticleType::Wall);
  p.add(Vec2(kL0, kL0), Vec2::Zero(), ParticleType::Wall);
  PressureSolveSettings settings;
  settings.gravity = Vec2(0.0, -9.81);
  settings.density = 998.0;
  settings.surface_offset = 0.5 * kL0;
  const DryWallRule water_line = dry_wall_rule(true, settings);
  CHECK(water_line.exclude);
  CHECK(water_line.level_tolerance == 0.5 * kL0);
  CHECK(water_line.density == 998.0);
  CHECK(water_line.gravity == settings.gravity);
  CHECK(water_line.excludes_particle(p, 0, 1));
  CHECK(water_line.excludes_particle(p, 0, 2));
  CHECK_FALSE(dry_wall_rule(false, settings).excludes_particle(p, 0, 1));
  settings.surface_offset = 0.0;
  const DryWallRule spec_surface = dry_wall_rule(true, settings);
  CHECK(spec_surface.level_tolerance == 0.0);
  CHECK_FALSE(spec_surface.excludes_particle(p, 0, 1));
  CHECK(spec_surface.excludes_particle(p, 0, 2));
}
