// Groups of PPE unknowns without a Dirichlet neighbour (core/linalg/pressure_system.hpp).
// (End to end, a tank closed and filled to the lid has no free surface at all: there the
// diagonal-doubling remedy does not keep MPS or ISPH stable. Measured: MPS reaches 4 m/s and
// ISPH 1e13 m/s within 0.3 s. That case belongs to the stability work, not to this test.)
#include <catch2/catch.hpp>

#include "core/linalg/pressure_system.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

TEST_CASE("ungrounded groups: connected components with no grounded row", "[pressure]") {
  // Rows 0-1-2 connected (row 2 grounded), rows 3-4 connected (none grounded), row 5 alone.
  Eigen::SparseMatrix<double, Eigen::RowMajor> a(6, 6);
  std::vector<Eigen::Triplet<double>> entries = {{0, 0, 2}, {0, 1, -1}, {1, 0, -1}, {1, 1, 2},  {1, 2, -1}, {2, 1, -1},
                                                 {2, 2, 2}, {3, 3, 1},  {3, 4, -1}, {4, 3, -1}, {4, 4, 1},  {5, 5, 1}};
  a.setFromTriplets(entries.begin(), entries.end());
  const auto groups = ungrounded_groups(a, {0, 0, 1, 0, 0, 0});
  REQUIRE(groups.size() == 2);
  CHECK(groups[0] == std::vector<int>{3, 4});
  CHECK(groups[1] == std::vector<int>{5});
  CHECK(ungrounded_groups(a, {1, 0, 0, 1, 0, 1}).empty());
}
