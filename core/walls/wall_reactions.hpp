#pragma once
// The fluid's reaction on wall particles: for every wall particle j, minus the sum over its
// fluid neighbours i of the force (N/m) the pair term of a method's operator gives i from j.
// One pass over the wall particles, each writing only its own entry (no write races); the
// same pair function as the fluid side's operator, so the two are equal and opposite by
// construction (docs/walls.md, "Loads on obstacles").
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/base/particles.hpp"
#include "core/search/for_each_neighbour.hpp"
#include "core/search/neighbour_search.hpp"

namespace mps_lab {

// reaction[j] -= sum_i pair_force(i, j) for every wall particle j over its fluid neighbours i
// (the list must hold j's row: every non-ghost particle has one). `pair_force(i, j)`: the force
// on fluid particle i from wall particle j, N/m. reaction has one entry per particle.
template <typename PairForce>
void add_wall_reactions(const ParticleSet& particles, const NeighbourList& neighbours, PairForce&& pair_force,
                        std::vector<Vec2>& reaction) {
  reaction.resize(particles.size(), Vec2::Zero());
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t j = 0; j < n; ++j) {
    if (particles.type[j] != ParticleType::Wall) continue;
    Vec2 sum = Vec2::Zero();
    for_each_neighbour(neighbours, j, [&](std::uint32_t i) {
      if (particles.type[i] == ParticleType::Fluid) sum += pair_force(i, static_cast<std::size_t>(j));
    });
    reaction[j] -= sum;
  }
}

}  // namespace mps_lab
