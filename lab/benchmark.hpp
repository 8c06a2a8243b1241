#pragma once
// The benchmark harness behind `mps_lab bench` (issue 7; docs/performance.md). Not a test:
// it measures, it does not assert.
//
// For every particle spacing it loads the scene with `particle_spacing` (and a time step
// proportional to it) overridden, then measures
//   - the kernels on the initial particles: one neighbour search (cell list + lists at
//     2.1 l0), one MPS number density sum and one SPH summation density (cubic spline,
//     h = 1.2 l0), each repeated and reported in ns per particle;
//   - whole steps of every method: `warmup_steps` unmeasured steps (after running to
//     `start_time`), then `steps` measured ones, with the run's per-phase timers
//     (core/run/profile.hpp): fluid particle-steps per second, ms per step per phase, mean solver
//     iterations and the time of one iteration of the main solver (its phase's seconds /
//     its iterations: "pressure_solve" of mps and isph, "density_solve" of dfsph), and the
//     resident memory the Simulation holds (bytes per particle).
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/run/method.hpp"
#include "core/run/profile.hpp"
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {

struct BenchmarkOptions {
  std::string scene_path;            // e.g. scenes/dambreak.json
  std::vector<std::string> methods;  // empty: every registered method
  std::vector<double> spacings;      // m; empty: the scene's own
  // Time step = time_step_per_spacing * l0 (s/m); 0 keeps the scene's time.time_step.
  // Default 0.02 s/m: 5e-4 s at l0 = 0.025 (the spec's), 1e-4 s at 0.005 (dambreak_fine).
  double time_step_per_spacing = 0.02;
  std::vector<std::string> overrides;  // further "dotted.key=value"
  // "dotted.key=factor": the key set to factor * l0 at every spacing (e.g. a method's largest
  // time step, methods.dfsph.max_time_step=1.0 s/m: 5e-3 s at l0 = 0.005).
  std::vector<std::string> per_spacing;
  double start_time = 0.0;  // s, run (unmeasured) to this time first
  long long warmup_steps = 5;
  long long steps = 20;
  std::vector<int> threads;  // OpenMP thread counts; empty: the current
  bool kernels = true;       // also the kernel micro-benchmarks
  bool progress = false;     // a line per case on stderr
};

// Runs every case; returns {"cases": [...]} with one object per (spacing, threads, method) and
// per (spacing, threads) kernel measurement. Throws InputError for a bad scene or method.
nlohmann::json run_benchmarks(const BenchmarkOptions& options, const MethodRegistry& methods,
                              const WallTreatmentRegistry& walls);

// The printed report of run_benchmarks(): one table of whole steps and one of kernels.
std::string benchmark_table(const nlohmann::json& results);

}  // namespace mps_lab
