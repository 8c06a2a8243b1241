#pragma once
// The neighbour loop of every operator, written once: particle i's neighbours j from the CSR
// neighbour list (core/search/neighbour_search.hpp), and i's wall samples w from the boundary
// model's list (core/walls/wall_samples.hpp; none when the boundary is made of particles).
//
//   for_each_neighbour(neighbours, i, [&](std::uint32_t j) { sum += ...; });
//   for_each_neighbour(samples, i, [&](const WallSample& wall) { sum += ...; });
//
// Inline templates taking the loop body as a lambda: the compiler inlines the body into the
// same loop as the hand-written one (docs/performance.md, "The neighbour loop as a helper":
// the dam break's wall time before and after). A `return` in the body skips to the next
// neighbour, as `continue` did.
#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "core/base/particles.hpp"
#include "core/search/neighbour_search.hpp"
#include "core/walls/wall_samples.hpp"

namespace mps_lab {

// visit(j) for every neighbour j of particle i (ghosts included: the body filters), or
// visit(k, j) with k the pair's index in the list (for per-pair arrays such as DFSPH's
// stored kernel gradients).
template <typename Visit>
inline void for_each_neighbour(const NeighbourList& neighbours, std::size_t i, Visit&& visit) {
  const std::uint32_t end = neighbours.end(i);
  for (std::uint32_t k = neighbours.begin(i); k < end; ++k) {
    if constexpr (std::is_invocable_v<Visit&, std::uint32_t, std::uint32_t>) {
      visit(k, neighbours.indices[k]);
    } else {
      visit(neighbours.indices[k]);
    }
  }
}

// visit(wall), or visit(k, wall) with k the sample's index in the list, for every wall
// sample of particle i; nothing when the list has no samples.
template <typename Visit>
inline void for_each_neighbour(const WallSampleList& samples, std::size_t i, Visit&& visit) {
  if (!samples.has_samples()) return;
  const std::uint32_t end = samples.end(i);
  for (std::uint32_t k = samples.begin(i); k < end; ++k) {
    if constexpr (std::is_invocable_v<Visit&, std::uint32_t, const WallSample&>) {
      visit(k, samples.samples[k]);
    } else {
      visit(samples.samples[k]);
    }
  }
}

// visit(i) for every fluid particle i, in parallel (OpenMP, static schedule: each thread
// writes only what belongs to its own particles). A `return` in the body skips to the next
// particle, as `continue` did.
template <typename Visit>
inline void for_each_fluid_particle(const ParticleSet& particles, Visit&& visit) {
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (particles.type[i] != ParticleType::Fluid) continue;
    visit(i);
  }
}

// Whether pred(j) holds for some neighbour j of particle i (stops at the first).
template <typename Predicate>
inline bool any_neighbour(const NeighbourList& neighbours, std::size_t i, Predicate&& pred) {
  const std::uint32_t end = neighbours.end(i);
  for (std::uint32_t k = neighbours.begin(i); k < end; ++k) {
    if (pred(neighbours.indices[k])) return true;
  }
  return false;
}

}  // namespace mps_lab
