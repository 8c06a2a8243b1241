#include "core/search/cell_order.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>

namespace mps_lab {

namespace {

// The cell grid over the bounding box of the non-ghost particles: the lower-left corner, m,
// and the number of cells in x and y (at least one each).
struct OrderGrid {
  Vec2 origin = Vec2::Zero();
  std::int64_t cells_x = 1;
  std::int64_t cells_y = 1;
  double cell_size = 1.0;

  std::int64_t cell_of(const Vec2& x) const {
    auto ix = static_cast<std::int64_t>(std::floor((x.x() - origin.x()) / cell_size));
    auto iy = static_cast<std::int64_t>(std::floor((x.y() - origin.y()) / cell_size));
    ix = std::clamp<std::int64_t>(ix, 0, cells_x - 1);  // the particles on the box's upper edges
    iy = std::clamp<std::int64_t>(iy, 0, cells_y - 1);
    return iy * cells_x + ix;
  }
};

OrderGrid order_grid(const std::vector<Vec2>& positions, const std::vector<ParticleType>& types, double cell_size) {
  double min_x = std::numeric_limits<double>::infinity(), min_y = min_x;
  double max_x = -min_x, max_y = -min_x;
  for (std::size_t i = 0; i < positions.size(); ++i) {
    if (types[i] == ParticleType::Ghost) continue;
    const Vec2& x = positions[i];
    if (!std::isfinite(x.x()) || !std::isfinite(x.y())) {
      throw std::runtime_error("cell order: particle " + std::to_string(i) + " has a non-finite position");
    }
    min_x = std::min(min_x, x.x());
    min_y = std::min(min_y, x.y());
    max_x = std::max(max_x, x.x());
    max_y = std::max(max_y, x.y());
  }
  OrderGrid grid;
  grid.cell_size = cell_size;
  if (!(min_x <= max_x)) return grid;  // no active particle: one cell
  grid.origin = Vec2(min_x, min_y);
  const double span_x = (max_x - min_x) / cell_size + 1.0;
  const double span_y = (max_y - min_y) / cell_size + 1.0;
  if (span_x * span_y > 1e9) {
    throw std::runtime_error("cell order: particles spread over " + std::to_string(span_x * span_y) + " cells");
  }
  grid.cells_x = static_cast<std::int64_t>(span_x);
  grid.cells_y = static_cast<std::int64_t>(span_y);
  return grid;
}

}  // namespace

ParticleOrder cell_order(const std::vector<Vec2>& positions, const std::vector<ParticleType>& types, double cell_size) {
  if (!(cell_size > 0.0)) throw std::invalid_argument("cell order: the cell size must be > 0");
  if (types.size() != positions.size()) throw std::invalid_argument("cell order: positions and types differ in size");
  const std::size_t n = positions.size();
  const OrderGrid grid = order_grid(positions, types, cell_size);
  // Counting sort (stable): the ghosts count as one more cell after the last.
  const auto cells = static_cast<std::size_t>(grid.cells_x * grid.cells_y);
  std::vector<std::size_t> cell(n);
  std::vector<std::uint32_t> start(cells + 2, 0);
  for (std::size_t i = 0; i < n; ++i) {
    cell[i] = types[i] == ParticleType::Ghost ? cells : static_cast<std::size_t>(grid.cell_of(positions[i]));
    ++start[cell[i] + 1];
  }
  for (std::size_t c = 0; c <= cells; ++c) start[c + 1] += start[c];
  std::vector<std::uint32_t> old_index(n);
  for (std::size_t i = 0; i < n; ++i) old_index[start[cell[i]]++] = static_cast<std::uint32_t>(i);
  return ParticleOrder::from_old_indices(std::move(old_index));
}

void permute_neighbour_list(NeighbourList& list, const ParticleOrder& order) {
  if (list.offsets.empty()) return;  // no search yet
  if (list.particle_count() != order.size()) {
    throw std::logic_error("neighbour list of " + std::to_string(list.particle_count()) + " particles reordered for " +
                           std::to_string(order.size()));
  }
  NeighbourList moved;
  moved.radius = list.radius;
  moved.offsets.resize(list.offsets.size());
  moved.indices.resize(list.indices.size());
  moved.offsets[0] = 0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::uint32_t i = order.old_index[k];
    std::uint32_t out = moved.offsets[k];
    for (std::uint32_t e = list.begin(i); e < list.end(i); ++e) moved.indices[out++] = order.new_index[list.indices[e]];
    moved.offsets[k + 1] = out;
  }
  list = std::move(moved);
}

void permute_wall_samples(WallSampleList& samples, const ParticleOrder& order) {
  if (!samples.has_samples()) return;
  if (samples.offsets.size() != order.size() + 1) {
    throw std::logic_error("wall samples of " + std::to_string(samples.offsets.size() - 1) +
                           " particles reordered for " + std::to_string(order.size()));
  }
  WallSampleList moved;
  moved.offsets.resize(samples.offsets.size());
  moved.samples.reserve(samples.samples.size());
  moved.offsets[0] = 0;
  for (std::size_t k = 0; k < order.size(); ++k) {
    const std::uint32_t i = order.old_index[k];
    for (std::uint32_t e = samples.begin(i); e < samples.end(i); ++e) {
      WallSample sample = samples.samples[e];
      sample.source = order.new_index[sample.source];
      moved.samples.push_back(sample);
    }
    moved.offsets[k + 1] = static_cast<std::uint32_t>(moved.samples.size());
  }
  samples = std::move(moved);
}

}  // namespace mps_lab
