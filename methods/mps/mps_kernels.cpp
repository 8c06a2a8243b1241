#include "methods/mps/mps_kernels.hpp"

#include <cmath>

namespace mps_lab {

MpsLatticeConstants mps_lattice_constants(double spacing, double re, double r_min) {
  const int reach = static_cast<int>(std::ceil(re / spacing)) + 1;
  double weight_sum = 0.0;
  double weighted_r2 = 0.0;
  for (int i = -reach; i <= reach; ++i) {
    for (int j = -reach; j <= reach; ++j) {
      if (i == 0 && j == 0) continue;
      const double r = spacing * std::hypot(static_cast<double>(i), static_cast<double>(j));
      const double w = mps_weight(r, re, r_min);
      weight_sum += w;
      weighted_r2 += r * r * w;
    }
  }
  return {weight_sum, weight_sum > 0.0 ? weighted_r2 / weight_sum : 0.0};
}

}  // namespace mps_lab
