#include "core/pressure_system.hpp"

namespace mps_lab {

std::vector<std::vector<int>> ungrounded_groups(const Eigen::SparseMatrix<double, Eigen::RowMajor>& matrix,
                                                const std::vector<char>& grounded) {
  using RowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;
  const auto rows = static_cast<int>(matrix.rows());
  std::vector<char> visited(static_cast<std::size_t>(rows), 0);
  std::vector<std::vector<int>> found;
  std::vector<int> stack;
  std::vector<int> members;
  for (int seed = 0; seed < rows; ++seed) {
    if (visited[static_cast<std::size_t>(seed)]) continue;
    bool touches_dirichlet = false;
    members.clear();
    stack.assign(1, seed);
    visited[static_cast<std::size_t>(seed)] = 1;
    while (!stack.empty()) {  // flood fill over the matrix graph
      const int row = stack.back();
      stack.pop_back();
      members.push_back(row);
      touches_dirichlet = touches_dirichlet || grounded[static_cast<std::size_t>(row)];
      for (RowMatrix::InnerIterator it(matrix, row); it; ++it) {
        const auto col = static_cast<std::size_t>(it.col());
        if (!visited[col]) {
          visited[col] = 1;
          stack.push_back(static_cast<int>(col));
        }
      }
    }
    if (!touches_dirichlet) found.push_back(members);
  }
  return found;
}

}  // namespace mps_lab
