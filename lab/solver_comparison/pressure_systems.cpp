#include "lab/solver_comparison/pressure_systems.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include <malloc.h>

#include "core/io/scene.hpp"
#include "core/linalg/amg.hpp"
#include "core/linalg/krylov.hpp"
#include "core/run/driver.hpp"

namespace mps_lab {

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

}  // namespace

double heap_bytes_in_use() {
  const struct mallinfo2 info = mallinfo2();
  return static_cast<double>(info.uordblks + info.hblkhd);
}

namespace {}  // namespace

bool record_pressure_system(const std::string& scene_path, const std::vector<std::string>& overrides,
                            const MethodRegistry& methods, const MethodInfo& method, const WallTreatmentRegistry& walls,
                            long long from_step, PressureSystem& system) {
  std::vector<std::string> scene_overrides = overrides;
  scene_overrides.push_back("method=" + method.name);
  const Scene scene = load_scene(scene_path, scene_overrides, methods, walls);
  long long current_step = 0;
  bool recorded = false;
  auto observer = [&](const CsrMatrix& matrix, const std::vector<double>& rhs,
                      const ProjectionSolverSettings& settings) {
    if (recorded || current_step < from_step) return;
    system.matrix = matrix;
    system.rhs = rhs;
    system.krylov = settings.method;
    system.tolerance = settings.tolerance;
    system.step = current_step;
    recorded = true;
  };
  Simulation simulation(scene, method, observer);
  system.method = method.name;
  system.particle_spacing = scene.particle_spacing;
  system.fluid_particles = simulation.particles().count(ParticleType::Fluid);
  for (current_step = 1; current_step <= from_step + 2 && !recorded; ++current_step) simulation.advance();
  return recorded;
}

double relative_residual(const CsrMatrix& matrix, const std::vector<double>& rhs, const std::vector<double>& x) {
  double residual_squared = 0.0, rhs_squared = 0.0;
  for (int row = 0; row < matrix.rows; ++row) {
    double product = 0.0;
    for (int k = matrix.row_start[row]; k < matrix.row_start[row + 1]; ++k)
      product += matrix.value[k] * x[matrix.column[k]];
    const double difference = rhs[row] - product;
    residual_squared += difference * difference;
    rhs_squared += rhs[row] * rhs[row];
  }
  return rhs_squared > 0.0 ? std::sqrt(residual_squared / rhs_squared) : 0.0;
}

SolveMeasure solve_with_core_amg(const PressureSystem& system, const AmgOptions& amg_options, int repeats,
                                 std::vector<double>& solution) {
  SolveMeasure best;
  best.setup_seconds = best.solve_seconds = std::numeric_limits<double>::infinity();
  KrylovSettings krylov;
  krylov.tolerance = system.tolerance;
  krylov.max_iterations = 10000;
  for (int repeat = 0; repeat < repeats; ++repeat) {
    const double memory_before = heap_bytes_in_use();
    AmgPreconditioner amg(amg_options);  // a fresh hierarchy each time: set-up from nothing, as a new run's first step
    KrylovWorkspace workspace;
    solution.assign(system.rhs.size(), 0.0);
    const auto setup_start = Clock::now();
    amg.setup(system.matrix);
    const double setup_seconds = seconds_since(setup_start);
    const auto solve_start = Clock::now();
    const KrylovResult result =
        system.krylov == KrylovMethod::ConjugateGradient
            ? conjugate_gradient(system.matrix, system.rhs.data(), solution.data(), amg, krylov, workspace)
            : bicgstab(system.matrix, system.rhs.data(), solution.data(), amg, krylov, workspace);
    const double solve_seconds = seconds_since(solve_start);
    best.memory_bytes = heap_bytes_in_use() - memory_before;  // the hierarchy and the workspace, alive
    best.setup_seconds = std::min(best.setup_seconds, setup_seconds);
    best.solve_seconds = std::min(best.solve_seconds, solve_seconds);
    best.iterations = result.iterations;
    best.converged = result.converged;
    best.levels = static_cast<int>(amg.levels().size());
    best.operator_complexity = amg.operator_complexity();
  }
  best.residual = relative_residual(system.matrix, system.rhs, solution);
  return best;
}

}  // namespace mps_lab
