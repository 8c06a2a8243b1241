// Cell-ordered particles (core/search/cell_order.hpp, core/base/particle_order.hpp): the
// counting sort, moving every per-particle array, the neighbour lists and wall samples a method
// keeps, and the run.sort_period key. The runs with reordering against runs without are in the
// contract suite (tests/test_contract.cpp), resuming across a reordering too.
#include <algorithm>
#include <cmath>
#include <numeric>
#include <random>

#include <catch2/catch.hpp>

#include "core/base/error.hpp"
#include "core/io/checkpoint.hpp"
#include "core/search/cell_order.hpp"
#include "core/search/neighbour_search.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

namespace {

struct RandomSet {
  std::vector<Vec2> positions;
  std::vector<ParticleType> types;
};

// n particles in [0, 1] x [0, 0.5] m, every seventh a ghost (at an absurd position, which the
// sort must ignore).
RandomSet random_set(std::size_t n, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> x(0.0, 1.0), y(0.0, 0.5);
  RandomSet set;
  for (std::size_t i = 0; i < n; ++i) {
    const bool ghost = i % 7 == 3;
    set.positions.emplace_back(ghost ? Vec2(1e30, -1e30) : Vec2(x(random), y(random)));
    set.types.push_back(ghost ? ParticleType::Ghost : (i % 5 == 0 ? ParticleType::Wall : ParticleType::Fluid));
  }
  return set;
}

// The cell number of the ordering (row-major from the lower left of the non-ghosts' box).
std::int64_t cell_number(const Vec2& x, const Vec2& origin, double size, std::int64_t cells_x) {
  return static_cast<std::int64_t>(std::floor((x.y() - origin.y()) / size)) * cells_x +
         static_cast<std::int64_t>(std::floor((x.x() - origin.x()) / size));
}

// A set whose every array holds values that name the particle: particle i at (i, 10 i) m, ...
ParticleSet recognisable_set(std::size_t n) {
  ParticleSet set;
  set.add_field("marker");
  for (std::size_t i = 0; i < n; ++i) {
    const auto v = static_cast<double>(i);
    set.add(Vec2(v, 10.0 * v), Vec2(-v, 0.5 * v), i % 3 == 0 ? ParticleType::Wall : ParticleType::Fluid,
            static_cast<std::uint8_t>(i % 4));
    set.pressure.back() = 100.0 + v;
  }
  set.field("marker") = std::vector<double>(n);
  std::iota(set.field("marker").begin(), set.field("marker").end(), 1000.0);
  set.wall_velocity.resize(n);
  set.wall_acceleration.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    set.wall_velocity[i] = Vec2(2000.0 + static_cast<double>(i), 0.0);
    set.wall_acceleration[i] = Vec2(0.0, 3000.0 + static_cast<double>(i));
  }
  return set;
}

}  // namespace

TEST_CASE("cell order is a stable permutation in cell-major order with the ghosts last", "[cell_order]") {
  const double size = 0.1;  // m: 10 x 5 cells over the box
  const RandomSet set = random_set(2000, 7);
  const ParticleOrder order = cell_order(set.positions, set.types, size);
  REQUIRE(order.size() == set.positions.size());
  // A permutation: every old index once, and new_index its inverse.
  std::vector<std::uint32_t> sorted = order.old_index;
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t k = 0; k < sorted.size(); ++k) REQUIRE(sorted[k] == k);
  for (std::size_t k = 0; k < order.size(); ++k) REQUIRE(order.new_index[order.old_index[k]] == k);

  Vec2 origin(1e300, 1e300);
  double max_x = -1e300;
  for (std::size_t i = 0; i < set.positions.size(); ++i) {
    if (set.types[i] == ParticleType::Ghost) continue;
    origin = origin.cwiseMin(set.positions[i]);
    max_x = std::max(max_x, set.positions[i].x());
  }
  const auto cells_x = static_cast<std::int64_t>((max_x - origin.x()) / size + 1.0);
  std::size_t ghosts = 0;
  for (std::size_t k = 1; k < order.size(); ++k) {
    const std::uint32_t before = order.old_index[k - 1], here = order.old_index[k];
    INFO("new index " << k);
    if (set.types[here] == ParticleType::Ghost) {
      ++ghosts;
      if (set.types[before] == ParticleType::Ghost) REQUIRE(before < here);  // ghosts in their old order
      continue;
    }
    REQUIRE(set.types[before] != ParticleType::Ghost);  // no particle after a ghost
    const auto a = cell_number(set.positions[before], origin, size, cells_x);
    const auto b = cell_number(set.positions[here], origin, size, cells_x);
    REQUIRE(a <= b);                     // cell-major
    if (a == b) REQUIRE(before < here);  // stable within a cell
  }
  CHECK(ghosts == 2000 / 7 + (2000 % 7 > 3 ? 1 : 0));
}

