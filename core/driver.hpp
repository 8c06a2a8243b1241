#pragma once
// The run driver: builds the particles of a scene, creates the chosen method through the
// registry, advances it to the end time, and writes frames, series.csv and run.json.
//
// Simulation is the in-memory part (used by tests and by run_simulation); run_simulation
// adds the output and the progress line.
#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/diagnostics.hpp"
#include "core/method.hpp"
#include "core/scene.hpp"

namespace mps_lab {

class Simulation {
 public:
  Simulation(const Scene& scene, const MethodInfo& method);

  // Advances one step; returns the step's report. Throws std::runtime_error if the state
  // stops being finite (a fluid velocity or pressure is NaN/Inf).
  const StepReport& advance();

  const Scene& scene() const { return scene_; }
  const MethodInfo& method_info() const { return info_; }
  const Method& method() const { return *method_; }
  ParticleSet& particles() { return particles_; }
  const ParticleSet& particles() const { return particles_; }
  double time() const { return time_; }
  long long steps() const { return steps_; }
  double last_time_step() const { return last_dt_; }
  const StepReport& last_report() const { return report_; }
  // Totals over all steps so far.
  long long total_solver_iterations() const { return total_iterations_; }
  long long max_solver_iterations() const { return max_iterations_; }
  // Run to scene.time.end_time (or the given time) without output.
  void run_to(double end_time);

 private:
  const Scene& scene_;
  const MethodInfo& info_;
  ParticleSet particles_;
  std::unique_ptr<Method> method_;
  double time_ = 0.0;
  double time_compensation_ = 0.0;  // Kahan summation: 4000 x 5e-4 s ends at 2 s, not 1.9999999999998
  long long steps_ = 0;
  double last_dt_ = 0.0;
  StepReport report_;
  long long total_iterations_ = 0;
  long long max_iterations_ = 0;
};

struct RunOptions {
  std::string scene_path;
  std::string method;                   // empty: the scene's "method"
  std::string output_directory;         // empty: the scene's output.directory
  std::vector<std::string> overrides;   // "dotted.key=value"
  std::optional<double> end_time;       // s, overrides time.end_time
  bool progress = false;                // progress line on stderr
};

struct RunResult {
  std::string status;        // "completed" or "failed"
  std::string message;       // why, when it failed
  long long steps = 0;
  double simulated_time = 0.0;
  double wall_seconds = 0.0;
  std::filesystem::path directory;
  nlohmann::json summary;    // what run.json holds
};

// Loads and validates the scene (InputError), prepares the output folder (OutputError),
// then runs. A failure during the run is reported in the result (status "failed") and in
// run.json, not thrown.
RunResult run_simulation(const RunOptions& options, const MethodRegistry& methods,
                         const WallTreatmentRegistry& walls);

// The series.csv columns of a run: the common ones, the scene's pressure sensors, then the
// method's own.
std::vector<std::string> series_columns(const MethodInfo& method, const Scene& scene);

const char* git_revision();

}  // namespace mps_lab
