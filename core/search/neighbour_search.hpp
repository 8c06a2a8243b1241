#pragma once
// Neighbour search. CellList is the production search: a cell-linked list ("bucket")
// over the bounding box of the active particles, O(N) to build and to query, queried in
// parallel with OpenMP. brute_force_neighbours is the O(N^2) reference kept for tests.
//
// Performance (docs/performance.md): build() keeps a copy of the positions in cell order, so
// a query scans three contiguous runs of memory (the three cells of a stencil row are
// neighbours in that order); the query makes one distance pass, each thread writing the
// lists of its block of particles into its own buffer, which is then copied into place.
// All buffers are kept between calls: a search in the time loop allocates nothing once the
// particle count has been reached.
//
// A neighbour list holds, for every particle i that is not a ghost, the indices j != i of
// the non-ghost particles with |x_j - x_i| < radius (strictly: every kernel here vanishes
// at r = radius). Lists are in a deterministic order (cell by cell, then by index), so the
// same input gives the same sums whatever the number of threads.
#include <cstdint>
#include <vector>

#include "core/base/types.hpp"

namespace mps_lab {

// Compressed-row storage: neighbours of i are indices[offsets[i] .. offsets[i+1]).
struct NeighbourList {
  std::vector<std::uint32_t> offsets;  // size N + 1
  std::vector<std::uint32_t> indices;
  double radius = 0.0;  // m

  std::size_t particle_count() const { return offsets.empty() ? 0 : offsets.size() - 1; }
  std::uint32_t begin(std::size_t i) const { return offsets[i]; }
  std::uint32_t end(std::size_t i) const { return offsets[i + 1]; }
  std::uint32_t count(std::size_t i) const { return offsets[i + 1] - offsets[i]; }
  std::uint32_t max_count() const;
};

class CellList {
 public:
  // Bins the non-ghost particles into square cells of side `cell_size` (>= the query radius).
  void build(const std::vector<Vec2>& positions, const std::vector<ParticleType>& types, double cell_size);
  // Fills `out` (its storage is reused between calls) with the neighbours within `radius`.
  // `radius` must not exceed the cell size given to build().
  void find_neighbours(const std::vector<Vec2>& positions, const std::vector<ParticleType>& types, double radius,
                       NeighbourList& out);

  double cell_size() const { return cell_size_; }
  int cells_x() const { return cells_x_; }
  int cells_y() const { return cells_y_; }
  // Heap held between searches, bytes (capacities; `mps_lab bench`'s memory breakdown).
  std::size_t held_bytes() const;

 private:
  std::int64_t cell_of(const Vec2& x) const;
  double cell_size_ = 0.0;
  Vec2 origin_ = Vec2::Zero();
  int cells_x_ = 0;
  int cells_y_ = 0;
  std::vector<std::uint32_t> cell_start_;                 // size cells + 1
  std::vector<std::uint32_t> sorted_;                     // particle indices sorted by cell, stable
  std::vector<std::int64_t> particle_cell_;               // -1 for ghosts
  std::vector<Vec2> sorted_positions_;                    // positions[sorted_[k]], m
  std::vector<std::uint32_t> fill_;                       // counting-sort cursor per cell
  std::vector<std::vector<std::uint32_t>> thread_lists_;  // per-thread neighbour buffers
};

NeighbourList brute_force_neighbours(const std::vector<Vec2>& positions, const std::vector<ParticleType>& types,
                                     double radius);

// Convenience: build a cell list with cell size = radius and return the neighbour list.
NeighbourList find_neighbours(const std::vector<Vec2>& positions, const std::vector<ParticleType>& types,
                              double radius);

}  // namespace mps_lab
