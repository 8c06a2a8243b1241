#pragma once
// Helpers for the pressure systems of the projection methods (MPS, ISPH).
#include <cstddef>
#include <vector>

#include <Eigen/SparseCore>

#include "core/linalg/sparse_matrix.hpp"

namespace mps_lab {

// Groups of unknowns connected through off-diagonal entries of `matrix` in which no row is
// `grounded` (touches a Dirichlet particle: a free-surface neighbour, P = 0). Such a group's
// block is singular: its pressure is defined only up to a constant. Each returned group
// lists its rows; what to do about it is the method's choice (MPS and ISPH double the
// diagonal of the group's fluid rows, the remedy of the public MPS-Basic code).
std::vector<std::vector<int>> ungrounded_groups(const CsrMatrix& matrix, const std::vector<char>& grounded);
std::vector<std::vector<int>> ungrounded_groups(const Eigen::SparseMatrix<double, Eigen::RowMajor>& matrix,
                                                const std::vector<char>& grounded);

// Doubles the diagonal of every row below `row_limit` in each ungrounded group of `matrix`
// (the remedy of the public MPS-Basic code: it pins the group's mean pressure near zero);
// rows from `row_limit` on (ISPH's wall rows) are left as they are. The matrix must store the
// diagonal first in each row (CsrAssembler::finish with diagonal_first). Returns the number
// of groups. `reached` is scratch (one byte per row): the common case, every row connected to a
// grounded one, is decided by a few in-order sweeps and allocates nothing once it has grown.
std::size_t pin_ungrounded_groups(CsrMatrix& matrix, const std::vector<char>& grounded, std::size_t row_limit,
                                  std::vector<char>& reached);

// The unknowns <-> the particles' pressures, row r being particle particle_of[r] (parallel,
// each entry written once):
//   gather:  solution[r] = pressure[particle_of[r]] (warm start) or 0; resizes `solution`;
//   scatter: pressure[particle_of[r]] = solution[r], or max(solution[r], 0) with clamp_negative
//            (spec §5.2-7 for mps).
void gather_unknowns(const std::vector<double>& pressure, const std::vector<int>& particle_of, bool warm_start,
                     std::vector<double>& solution);
void scatter_unknowns(const std::vector<double>& solution, const std::vector<int>& particle_of, bool clamp_negative,
                      std::vector<double>& pressure);

// The same matrix as an Eigen sparse matrix (tests compare with Eigen's direct solvers).
Eigen::SparseMatrix<double, Eigen::RowMajor> to_eigen(const CsrMatrix& matrix);

}  // namespace mps_lab
