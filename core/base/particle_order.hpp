#pragma once
// A reordering of the particles (issue 17, item 2: cell-ordered particles). After the
// reordering, the particle at index k is the one that was at old_index[k]; the one that was at
// index i is at new_index[i]. Every per-particle array is moved the same way (permute_values):
// the ParticleSet's (permute_particles, core/base/particles.hpp), a method's
// (Method::permute_state), the neighbour lists and wall samples a method keeps between steps
// (core/search/cell_order.hpp).
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace mps_lab {

struct ParticleOrder {
  std::vector<std::uint32_t> old_index;  // size N: where the particle now at k was
  std::vector<std::uint32_t> new_index;  // size N: where the particle that was at i is now

  std::size_t size() const { return old_index.size(); }
  bool is_identity() const {
    for (std::size_t k = 0; k < old_index.size(); ++k) {
      if (old_index[k] != k) return false;
    }
    return true;
  }
  // From the old indices in their new order; std::logic_error unless they are a permutation of 0..N-1.
  static ParticleOrder from_old_indices(std::vector<std::uint32_t> old_index) {
    ParticleOrder order;
    const std::size_t n = old_index.size();
    order.new_index.assign(n, static_cast<std::uint32_t>(n));
    for (std::size_t k = 0; k < n; ++k) {
      const std::uint32_t i = old_index[k];
      if (i >= n || order.new_index[i] != n) {
        throw std::logic_error("particle order: index " + std::to_string(i) + " is out of range or repeated");
      }
      order.new_index[i] = static_cast<std::uint32_t>(k);
    }
    order.old_index = std::move(old_index);
    return order;
  }
};

// values[k] <- values[old_index[k]]. An empty array stays empty (an optional per-particle array
// that is not in use, e.g. ParticleSet::wall_velocity while every wall is fixed); any other
// size than N is a programming error (std::logic_error).
template <class T>
void permute_values(std::vector<T>& values, const ParticleOrder& order) {
  if (values.empty()) return;
  if (values.size() != order.size()) {
    throw std::logic_error("particle order of " + std::to_string(order.size()) + " particles applied to an array of " +
                           std::to_string(values.size()));
  }
  std::vector<T> moved;
  moved.reserve(values.size());
  for (const std::uint32_t i : order.old_index) moved.push_back(values[i]);
  values.swap(moved);
}

}  // namespace mps_lab
