// MPS weight function and lattice constants (spec §2, §3).
#include <catch2/catch.hpp>

#include "methods/mps/mps_kernels.hpp"

using namespace mps_lab;

TEST_CASE("MPS weight: values - the R_MIN clamp and zero beyond re", "[kernels]") {
  const double l0 = 0.025, re = 2.1 * l0, r_min = 0.01 * l0;
  // w(r) = re/r - 1: exact values at the lattice distances.
  CHECK(mps_weight(l0, re, r_min) == Approx(1.1).epsilon(1e-14));
  CHECK(mps_weight(std::sqrt(2.0) * l0, re, r_min) == Approx(2.1 / std::sqrt(2.0) - 1.0).epsilon(1e-14));
  CHECK(mps_weight(2.0 * l0, re, r_min) == Approx(0.05).epsilon(1e-12));
  // Zero at and beyond re.
  CHECK(mps_weight(re, re, r_min) == 0.0);
  CHECK(mps_weight(std::nextafter(re, 1.0), re, r_min) == 0.0);
  CHECK(mps_weight(3.0 * l0, re, r_min) == 0.0);
  // Below R_MIN the distance is clamped: w = re / R_MIN - 1 = 209 for any smaller r.
  CHECK(mps_weight(r_min, re, r_min) == Approx(209.0).epsilon(1e-12));
  CHECK(mps_weight(1e-3 * r_min, re, r_min) == Approx(209.0).epsilon(1e-12));
  CHECK(mps_weight(0.0, re, r_min) == Approx(209.0).epsilon(1e-12));
  // Continuous and decreasing just inside re.
  CHECK(mps_weight(re * (1 - 1e-9), re, r_min) == Approx(0.0).margin(1e-8));
}

TEST_CASE("n0 and lambda of the square lattice equal the lattice sums", "[kernels]") {
  // re = 2.1 l0: neighbours at 1 (x4), sqrt2 (x4), 2 (x4); sqrt5 = 2.236 > 2.1 is outside.
  //   n0 = 4(1.1) + 4(2.1/sqrt2 - 1) + 4(0.05) = 6.5397...
  //   lambda = (4*1*1.1 + 4*2*(2.1/sqrt2 - 1) + 4*4*0.05) / n0 l0^2 = 1.38835 l0^2
  const double exact_n0 = 4 * 1.1 + 4 * (2.1 / std::sqrt(2.0) - 1.0) + 4 * 0.05;
  const double exact_lambda = (4 * 1.1 + 8 * (2.1 / std::sqrt(2.0) - 1.0) + 16 * 0.05) / exact_n0;
  for (double l0 : {0.025, 0.0125, 0.005}) {
    const auto constants = mps_lattice_constants(l0, 2.1 * l0, 0.01 * l0);
    CHECK(constants.number_density == Approx(exact_n0).epsilon(1e-12));
    CHECK(constants.lambda / (l0 * l0) == Approx(exact_lambda).epsilon(1e-12));
  }
  // The spec's rounded values.
  const auto spec = mps_lattice_constants(0.025, 2.1 * 0.025, 0.01 * 0.025);
  CHECK(spec.number_density == Approx(6.5397).margin(5e-5));
  CHECK(spec.lambda / (0.025 * 0.025) == Approx(1.38835).margin(5e-6));
  // A larger Laplacian radius (K&O 1996: 4.0 l0) includes sqrt5, sqrt8, 3, sqrt10, sqrt13 ...
  const auto wide = mps_lattice_constants(1.0, 4.0, 0.01);
  CHECK(wide.number_density > spec.number_density);
}
