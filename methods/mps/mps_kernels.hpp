#pragma once
// Weight functions and their lattice constants.
#include <algorithm>

namespace mps_lab {

// MPS weight function (spec §2; Koshizuka & Oka 1996, eq. 3):
//   w(r, re) = re / r - 1  for 0 < r < re,  0 for r >= re,
// with r clamped from below to r_min (spec: R_MIN = 0.01 l0) so that coincident particles
// give a large but finite weight.
inline double mps_weight(double r, double re, double r_min) {
  if (r >= re) return 0.0;
  return re / std::max(r, r_min) - 1.0;
}

// Constants of the MPS operators measured on the initial square lattice (spec §2 note):
// a particle with full support on a lattice of spacing l0.
struct MpsLatticeConstants {
  double number_density;  // n0 = sum_j w(|r_j|, re)                        (dimensionless)
  double lambda;          // lambda = sum_j |r_j|^2 w_j / sum_j w_j          (m^2)
};

// Sums over the lattice points (i l0, j l0) != 0 with |r| < re.
MpsLatticeConstants mps_lattice_constants(double spacing, double re, double r_min);

}  // namespace mps_lab