TEST_CASE("cell order of four particles by hand - and of empty and one-particle sets", "[cell_order]") {
  // Box from (0.1, 0.1) to (1.5, 1.5), cells of 1 m: 2 x 2 cells. Particles 1 and 3 are in cell 0
  // (stable: 1 before 3), particle 0 in cell 1 (x in [1.1, 2.1)), particle 2 in cell 2.
  const std::vector<Vec2> positions = {Vec2(1.5, 0.2), Vec2(0.2, 0.2), Vec2(0.3, 1.5), Vec2(0.1, 0.1)};
  const std::vector<ParticleType> fluid(4, ParticleType::Fluid);
  CHECK(cell_order(positions, fluid, 1.0).old_index == std::vector<std::uint32_t>{1, 3, 0, 2});
  CHECK(cell_order(positions, fluid, 1.0).new_index == std::vector<std::uint32_t>{2, 0, 3, 1});

  CHECK(cell_order({}, {}, 0.1).size() == 0);
  const ParticleOrder one = cell_order({Vec2(0.3, 0.4)}, {ParticleType::Fluid}, 0.1);
  CHECK(one.old_index == std::vector<std::uint32_t>{0});
  CHECK(one.is_identity());
  // Only ghosts: nothing to order, their order is kept.
  CHECK(cell_order({Vec2(5.0, 5.0), Vec2(0.0, 0.0)}, {ParticleType::Ghost, ParticleType::Ghost}, 0.1).is_identity());
  CHECK_THROWS_AS(cell_order(positions, fluid, 0.0), std::invalid_argument);
  CHECK_THROWS_AS(cell_order({Vec2(NAN, 0.0)}, {ParticleType::Fluid}, 0.1), std::runtime_error);
  CHECK_THROWS_AS(ParticleOrder::from_old_indices({0, 2, 2}), std::logic_error);
  CHECK_THROWS_AS(ParticleOrder::from_old_indices({0, 3, 1}), std::logic_error);
}

TEST_CASE("permute_particles moves every per-particle array and the ids", "[cell_order]") {
  const std::size_t n = 9;
  ParticleSet set = recognisable_set(n);
  const ParticleOrder order = ParticleOrder::from_old_indices({4, 8, 0, 3, 7, 1, 6, 2, 5});
  permute_particles(set, order);
  for (std::size_t k = 0; k < n; ++k) {
    const std::uint32_t i = order.old_index[k];
    const auto v = static_cast<double>(i);
    INFO("new index " << k << ", old index " << i);
    CHECK(set.position[k] == Vec2(v, 10.0 * v));
    CHECK(set.velocity[k] == Vec2(-v, 0.5 * v));
    CHECK(set.pressure[k] == 100.0 + v);
    CHECK(set.type[k] == (i % 3 == 0 ? ParticleType::Wall : ParticleType::Fluid));
    CHECK(set.wall_layer[k] == i % 4);
    CHECK(set.wall_velocity[k].x() == 2000.0 + v);
    CHECK(set.wall_acceleration[k].y() == 3000.0 + v);
    CHECK(set.field("marker")[k] == 1000.0 + v);
    CHECK(set.id[k] == i);
  }
  // In id order the set is the original one; moving it back restores every bit.
  const std::vector<std::uint32_t> by_id = indices_in_id_order(set);
  for (std::size_t d = 0; d < n; ++d) CHECK(set.id[by_id[d]] == d);
  permute_particles(set, ParticleOrder::from_old_indices(by_id));
  const ParticleSet original = recognisable_set(n);
  CHECK(set.position == original.position);
  CHECK(set.pressure == original.pressure);
  CHECK(set.id == original.id);
  CHECK(set.scalar_fields == original.scalar_fields);
  // Unused optional arrays stay empty; a mismatched order is a programming error.
  ParticleSet fixed_walls;
  fixed_walls.add(Vec2::Zero(), Vec2::Zero(), ParticleType::Fluid);
  fixed_walls.add(Vec2::Ones(), Vec2::Zero(), ParticleType::Fluid);
  permute_particles(fixed_walls, ParticleOrder::from_old_indices({1, 0}));
  CHECK(fixed_walls.wall_velocity.empty());
  CHECK(fixed_walls.id == std::vector<std::uint32_t>{1, 0});
  CHECK_THROWS_AS(permute_particles(fixed_walls, ParticleOrder::from_old_indices({0, 1, 2})), std::logic_error);
}

