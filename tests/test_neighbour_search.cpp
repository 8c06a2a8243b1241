// Cell-list neighbour search against the brute-force reference.
#include <algorithm>
#include <random>

#include <catch2/catch.hpp>

#include "core/search/neighbour_search.hpp"

using namespace mps_lab;

namespace {

// Neighbour sets must be equal as sets (the cell list orders by cell, brute force by index).
void require_same_lists(const NeighbourList& a, const NeighbourList& b) {
  REQUIRE(a.particle_count() == b.particle_count());
  std::size_t pairs = 0;
  for (std::size_t i = 0; i < a.particle_count(); ++i) {
    std::vector<std::uint32_t> la(a.indices.begin() + a.begin(i), a.indices.begin() + a.end(i));
    std::vector<std::uint32_t> lb(b.indices.begin() + b.begin(i), b.indices.begin() + b.end(i));
    std::sort(la.begin(), la.end());
    std::sort(lb.begin(), lb.end());
    INFO("particle " << i);
    REQUIRE(la == lb);
    pairs += la.size();
  }
  CHECK(pairs == a.indices.size());
}

}  // namespace

TEST_CASE("cell list equals brute force on random particles", "[neighbours]") {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> coordinate(-0.3, 1.7);
  for (int trial = 0; trial < 5; ++trial) {
    std::vector<Vec2> x(800);
    std::vector<ParticleType> type(800, ParticleType::Fluid);
    for (auto& p : x) p = Vec2(coordinate(rng), 0.5 * coordinate(rng));
    for (std::size_t i = 0; i < type.size(); i += 7) type[i] = ParticleType::Wall;
    for (std::size_t i = 3; i < type.size(); i += 11) type[i] = ParticleType::Ghost;
    const double radius = 0.0525 + 0.02 * trial;
    const NeighbourList cells = find_neighbours(x, type, radius);
    const NeighbourList brute = brute_force_neighbours(x, type, radius);
    require_same_lists(cells, brute);
    // Ghosts have no neighbours and are nobody's neighbour.
    for (std::size_t i = 3; i < type.size(); i += 11) CHECK(cells.count(i) == 0);
    for (auto j : cells.indices) CHECK(type[j] != ParticleType::Ghost);
  }
}

TEST_CASE("cell list equals brute force on a lattice - with particles exactly on cell edges", "[neighbours]") {
  // Lattice spacing 0.025 and radius (= cell size) 2 l0: many pairs lie exactly on the
  // radius and many particles exactly on cell boundaries. Pairs at exactly r = radius are
  // excluded by both searches (kernels vanish there).
  const double l0 = 0.025;
  std::vector<Vec2> x;
  for (int j = -2; j <= 24; ++j) {
    for (int i = -2; i <= 42; ++i) x.emplace_back(i * l0, j * l0);
  }
  std::vector<ParticleType> type(x.size(), ParticleType::Fluid);
  for (double radius : {2.0 * l0, 2.1 * l0, 1.0 * l0, 3.0 * l0}) {
    const NeighbourList cells = find_neighbours(x, type, radius);
    const NeighbourList brute = brute_force_neighbours(x, type, radius);
    require_same_lists(cells, brute);
  }
  // An interior particle at radius 2.1 l0 has exactly the 12 lattice neighbours of n0.
  const NeighbourList list = find_neighbours(x, type, 2.1 * l0);
  const std::size_t interior = 10 * 45 + 20;
  CHECK(list.count(interior) == 12);
  // Corner particle of the block (domain edge): 5 neighbours (2 at l0, 1 at sqrt2 l0, 2 at 2 l0).
  CHECK(list.count(0) == 5);
}

TEST_CASE("cell list handles degenerate sets", "[neighbours]") {
  std::vector<Vec2> x = {Vec2(0.5, 0.5)};
  std::vector<ParticleType> type = {ParticleType::Fluid};
  CHECK(find_neighbours(x, type, 0.1).indices.empty());
  // Two coincident particles are neighbours of each other.
  x.push_back(Vec2(0.5, 0.5));
  type.push_back(ParticleType::Fluid);
  CHECK(find_neighbours(x, type, 0.1).indices.size() == 2);
  // All ghosts: nothing, and no crash.
  std::fill(type.begin(), type.end(), ParticleType::Ghost);
  CHECK(find_neighbours(x, type, 0.1).indices.empty());
  // The same input gives the same order whatever the thread count (lists are rebuilt deterministically).
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec2> y(2000);
  for (auto& p : y) p = Vec2(u(rng), u(rng));
  std::vector<ParticleType> fluid(y.size(), ParticleType::Fluid);
  const NeighbourList first = find_neighbours(y, fluid, 0.04);
  const NeighbourList second = find_neighbours(y, fluid, 0.04);
  CHECK(first.indices == second.indices);
  CHECK(first.offsets == second.offsets);
}
