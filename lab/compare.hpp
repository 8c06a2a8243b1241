#pragma once
// Comparing methods on one scene: run each method into its own folder, then measure every
// run the same way (lab/validation.hpp) and write summary.csv, one row per method.
#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "core/run/method.hpp"
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {

// What summary.csv holds for one run; every number is recomputed from the run folder
// (run.json and series.csv), so evaluate_run can check any folder, not only fresh runs.
struct RunEvaluation {
  std::string method;
  std::string status;
  long long steps = 0;
  double wall_seconds = 0.0;
  double particle_steps_per_second = 0.0;  // fluid particles x steps / wall seconds
  double mean_solver_iterations = 0.0;
  double front_rms = 0.0;  // Z = front / a vs Martin & Moyce Table 2 at its T points
  double front_max = 0.0;
  std::size_t front_points = 0;
  double front_shift = 0.0;  // best T shift in [-0.3, 0.3] (positive: simulation ahead)
  double front_rms_shifted = 0.0;
  double height_rms = 0.0;  // H* vs Martin & Moyce Table 6 at its tau points
  double height_max = 0.0;
  std::size_t height_points = 0;
  double density_error_mean = 0.0;  // time average of the common density_error column
  double density_error_max = 0.0;
  long long ghosts = 0;
};

RunEvaluation evaluate_run(const std::filesystem::path& folder);

// Column names and one CSV line per evaluation.
std::string summary_csv(const std::vector<RunEvaluation>& rows);

struct CompareOptions {
  std::string scene_path;
  std::vector<std::string> methods;  // empty: every registered method
  std::filesystem::path output_directory;
  std::vector<std::string> overrides;
  std::optional<double> end_time;
  bool load_setting = false;  // each method's setting for wall loads (RunOptions::load_setting)
  bool progress = false;
  std::function<std::string()> stop_reason;  // as RunOptions::stop_reason; polled in every run
};

// Runs every method (a failed run is recorded, not fatal), writes <out>/<method>/ and
// <out>/summary.csv. An interrupted run (stop_reason) is the last one: the methods after it
// are not run. Throws InputError for a bad scene or an unknown method name.
std::vector<RunEvaluation> compare_methods(const CompareOptions& options, const MethodRegistry& methods,
                                           const WallTreatmentRegistry& walls);

}  // namespace mps_lab