TEST_CASE("a kept neighbour list and wall samples follow a reordering entry for entry", "[cell_order]") {
  RandomSet set = random_set(600, 11);
  const double radius = 0.06;  // m: about 8 neighbours a particle
  NeighbourList list = find_neighbours(set.positions, set.types, radius);
  const NeighbourList before = list;
  WallSampleList samples;
  samples.offsets.push_back(0);
  for (std::size_t i = 0; i < set.positions.size(); ++i) {  // i % 3 samples of source (i + 1) % n
    for (std::size_t s = 0; s < i % 3; ++s) {
      WallSample sample;
      sample.position = Vec2(static_cast<double>(i), static_cast<double>(s));
      sample.source = static_cast<std::uint32_t>((i + 1) % set.positions.size());
      samples.samples.push_back(sample);
    }
    samples.offsets.push_back(static_cast<std::uint32_t>(samples.samples.size()));
  }
  const WallSampleList samples_before = samples;

  const ParticleOrder order = cell_order(set.positions, set.types, 0.12);
  REQUIRE_FALSE(order.is_identity());
  permute_neighbour_list(list, order);
  permute_wall_samples(samples, order);
  permute_values(set.positions, order);
  permute_values(set.types, order);
  CHECK(list.radius == before.radius);
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::uint32_t i = order.old_index[k];
    INFO("new index " << k);
    // The same neighbours in the same order (every sum over them adds the same terms in turn).
    REQUIRE(list.count(k) == before.count(i));
    for (std::uint32_t e = 0; e < list.count(k); ++e) {
      REQUIRE(list.indices[list.begin(k) + e] == order.new_index[before.indices[before.begin(i) + e]]);
    }
    REQUIRE(samples.end(k) - samples.begin(k) == samples_before.end(i) - samples_before.begin(i));
    for (std::uint32_t e = 0; e < samples.end(k) - samples.begin(k); ++e) {
      const WallSample& moved = samples.samples[samples.begin(k) + e];
      const WallSample& was = samples_before.samples[samples_before.begin(i) + e];
      REQUIRE(moved.position == was.position);
      REQUIRE(moved.source == order.new_index[was.source]);
    }
  }
  // And it is the neighbour list of the reordered particles (as sets; the search's own order
  // within a row differs).
  const NeighbourList fresh = find_neighbours(set.positions, set.types, radius);
  for (std::size_t k = 0; k < order.size(); ++k) {
    std::vector<std::uint32_t> a(list.indices.begin() + list.begin(k), list.indices.begin() + list.end(k));
    std::vector<std::uint32_t> b(fresh.indices.begin() + fresh.begin(k), fresh.indices.begin() + fresh.end(k));
    std::sort(a.begin(), a.end());
    std::sort(b.begin(), b.end());
    REQUIRE(a == b);
  }
  // A boundary model of wall particles keeps no samples: nothing to move.
  WallSampleList none;
  permute_wall_samples(none, order);
  CHECK_FALSE(none.has_samples());
}

TEST_CASE("run.sort_period - default and bad values are one-line errors naming the key", "[cell_order]") {
  CHECK(load("dambreak.json").run.sort_period == kDefaultSortPeriod);
  CHECK(load("dambreak.json", {"run.sort_period=0"}).run.sort_period == 0);
  CHECK(load("dambreak.json", {"run.sort_period=200"}).run.sort_period == 200);
  for (const std::string bad : {"-1", "2.5", "\"often\"", "true"}) {
    INFO("run.sort_period=" << bad);
    try {
      load("dambreak.json", {"run.sort_period=" + bad});
      FAIL("accepted");
    } catch (const InputError& error) {
      const std::string message = error.what();
      CHECK(message.find("run.sort_period") != std::string::npos);
      CHECK(message.find('\n') == std::string::npos);
    }
  }
  try {
    load("dambreak.json", {"run.sort_every=10"});
    FAIL("accepted an unknown key");
  } catch (const InputError& error) {
    CHECK(std::string(error.what()).find("run.sort_every") != std::string::npos);
  }
}

TEST_CASE("the particles' order is in the checkpoint - ids that are no permutation are an error", "[cell_order]") {
  ParticleSet saved = recognisable_set(5);
  permute_particles(saved, ParticleOrder::from_old_indices({3, 0, 4, 1, 2}));
  CheckpointWriter writer;
  writer.begin_section("particles");
  write_particles(writer, saved);
  writer.end_section();
  {
    CheckpointReader reader(writer.file_content("rev"), "run/checkpoint.bin", "rev");
    ParticleSet restored = recognisable_set(5);  // as a fresh Simulation builds it: index = id
    reader.begin_section("particles");
    read_particles(reader, restored);
    reader.end_section();
    CHECK(restored.id == std::vector<std::uint32_t>{3, 0, 4, 1, 2});
    CHECK(restored.position == saved.position);
    CHECK(restored.field("marker") == saved.field("marker"));
  }
  saved.id[2] = 3;  // particle 3 twice, particle 4 missing
  CheckpointWriter broken;
  broken.begin_section("particles");
  write_particles(broken, saved);
  broken.end_section();
  CheckpointReader reader(broken.file_content("rev"), "run/checkpoint.bin", "rev");
  ParticleSet restored = recognisable_set(5);
  reader.begin_section("particles");
  try {
    read_particles(reader, restored);
    FAIL("accepted");
  } catch (const InputError& error) {
    const std::string message = error.what();
    CHECK_THAT(message, Catch::StartsWith("run/checkpoint.bin") &&
                            Catch::Contains("particle ids that are not a permutation of 0..4"));
    CHECK(message.find('\n') == std::string::npos);
  }
}
