#pragma once
// The run driver: builds the particles of a scene, creates the chosen method through the
// registry, advances it to the end time, and writes frames, series.csv and run.json.
//
// Simulation is the in-memory part (used by tests and by run_simulation); run_simulation
// adds the output and the progress line.
#include <filesystem>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/bodies/rigid_bodies.hpp"
#include "core/io/scene.hpp"
#include "core/run/diagnostics.hpp"
#include "core/run/method.hpp"
#include "core/run/pressure_sensors.hpp"
#include "core/run/profile.hpp"
#include "core/run/stability.hpp"
#include "core/walls/moving_walls.hpp"
#include "core/walls/obstacle_loads.hpp"
#include "core/walls/surface_pressure_loads.hpp"

namespace mps_lab {

class CheckpointWriter;
class CheckpointReader;

class Simulation {
 public:
  // `pressure_system_observer` goes to the method (MethodSetup): empty in a run.
  Simulation(const Scene& scene, const MethodInfo& method, PressureSystemObserver pressure_system_observer = {});
  // It keeps a reference to its scene: a temporary one would dangle (caught by AddressSanitizer in a
  // test as stack-use-after-scope), so it is refused at compile time.
  Simulation(const Scene&& scene, const MethodInfo& method,
             PressureSystemObserver pressure_system_observer = {}) = delete;

  // Advances one step; returns the step's report. Before a step whose index (steps()) is a
  // positive multiple of the scene's run.sort_period, the particles are first reordered by cell
  // (reorder_by_cell). The stability monitor checks the new
  // state and throws RunStopped when the scene's "stability" block says the run must stop
  // (always for a non-finite state).
  const StepReport& advance();

  const Scene& scene() const { return scene_; }
  const MethodInfo& method_info() const { return info_; }
  const Method& method() const { return *method_; }
  const StabilityMonitor& monitor() const { return monitor_; }
  // The rigid bodies (walls.obstacles[k].body; core/bodies/rigid_bodies.hpp), advanced after
  // every method step.
  const RigidBodies& bodies() const { return bodies_; }
  // Per-phase timers of this process's steps (core/run/profile.hpp): "setup" (particles and the
  // method's initialisation), the method's phases and "diagnostics" (the stability monitor).
  // Not part of a checkpoint: a resumed run profiles its own session.
  PhaseTimers& timers() { return timers_; }
  const PhaseTimers& timers() const { return timers_; }
  ParticleSet& particles() { return particles_; }
  const ParticleSet& particles() const { return particles_; }
  double time() const { return time_; }
  long long steps() const { return steps_; }
  double last_time_step() const { return last_dt_; }
  const StepReport& last_report() const { return report_; }
  // The wall-pressure sensors, read after every step (core/run/pressure_sensors.hpp); a
  // series row takes their mean and peak since the previous row (take_row).
  PressureSensorRecord& pressure_sensors() { return sensors_; }
  const PressureSensorRecord& pressure_sensors() const { return sensors_; }
  // The fluid's load on each obstacle in the last step (core/walls/obstacle_loads.hpp); empty when
  // the run does not report them (reports_obstacle_loads, core/run/method.hpp) or before a step.
  const ObstacleLoads& obstacle_loads() const { return loads_; }
  bool reports_obstacle_loads() const { return reports_loads_; }
  // Totals over all steps so far.
  long long total_solver_iterations() const { return total_iterations_; }
  long long max_solver_iterations() const { return max_iterations_; }
  // Run to scene.time.end_time (or the given time) without output.
  void run_to(double end_time);

  // Checkpoints (core/io/checkpoint.hpp): save_checkpoint writes one section per part of the
  // state (the clock and totals, the particles, the method, the stability monitor);
  // restore_checkpoint, called on a Simulation freshly built from the same scene, reads them
  // back, after which advance() continues bit for bit.
  void save_checkpoint(CheckpointWriter& out) const;
  void restore_checkpoint(CheckpointReader& in);

