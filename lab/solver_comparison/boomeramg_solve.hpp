#pragma once
// The same pressure systems solved with hypre (https://github.com/hypre-space/hypre, Debian's
// libhypre-dev 2.26): BoomerAMG, one V-cycle as the preconditioner of hypre's PCG (symmetric
// systems) or BiCGSTAB (the others), from a zero initial guess, to the method's own relative
// tolerance. The rows are split evenly over the MPI ranks of `communicator`; every rank passes
// the whole system (each recorded the same one: the runs are deterministic).
//
// BoomerAMG settings: hypre's defaults (HMIS coarsening, extended+i interpolation,
// hybrid symmetric Gauss-Seidel / l1 smoothing) with the strength threshold 0.25 that hypre's
// manual advises for 2-D problems.
#include <mpi.h>

#include <vector>

#include "lab/solver_comparison/pressure_systems.hpp"

namespace mps_lab {

struct BoomerAmgSettings {
  double strength_threshold = 0.25;
  int max_iterations = 10000;
};

// The best of `repeats` set-ups and solves; `solution` (every rank) holds the whole solution.
SolveMeasure solve_with_boomeramg(const PressureSystem& system, MPI_Comm communicator,
                                  const BoomerAmgSettings& settings, int repeats, std::vector<double>& solution);

}  // namespace mps_lab
