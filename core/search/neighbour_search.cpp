#include "core/search/neighbour_search.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <omp.h>

#include "core/base/memory_bytes.hpp"

namespace mps_lab {

std::size_t CellList::held_bytes() const {
  std::size_t bytes = mps_lab::held_bytes(cell_start_, sorted_, particle_cell_, sorted_positions_, fill_);
  for (const auto& list : thread_lists_) bytes += mps_lab::held_bytes(list);
  return bytes;
}

std::uint32_t NeighbourList::max_count() const {
  std::uint32_t largest = 0;
  for (std::size_t i = 0; i + 1 < offsets.size(); ++i) largest = std::max(largest, count(i));
  return largest;
}

std::int64_t CellList::cell_of(const Vec2& x) const {
  // Clamped to the interior: rounding can put the extreme particles a hair into the padding,
  // and the 3x3 stencil must stay inside the grid. Shifting a particle lying on a cell
  // boundary to the neighbouring cell loses no pair, since the cell size is >= the radius.
  auto ix = static_cast<std::int64_t>(std::floor((x.x() - origin_.x()) / cell_size_));
  auto iy = static_cast<std::int64_t>(std::floor((x.y() - origin_.y()) / cell_size_));
  ix = std::clamp<std::int64_t>(ix, 1, cells_x_ - 2);
  iy = std::clamp<std::int64_t>(iy, 1, cells_y_ - 2);
  return iy * cells_x_ + ix;
}

void CellList::build(const std::vector<Vec2>& positions, const std::vector<ParticleType>& types, double cell_size) {
  if (!(cell_size > 0.0)) throw std::invalid_argument("CellList: cell size must be > 0");
  cell_size_ = cell_size;
  const std::size_t n = positions.size();

  // Bounding box of the active particles (non-finite positions are the caller's to ghost).
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -min_x, max_y = -min_x;
#pragma omp parallel for reduction(min : min_x, min_y) reduction(max : max_x, max_y)
  for (std::size_t i = 0; i < n; ++i) {
    if (types[i] == ParticleType::Ghost) continue;
    min_x = std::min(min_x, positions[i].x());
    min_y = std::min(min_y, positions[i].y());
    max_x = std::max(max_x, positions[i].x());
    max_y = std::max(max_y, positions[i].y());
  }
  if (!(min_x <= max_x)) {  // no active particle
    min_x = min_y = max_x = max_y = 0.0;
  }
  if (!std::isfinite(min_x) || !std::isfinite(min_y) || !std::isfinite(max_x) || !std::isfinite(max_y)) {
    throw std::runtime_error("neighbour search: a particle has a non-finite position");
  }
  // One empty cell of padding on every side keeps the 3x3 stencil inside the grid.
  origin_ = Vec2(min_x - cell_size, min_y - cell_size);
  const double span_x = (max_x - min_x) / cell_size + 3.0;
  const double span_y = (max_y - min_y) / cell_size + 3.0;
  if (span_x * span_y > 1e9) {
    throw std::runtime_error("neighbour search: particles spread over " + std::to_string(span_x * span_y) +
                             " cells; particles are escaping the domain");
  }
  cells_x_ = static_cast<int>(span_x) + 1;
  cells_y_ = static_cast<int>(span_y) + 1;
  const auto cells = static_cast<std::size_t>(cells_x_) * static_cast<std::size_t>(cells_y_);

  particle_cell_.resize(n);
#pragma omp parallel for
  for (std::size_t i = 0; i < n; ++i) {
    particle_cell_[i] = types[i] == ParticleType::Ghost ? -1 : cell_of(positions[i]);
  }
  // Counting sort by cell (stable: within a cell, particles stay in index order).
  assign_with_headroom(cell_start_, cells + 1, 0u);
  for (std::size_t i = 0; i < n; ++i) {
    if (particle_cell_[i] >= 0) ++cell_start_[static_cast<std::size_t>(particle_cell_[i]) + 1];
  }
  for (std::size_t c = 0; c < cells; ++c) cell_start_[c + 1] += cell_start_[c];
  resize_with_headroom(sorted_, cell_start_[cells]);
  resize_with_headroom(sorted_positions_, cell_start_[cells]);
  fill_.assign(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t i = 0; i < n; ++i) {
    if (particle_cell_[i] < 0) continue;
    const std::uint32_t slot = fill_[static_cast<std::size_t>(particle_cell_[i])]++;
    sorted_[slot] = static_cast<std::uint32_t>(i);
    sorted_positions_[slot] = positions[i];
  }
}

void CellList::find_neighbours(const std::vector<Vec2>& positions, const std::vector<ParticleType>& types,
                               double radius, NeighbourList& out) {
  if (radius > cell_size_ * (1.0 + 1e-12)) {
    throw std::invalid_argument("CellList: query radius exceeds the cell size");
  }
  const std::size_t n = positions.size();
  const double radius2 = radius * radius;
  out.radius = radius;
  out.offsets.resize(n + 1);
  out.offsets[0] = 0;

  // The neighbours of i in a fixed order: stencil rows bottom to top, and in each row the
  // three cells left to right, which are one contiguous run of the cell-sorted arrays
  // (particles by index within a cell). Branch-free: every candidate is written at the
  // list's end, and the end advances only past a neighbour (about a third of the candidates
  // pass, at random, so a branch would be mispredicted often; docs/performance.md). `used`
  // is the list's length; its storage is kept at least `used` + one row's candidates long
  // (grown by an eighth: the storage is held between searches and counted in the memory).
  const auto append_neighbours = [&](std::size_t i, std::vector<std::uint32_t>& list, std::size_t& used) {
    const std::int64_t cell = particle_cell_[i];
    const std::int64_t cx = cell % cells_x_;
    const std::int64_t cy = cell / cells_x_;
    const Vec2 xi = positions[i];
    const auto self = static_cast<std::uint32_t>(i);
    for (std::int64_t dy = -1; dy <= 1; ++dy) {
      const auto row = static_cast<std::size_t>((cy + dy) * cells_x_ + cx);
      const std::uint32_t first = cell_start_[row - 1];
      const std::uint32_t last = cell_start_[row + 2];
      const std::size_t needed = used + (last - first);
      if (list.size() < needed) list.resize(needed + needed / 8 + 64);  // 1/8 headroom: capacity near the list's size
      std::uint32_t* end = list.data() + used;
      for (std::uint32_t k = first; k < last; ++k) {
        const std::uint32_t j = sorted_[k];
        *end = j;
        end += static_cast<std::size_t>(((sorted_positions_[k] - xi).squaredNorm() < radius2) & (j != self));
      }
      used = static_cast<std::size_t>(end - list.data());
    }
  };

  // One distance pass: thread t lists the neighbours of its block [begin_t, end_t) of
  // particles into thread_lists_[t] and the counts into offsets; after a prefix sum each
  // block is copied into place. Thread 0's block begins at entry 0, so it lists straight into
  // out.indices (no copy of it is held: docs/performance.md, "Memory"). The lists do not
  // depend on the number of threads.
#pragma omp parallel
  {
    const auto threads = static_cast<std::size_t>(omp_get_num_threads());
    const auto thread = static_cast<std::size_t>(omp_get_thread_num());
#pragma omp single
    if (thread_lists_.size() < threads) thread_lists_.resize(threads);
    const std::size_t begin = n * thread / threads;
    const std::size_t end = n * (thread + 1) / threads;
    std::vector<std::uint32_t>& list = thread == 0 ? out.indices : thread_lists_[thread];
    std::size_t used = 0;
    for (std::size_t i = begin; i < end; ++i) {
      const std::size_t before = used;
      if (types[i] != ParticleType::Ghost) append_neighbours(i, list, used);
      out.offsets[i + 1] = static_cast<std::uint32_t>(used - before);
    }
#pragma omp barrier
#pragma omp single
    {
      for (std::size_t i = 0; i < n; ++i) out.offsets[i + 1] += out.offsets[i];
      resize_with_headroom(out.indices, out.offsets[n]);  // keeps thread 0's lists at the front
    }
    if (thread != 0) {
      std::copy(list.begin(), list.begin() + static_cast<std::ptrdiff_t>(used),
                out.indices.begin() + out.offsets[begin]);
    }
  }
}

NeighbourList brute_force_neighbours(const std::vector<Vec2>& positions, const std::vector<ParticleType>& types,
                                     double radius) {
  const std::size_t n = positions.size();
  NeighbourList out;
  out.radius = radius;
  out.offsets.assign(n + 1, 0);
  for (std::size_t i = 0; i < n; ++i) {
    if (types[i] != ParticleType::Ghost) {
      for (std::size_t j = 0; j < n; ++j) {
        if (j == i || types[j] == ParticleType::Ghost) continue;
        if ((positions[j] - positions[i]).squaredNorm() < radius * radius) {
          out.indices.push_back(static_cast<std::uint32_t>(j));
        }
      }
    }
    out.offsets[i + 1] = static_cast<std::uint32_t>(out.indices.size());
  }
  return out;
}

NeighbourList find_neighbours(const std::vector<Vec2>& positions, const std::vector<ParticleType>& types,
                              double radius) {
  CellList cells;
  cells.build(positions, types, radius);
  NeighbourList list;
  cells.find_neighbours(positions, types, radius, list);
  return list;
}

}  // namespace mps_lab