 private:
  // Cell-ordered particles (core/search/cell_order.hpp): the ParticleSet, the moving walls'
  // members and the method's per-particle state (Method::permute_state) in cell-major order.
  void reorder_by_cell();
  void place_moving_walls(double t);
  void sum_loads(double t);
  void sum_wall_sample_loads();

  PhaseTimers timers_;  // first: the constructor's own time is its "setup" phase
  PhaseTimers::Clock::time_point setup_started_ = PhaseTimers::Clock::now();
  PhaseTimers::Id diagnostics_phase_ = timers_.phase("diagnostics");
  PhaseTimers::Id cell_order_phase_ = timers_.phase("cell_order");
  const Scene& scene_;
  const MethodInfo& info_;
  ParticleSet particles_;
  MovingWalls moving_walls_;                  // obstacles with a motion law or a body (empty: every wall fixed)
  RigidBodies bodies_;                        // obstacles with a body block
  std::vector<std::int32_t> obstacle_of_id_;  // per particle id (core/walls/obstacle_membership.hpp)
  bool reports_loads_ = false;
  bool wall_particles_ = true;  // the boundary model is made of wall particles (else of wall samples)
  // The fluid's pressure over the obstacles' surface, for a method whose load is FluidPressure (made at
  // the first step that needs it).
  std::unique_ptr<SurfacePressureLoads> surface_loads_;
  // The fluid's load on each obstacle in the last step (core/walls/obstacle_loads.hpp); it moves
  // the bodies (advance()).
  ObstacleLoads loads_;
  std::unique_ptr<Method> method_;
  StabilityMonitor monitor_;
  PressureSensorRecord sensors_;
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
  std::string method;                               // empty: the scene's "method"
  std::string output_directory;                     // empty: the scene's output.directory
  std::vector<std::string> overrides;               // "dotted.key=value"
  std::optional<double> end_time;                   // s, overrides time.end_time
  std::optional<long long> checkpoint_every_steps;  // overrides output.checkpoint_every_steps
  // The method's setting for wall loads (MethodInfo::load_setting) before `overrides`, so that
  // an override still wins, and its defaults after them (with_load_setting); run.json records its
  // assignments among the overrides (a resumed run runs the same scene). Ignored when resuming.
  bool load_setting = false;
  // OpenMP threads of every step; 0: chosen by measurement (core/run/thread_governor.hpp).
  int threads = 0;
  bool progress = false;  // progress line on stderr
  // Polled after every step. A non-empty answer (the reason, e.g. "SIGTERM") stops the run
  // after that step: checkpoint.bin, a final frame, run.json with status "interrupted".
  std::function<std::string()> stop_reason;
  // Non-empty: resume the run in this folder from its checkpoint.bin instead of starting one.
  // The scene, method and overrides are those of its run.json; scene_path, method,
  // output_directory and overrides are ignored; end_time and checkpoint_every_steps apply.
  std::filesystem::path resume_directory;
};

struct RunResult {
  std::string status;   // "completed", "interrupted", or why it stopped ("failed", ...)
  std::string message;  // why, when it did not complete
  long long steps = 0;
  double simulated_time = 0.0;
  double wall_seconds = 0.0;
  std::filesystem::path directory;
  nlohmann::json summary;  // what run.json holds
};

// Loads and validates the scene (InputError), prepares the output folder (OutputError),
// then runs. A failure during the run is reported in the result (status "failed") and in
// run.json, not thrown. With options.resume_directory it continues that run instead
// (InputError if its run.json or checkpoint.bin is missing, mismatched or truncated, or if
// the run is complete and no later end time is given).
RunResult run_simulation(const RunOptions& options, const MethodRegistry& methods, const WallTreatmentRegistry& walls);

// The series.csv columns of a run: the common ones, the scene's pressure sensors (mean and peak), the rigid
// bodies' (docs/bodies.md), then the method's own.
std::vector<std::string> series_columns(const MethodInfo& method, const Scene& scene);

const char* git_revision();

}  // namespace mps_lab
