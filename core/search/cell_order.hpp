#pragma once
// Cell-ordered particles (issue 17, item 2). A long run mixes the particles: neighbours in
// space drift apart in memory, and the neighbour search and every operator's gather over
// neighbours read scattered memory. The driver therefore reorders the particles by cell every
// run.sort_period steps (core/run/driver.cpp, Simulation::advance): cell_order gives the order,
// permute_particles (core/base/particles.hpp) moves the ParticleSet, and each method moves what
// it keeps per particle between steps (Method::permute_state) with permute_values and the two
// helpers below.
#include <vector>

#include "core/base/particle_order.hpp"
#include "core/base/types.hpp"
#include "core/search/neighbour_search.hpp"
#include "core/walls/wall_samples.hpp"

namespace mps_lab {

// The particles in cell-major order: square cells of side `cell_size` (m, > 0) over the
// bounding box of the non-ghost particles, numbered row by row from the lower left (cell
// (ix, iy) has number iy * cells_x + ix); a stable counting sort, so that within a cell the
// particles keep their present order; ghosts after every other particle, in their present order.
// Deterministic and independent of the thread count. Throws std::runtime_error on a non-finite
// position of a non-ghost particle (as the neighbour search does).
ParticleOrder cell_order(const std::vector<Vec2>& positions, const std::vector<ParticleType>& types, double cell_size);

// A neighbour list kept across a reordering: row k becomes the old row old_index[k], its
// entries renumbered, in the same order (every sum over it then adds the same terms in the same
// order as before the reordering).
void permute_neighbour_list(NeighbourList& list, const ParticleOrder& order);

// Wall samples kept across a reordering: rows moved as the neighbour list's, every sample's
// source particle renumbered. Nothing to do when the list is empty (a boundary model of wall
// particles).
void permute_wall_samples(WallSampleList& samples, const ParticleOrder& order);

}  // namespace mps_lab
