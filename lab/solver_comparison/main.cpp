// mps_lab_solver_bench: the project's smoothed-aggregation AMG (core/linalg/amg.hpp) against
// hypre's BoomerAMG on the pressure systems of every registered method that solves one,
// recorded from a real run of a scene (docs/beyond-one-machine.md, tools/solver-comparison.sh).
//
//   mps_lab_solver_bench [scene] --spacings 0.005,0.001,0.00035 --threads 1,2 --json out.json
//   mpirun -np 2 mps_lab_solver_bench [scene] --spacings ...      (BoomerAMG on 2 ranks only)
//
// With one MPI rank it times both solvers (the project's with each OpenMP thread count of
// --threads; hypre's Debian build has no OpenMP, so one rank is one thread); with more ranks it
// times BoomerAMG alone, its rows split over the ranks. Both start from zero and stop at the
// method's own relative tolerance; the residual printed is recomputed the same way for both.
#include <mpi.h>
#include <omp.h>

#include <HYPRE_utilities.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/io/output.hpp"
#include "core/walls/wall_treatment.hpp"
#include "lab/data_directory.hpp"
#include "lab/solver_comparison/boomeramg_solve.hpp"
#include "lab/solver_comparison/pressure_systems.hpp"

namespace {

using mps_lab::PressureSystem;
using mps_lab::SolveMeasure;

struct BenchOptions {
  std::string scene;
  std::vector<double> spacings{0.005};
  std::vector<int> threads{1};
  // Smoother degrees of the project's AMG (AmgOptions::smoother_sweeps); the first is the one
  // BoomerAMG is compared with. Default: the library's default.
  std::vector<int> amg_degrees{mps_lab::AmgOptions{}.smoother_sweeps};
  // Cycles per coarse level (AmgOptions::coarse_cycles: 1 V-cycle, 2 W-cycle), each timed with
  // every degree; the first is the one compared with BoomerAMG.
  std::vector<int> amg_coarse_cycles{mps_lab::AmgOptions{}.coarse_cycles};
  // time.time_step = this x l0 (s/m): the spec's 5e-4 s at l0 = 0.025, and a Courant number that
  // stays below 1 at every spacing (the performance study's rule, docs/performance.md).
  double time_step_per_spacing = 0.02;
  int repeats = 3;
  long long from_step = 1;
  std::string json;
  // --check: fail unless every solve reaches its tolerance and the two solvers' solutions agree
  // within max_difference (relative 2-norm; see check_case).
  bool check = false;
  double max_difference = 1.0e-4;
};

double relative_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double difference = 0.0, norm = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    difference += (a[i] - b[i]) * (a[i] - b[i]);
    norm += a[i] * a[i];
  }
  return norm > 0.0 ? std::sqrt(difference / norm) : std::sqrt(difference);
}

// Both solvers stop at ||b - A x|| / ||b|| <= tol (1e-8), so their solutions differ by at most
// kappa(A) * 2 tol relative to ||x||; the pressure matrices of a few thousand unknowns have
// kappa of order N (a Poisson matrix: about 4 N / pi^2), hence 1e-4 at N <= 5e3 with margin.
void check_case(const PressureSystem& system, const nlohmann::json& solves, double difference,
                const BenchOptions& options) {
  for (const auto& solve : solves) {
    const auto& m = solve.at("measure");
    if (m.at("residual").get<double>() > system.tolerance * 1.0001) {
      throw std::runtime_error(system.method + ": " + solve.at("solver").get<std::string>() + " residual " +
                               mps_lab::format_double(m.at("residual").get<double>()) + " above the tolerance " +
                               mps_lab::format_double(system.tolerance));
    }
  }
  if (difference > options.max_difference) {
    throw std::runtime_error(system.method + ": the solutions differ by " + mps_lab::format_double(difference) +
                             " (relative), more than " + mps_lab::format_double(options.max_difference));
  }
}

nlohmann::json measure_json(const SolveMeasure& m) {
  return {{"setup_seconds", m.setup_seconds},
          {"solve_seconds", m.solve_seconds},
          {"iterations", m.iterations},
          {"residual", m.residual},
          {"memory_bytes", m.memory_bytes},
          {"converged", m.converged},
          {"levels", m.levels},
          {"operator_complexity", m.operator_complexity}};
}

