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

namespace {

// The graph Laplacian of paths through the rows, each path visiting its rows in the given order
// (diagonal first in each row, as pin_ungrounded_groups expects).
CsrMatrix path_laplacian(int n, const std::vector<std::vector<int>>& paths) {
  std::vector<std::vector<int>> neighbours(static_cast<std::size_t>(n));
  for (const auto& path : paths) {
    for (std::size_t k = 0; k + 1 < path.size(); ++k) {
      neighbours[static_cast<std::size_t>(path[k])].push_back(path[k + 1]);
      neighbours[static_cast<std::size_t>(path[k + 1])].push_back(path[k]);
    }
  }
  CsrMatrix a;
  a.rows = n;
  a.row_start.assign(1, 0);
  for (int row = 0; row < n; ++row) {
    a.column.push_back(row);
    a.value.push_back(2.0);
    for (const int col : neighbours[static_cast<std::size_t>(row)]) {
      a.column.push_back(col);
      a.value.push_back(-1.0);
    }
    a.row_start.push_back(static_cast<int>(a.column.size()));
  }
  return a;
}

std::vector<double> diagonal(const CsrMatrix& a) {
  std::vector<double> d;
  for (int row = 0; row < a.rows; ++row)
    d.push_back(a.value[static_cast<std::size_t>(a.row_start[static_cast<std::size_t>(row)])]);
  return d;
}

}  // namespace

// pin_ungrounded_groups decides the common case (every row connected to a grounded one) by in-order
// sweeps and leaves the rest to the flood fill: both paths must give the flood fill's answer.
TEST_CASE("pinned groups: the sweeps and the flood fill agree", "[pressure]") {
  std::vector<char> reached;
  const int n = 40;
  std::vector<int> straight(n);
  for (int k = 0; k < n; ++k) straight[static_cast<std::size_t>(k)] = k;
  SECTION("a straight path grounded at either end: reached by the sweeps, nothing pinned") {
    for (const int end : {0, n - 1}) {
      CsrMatrix a = path_laplacian(n, {straight});
      std::vector<char> grounded(n, 0);
      grounded[static_cast<std::size_t>(end)] = 1;
      CHECK(pin_ungrounded_groups(a, grounded, n, reached) == 0);
      CHECK(diagonal(a) == std::vector<double>(n, 2.0));
    }
  }
  SECTION("a path zigzagging through the rows (more turns than sweeps): the flood fill finds it grounded") {
    // 0, 39, 1, 38, 2, ...: each step reverses the direction, so each sweep carries the mark one row.
    std::vector<int> zigzag;
    for (int k = 0; k < n / 2; ++k) {
      zigzag.push_back(k);
      zigzag.push_back(n - 1 - k);
    }
    CsrMatrix a = path_laplacian(n, {zigzag});
    std::vector<char> grounded(n, 0);
    grounded[0] = 1;
    CHECK(pin_ungrounded_groups(a, grounded, n, reached) == 0);
    CHECK(diagonal(a) == std::vector<double>(n, 2.0));
  }
  SECTION("two paths, one grounded: the other's fluid rows below row_limit are doubled") {
    const std::vector<int> first(straight.begin(), straight.begin() + 20),
        second(straight.begin() + 20, straight.end());
    CsrMatrix a = path_laplacian(n, {first, second});
    std::vector<char> grounded(n, 0);
    grounded[5] = 1;
    CHECK(pin_ungrounded_groups(a, grounded, 30, reached) == 1);
    const auto d = diagonal(a);
    for (int row = 0; row < n; ++row) {
      CHECK(d[static_cast<std::size_t>(row)] == (row >= 20 && row < 30 ? 4.0 : 2.0));
    }
  }
}
