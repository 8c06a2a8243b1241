#pragma once
// The pressure systems of the projection methods, taken from real runs, and the project's own
// solve of them (core/linalg: smoothed-aggregation AMG + CG or BiCGSTAB), for the comparison
// with hypre's BoomerAMG (docs/beyond-one-machine.md, tools/solver-comparison.sh).
//
// A system is recorded through MethodSetup::pressure_system_observer: whichever registered
// method hands a system to its ProjectionSolver in its first steps has one (today mps and
// isph); a method that solves no linear pressure system (dfsph's iterations, explicit methods)
// records none. No method is named here.
#include <cstddef>
#include <string>
#include <vector>

#include "core/linalg/amg.hpp"
#include "core/linalg/projection_solver.hpp"
#include "core/linalg/sparse_matrix.hpp"
#include "core/run/method.hpp"

namespace mps_lab {

struct PressureSystem {
  std::string method;
  double particle_spacing = 0.0;  // m
  std::size_t fluid_particles = 0;
  long long step = 0;  // the step whose solve it is
  CsrMatrix matrix;
  std::vector<double> rhs;
  KrylovMethod krylov = KrylovMethod::ConjugateGradient;
  double tolerance = 1.0e-8;  // the method's relative residual ||b - A p|| / ||b||
};

// Runs `method` on the scene (with `overrides`) until its ProjectionSolver receives a system
// at or after step `from_step` (1 = the first step), and returns that system; false when none
// came within `from_step` + 2 steps (the method solves no linear pressure system).
bool record_pressure_system(const std::string& scene_path, const std::vector<std::string>& overrides,
                            const MethodRegistry& methods, const MethodInfo& method, const WallTreatmentRegistry& walls,
                            long long from_step, PressureSystem& system);

// One solve of a system from a zero initial guess.
struct SolveMeasure {
  double setup_seconds = 0.0;  // the preconditioner's set-up
  double solve_seconds = 0.0;  // the Krylov iterations
  long long iterations = 0;
  double residual = 0.0;      // ||b - A x|| / ||b||, recomputed with the project's own product
  double memory_bytes = 0.0;  // heap the preconditioner and the Krylov workspace hold after the solve (all ranks)
  int levels = 0;
  double operator_complexity = 0.0;
  bool converged = false;
};

// The project's solve (core/linalg/amg.hpp + krylov.hpp) with `amg` options, the best of
// `repeats` timings with the calling thread's OpenMP team.
SolveMeasure solve_with_core_amg(const PressureSystem& system, const AmgOptions& amg, int repeats,
                                 std::vector<double>& solution);

// Heap bytes in use by this process (glibc mallinfo2: small and mmap'd blocks).
double heap_bytes_in_use();

// ||b - A x|| / ||b||.
double relative_residual(const CsrMatrix& matrix, const std::vector<double>& rhs, const std::vector<double>& x);

}  // namespace mps_lab