void print_row(const PressureSystem& system, const char* solver, int parallelism, const SolveMeasure& m) {
  std::printf("%-6s %9.5f %9d %10zu  %-10s %2d  %9.4f %9.4f %5lld %9.2e %9.1f\n", system.method.c_str(),
              system.particle_spacing, system.matrix.rows, system.matrix.nonzeros(), solver, parallelism,
              m.setup_seconds, m.solve_seconds, m.iterations, m.residual, m.memory_bytes / system.matrix.rows);
}

// "core_amg" for the library's default smoother degree and cycle, "core_amg_degreeN" for another
// degree, "_w" appended for the W-cycle.
std::string core_amg_label(int degree, int coarse_cycles) {
  const mps_lab::AmgOptions defaults;
  std::string label = degree == defaults.smoother_sweeps ? "core_amg" : "core_amg_degree" + std::to_string(degree);
  if (coarse_cycles != defaults.coarse_cycles)
    label += coarse_cycles == 2 ? "_w" : "_cycles" + std::to_string(coarse_cycles);
  return label;
}

// Each smoother degree and cycle of the project's AMG on every thread count.
void time_core_amg(const PressureSystem& system, const BenchOptions& options, nlohmann::json& rows,
                   std::vector<double>& core_solution) {
  std::vector<double> other_solution;
  for (int cycles : options.amg_coarse_cycles) {
    for (int degree : options.amg_degrees) {
      mps_lab::AmgOptions amg;
      amg.smoother_sweeps = degree;
      amg.coarse_cycles = cycles;
      const std::string label = core_amg_label(degree, cycles);
      const bool first = degree == options.amg_degrees.front() && cycles == options.amg_coarse_cycles.front();
      for (int threads : options.threads) {
        omp_set_num_threads(threads);
        const SolveMeasure m =
            mps_lab::solve_with_core_amg(system, amg, options.repeats, first ? core_solution : other_solution);
        print_row(system, label.c_str(), threads, m);
        rows.push_back({{"solver", label},
                        {"threads", threads},
                        {"ranks", 1},
                        {"smoother_degree", degree},
                        {"coarse_cycles", cycles},
                        {"measure", measure_json(m)}});
      }
    }
  }
}

// The project's AMG (one rank only; time_core_amg), then BoomerAMG on the ranks; the solutions
// compared are those of the first degree and cycle.
nlohmann::json compare_on(const PressureSystem& system, const BenchOptions& options, int ranks, int rank) {
  nlohmann::json rows = nlohmann::json::array();
  std::vector<double> solution, core_solution;
  if (ranks == 1) time_core_amg(system, options, rows, core_solution);
  omp_set_num_threads(1);
  const SolveMeasure m =
      mps_lab::solve_with_boomeramg(system, MPI_COMM_WORLD, mps_lab::BoomerAmgSettings{}, options.repeats, solution);
  if (rank == 0) print_row(system, "boomeramg", ranks, m);
  rows.push_back({{"solver", "boomeramg"}, {"threads", 1}, {"ranks", ranks}, {"measure", measure_json(m)}});
  double difference = 0.0;  // with several ranks the project's solve did not run
  if (ranks == 1) {
    difference = relative_difference(core_solution, solution);
    std::printf("%-6s %9.5f  solutions differ by %.2e (relative 2-norm)\n", system.method.c_str(),
                system.particle_spacing, difference);
  }
  if (options.check) check_case(system, rows, difference, options);
  return rows;
}

nlohmann::json system_json(const PressureSystem& system) {
  return {{"method", system.method},
          {"particle_spacing", system.particle_spacing},
          {"fluid_particles", system.fluid_particles},
          {"step", system.step},
          {"unknowns", system.matrix.rows},
          {"nonzeros", system.matrix.nonzeros()},
          {"krylov", system.krylov == mps_lab::KrylovMethod::ConjugateGradient ? "cg" : "bicgstab"},
          {"tolerance", system.tolerance}};
}

