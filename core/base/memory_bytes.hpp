#pragma once
// The heap a structure holds, by name: what `mps_lab bench` reports as a case's
// "memory_breakdown" (docs/performance.md, "Memory"). Bytes are the capacity of the big
// containers (capacity x element size), not what the allocator or the kernel add; the
// process's resident memory is measured separately (core/run/profile.hpp).
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

namespace mps_lab {

// (name, bytes) in a fixed order; names are dotted paths ("ppe.matrix", "amg.level0.prolongator").
using MemoryBreakdown = std::vector<std::pair<std::string, std::size_t>>;

template <typename T>
std::size_t held_bytes(const std::vector<T>& vector) {
  return vector.capacity() * sizeof(T);
}

template <typename T, typename... Rest>
std::size_t held_bytes(const std::vector<T>& first, const Rest&... rest) {
  return held_bytes(first) + held_bytes(rest...);
}

// Resizes `vector` to `size` (new elements value-initialised, as resize). When that needs more
// capacity, it reserves size + size/headroom_divisor first: a size that creeps up from step to
// step (the unknowns, the matrix's entries, the cells of a spreading flow) then grows the capacity
// by an eighth, where std::vector's own growth doubles the old size (libstdc++), which left a
// matrix holding twice the bytes of its entries (docs/performance.md, "Memory").
template <typename T>
void resize_with_headroom(std::vector<T>& vector, std::size_t size, std::size_t headroom_divisor = 8) {
  if (size > vector.capacity()) vector.reserve(size + size / headroom_divisor);
  vector.resize(size);
}

// assign(size, value) with the headroom of resize_with_headroom.
template <typename T>
void assign_with_headroom(std::vector<T>& vector, std::size_t size, const T& value) {
  if (size > vector.capacity()) vector.reserve(size + size / 8);
  vector.assign(size, value);
}

// Appends every entry of `items` to `out` with `prefix` + "." before its name.
inline void append_breakdown(MemoryBreakdown& out, const std::string& prefix, const MemoryBreakdown& items) {
  for (const auto& [name, bytes] : items) out.emplace_back(prefix + "." + name, bytes);
}

}  // namespace mps_lab
