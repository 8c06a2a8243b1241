#pragma once
// Parallel reductions whose result does not depend on the number of OpenMP threads.
//
// A floating-point sum depends on its order; OpenMP's reduction(+) adds per-thread partial
// sums, so one and two threads give different last bits, and the determinism tests compare
// runs with 1 and 2 threads byte for byte. deterministic_sum cuts the index range into fixed
// blocks (independent of the thread count), sums each block in index order in parallel, then
// adds the block sums in block order. Exact reductions (integer counts, min, max) may use
// OpenMP's reduction clauses directly.
#include <algorithm>
#include <cstddef>
#include <vector>

namespace mps_lab {

constexpr std::size_t kDeterministicBlock = 4096;  // entries per partial sum

// sum_{i < n} term(i), the same bits for any thread count. `term` must be safe to call from
// several threads at once.
template <typename Term>
double deterministic_sum(std::size_t n, Term&& term) {
  const std::size_t blocks = (n + kDeterministicBlock - 1) / kDeterministicBlock;
  if (blocks <= 1) {
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) sum += term(i);
    return sum;
  }
  double stack_partial[1024];  // up to 4.2 M entries without touching the heap
  std::vector<double> heap_partial;
  double* partial = stack_partial;
  if (blocks > 1024) {
    heap_partial.resize(blocks);
    partial = heap_partial.data();
  }
  const auto block_count = static_cast<std::ptrdiff_t>(blocks);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t block = 0; block < block_count; ++block) {
    const std::size_t begin = static_cast<std::size_t>(block) * kDeterministicBlock;
    const std::size_t end = std::min(n, begin + kDeterministicBlock);
    double sum = 0.0;
    for (std::size_t i = begin; i < end; ++i) sum += term(i);
    partial[block] = sum;
  }
  double total = 0.0;
  for (std::size_t block = 0; block < blocks; ++block) total += partial[block];
  return total;
}

}  // namespace mps_lab