// Records the method's system; false (and a line on rank 0) when it solves none or its run stops
// before one (a method's own failure is reported, not fatal to the comparison of the others).
bool record_or_report(const BenchOptions& options, const std::vector<std::string>& overrides,
                      const mps_lab::MethodRegistry& methods, const mps_lab::MethodInfo& method,
                      const mps_lab::WallTreatmentRegistry& walls, double spacing, int rank, PressureSystem& system) {
  std::string why = "solves no linear pressure system";
  try {
    if (mps_lab::record_pressure_system(options.scene, overrides, methods, method, walls, options.from_step, system)) {
      return true;
    }
  } catch (const std::runtime_error& error) {
    why = std::string("stopped before a system: ") + error.what();
  }
  if (rank == 0) std::printf("%-6s %9.5f  %s\n", method.name.c_str(), spacing, why.c_str());
  return false;
}

nlohmann::json run_comparison(const BenchOptions& options, int ranks, int rank) {
  const mps_lab::MethodRegistry methods = mps_lab::builtin_methods();
  const mps_lab::WallTreatmentRegistry walls = mps_lab::builtin_wall_treatments();
  nlohmann::json cases = nlohmann::json::array();
  if (rank == 0) {
    std::printf(
        "method   spacing  unknowns   nonzeros  solver     np  setup [s] solve [s] iters  residual  heap B/row\n");
  }
  for (double spacing : options.spacings) {
    for (const mps_lab::MethodInfo* method : methods.all()) {
      PressureSystem system;
      const std::vector<std::string> overrides{
          "particle_spacing=" + mps_lab::format_double(spacing),
          "time.time_step=" + mps_lab::format_double(options.time_step_per_spacing * spacing)};
      omp_set_num_threads(options.threads.back());
      if (!record_or_report(options, overrides, methods, *method, walls, spacing, rank, system)) continue;
      nlohmann::json entry = system_json(system);
      entry["solves"] = compare_on(system, options, ranks, rank);
      cases.push_back(entry);
    }
  }
  return {{"version", mps_lab::version_line()}, {"scene", options.scene}, {"ranks", ranks}, {"cases", cases}};
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  HYPRE_Init();
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  BenchOptions options;
  options.scene = mps_lab::data_directory() + "/scenes/dambreak.json";
  CLI::App app{"The project's AMG against hypre's BoomerAMG on recorded pressure systems"};
  app.add_option("scene", options.scene, "scene file (default: scenes/dambreak.json)");
  app.add_option("--spacings", options.spacings, "particle spacings, m")->delimiter(',');
  app.add_option("--threads", options.threads, "OpenMP threads of the project's AMG (one rank only)")->delimiter(',');
  app.add_option("--amg-degrees", options.amg_degrees,
                 "smoother degrees of the project's AMG, each timed (the first is compared with BoomerAMG)")
      ->delimiter(',')
      ->check(CLI::PositiveNumber);
  app.add_option("--amg-coarse-cycles", options.amg_coarse_cycles,
                 "cycles per coarse level of the project's AMG (1: V-cycle, 2: W-cycle), each timed")
      ->delimiter(',')
      ->check(CLI::Range(1, 2));
  app.add_option("--time-step-per-spacing", options.time_step_per_spacing, "time.time_step / particle_spacing, s/m")
      ->check(CLI::PositiveNumber);
  app.add_option("--repeats", options.repeats, "timings per solve; the best is reported")->check(CLI::PositiveNumber);
  app.add_option("--from-step", options.from_step, "record the first system at or after this step")
      ->check(CLI::PositiveNumber);
  app.add_option("--json", options.json, "write the results here");
  app.add_flag("--check", options.check, "fail unless every solve converges and the two solvers agree");
  app.add_option("--max-difference", options.max_difference, "largest relative difference --check accepts");
  int status = 0;
  try {
    app.parse(argc, argv);
    const nlohmann::json results = run_comparison(options, ranks, rank);
    if (rank == 0 && !options.json.empty()) mps_lab::write_file_atomically(options.json, results.dump(1) + "\n");
  } catch (const CLI::ParseError& error) {
    status = rank == 0 ? app.exit(error) : 1;
  } catch (const std::exception& error) {
    std::fprintf(stderr, "mps_lab_solver_bench: %s\n", error.what());
    status = 1;
  }
  HYPRE_Finalize();
  MPI_Finalize();
  return status;
}
