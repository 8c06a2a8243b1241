#pragma once
// Helpers for the pressure systems of the projection methods (MPS, ISPH).
#include <vector>

#include <Eigen/SparseCore>

#include "core/sparse_matrix.hpp"

namespace mps_lab {

// Groups of unknowns connected through off-diagonal entries of `matrix` in which no row is
// `grounded` (touches a Dirichlet particle: a free-surface neighbour, P = 0). Such a group's
// block is singular: its pressure is defined only up to a constant. Each returned group
// lists its rows; what to do about it is the method's choice (MPS and ISPH double the
// diagonal of the group's fluid rows, the remedy of the public MPS-Basic code).
std::vector<std::vector<int>> ungrounded_groups(const CsrMatrix& matrix, const std::vector<char>& grounded);
std::vector<std::vector<int>> ungrounded_groups(const Eigen::SparseMatrix<double, Eigen::RowMajor>& matrix,
                                                const std::vector<char>& grounded);

// The same matrix as an Eigen sparse matrix (tests compare with Eigen's direct solvers).
Eigen::SparseMatrix<double, Eigen::RowMajor> to_eigen(const CsrMatrix& matrix);

}  // namespace mps_lab
