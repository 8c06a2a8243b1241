#include "core/run/driver.hpp"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <fstream>

#include <omp.h>
#include <unistd.h>

#include "core/base/error.hpp"
#include "core/io/checkpoint.hpp"
#include "core/io/geometry.hpp"
#include "core/io/output.hpp"
#include "core/run/profile.hpp"
#include "core/run/thread_governor.hpp"
#include "core/search/cell_order.hpp"
#include "core/walls/obstacle_membership.hpp"

namespace mps_lab {

namespace {

using Clock = std::chrono::steady_clock;

constexpr std::size_t kTestedParticles = 10000;
// The side of the cells the particles are ordered by, in l0: about a kernel support, so that a
// particle's neighbours lie in a few runs of memory (docs/performance.md, "Cell-ordered particles").
constexpr double kCellOrderSpacings = 2.0;

double seconds_since(Clock::time_point start) { return std::chrono::duration<double>(Clock::now() - start).count(); }

std::string utc_timestamp() {
  const std::time_t now = std::time(nullptr);
  std::tm parts{};
  gmtime_r(&now, &parts);
  char buffer[32];
  std::strftime(buffer, sizeof buffer, "%Y-%m-%dT%H:%M:%SZ", &parts);
  return buffer;
}

}  // namespace

std::vector<std::string> series_columns(const MethodInfo& method, const Scene& scene) {
  std::vector<std::string> columns = {"step",
                                      "time",
                                      "dt",
                                      "front",
                                      "front_max_x",
                                      "height",
                                      "kinetic_energy",
                                      "max_speed",
                                      "density_error",
                                      "fluid_particles",
                                      "ghost_particles",
                                      "solver_iterations",
                                      "solver_residual",
                                      "wall_seconds",
                                      "courant_number",
                                      "mechanical_energy",
                                      "stability_events"};
  for (const auto& sensor : scene.diagnostics.pressure_sensors) {
    columns.push_back("pressure_" + sensor.name);           // Pa, time-weighted mean since the previous row
    columns.push_back("pressure_" + sensor.name + "_max");  // Pa, peak since the previous row
  }
  const std::vector<std::string> bodies = RigidBodies::series_columns(scene);  // docs/bodies.md
  columns.insert(columns.end(), bodies.begin(), bodies.end());
  columns.insert(columns.end(), method.series_columns.begin(), method.series_columns.end());
  if (reports_obstacle_loads(scene, method)) {  // core/walls/obstacle_loads.hpp, docs/walls.md
    for (std::size_t k = 0; k < scene.walls.obstacles.size(); ++k) {
      const std::string name = "obstacle_" + std::to_string(k);
      columns.insert(columns.end(), {name + "_fx", name + "_fy", name + "_torque"});  // N/m, N/m, N
    }
  }
  return columns;
}

namespace {

// Wall particles exist only for a boundary model made of them (core/walls/wall_treatment.hpp).
bool wants_wall_particles(const Scene& scene, const MethodInfo& info) {
  const WallTreatmentChoice* boundary = boundary_choice(scene.method_config(info.name).wall_treatments);
  return boundary == nullptr || boundary->info->wall_particles;
}

// A moving obstacle needs a boundary model whose wall follows it (WallTreatmentInfo::moving_walls)
// and a method whose operators use the walls' velocity (MethodInfo::moving_walls).
void check_moving_walls(const Scene& scene, const MethodInfo& method, const MethodConfig& config) {
  if (!scene.walls.any_moving()) return;
  const WallTreatmentChoice* boundary = boundary_choice(config.wall_treatments);
  const bool model_moves = boundary != nullptr && boundary->info->moving_walls;
  if (model_moves && method.moving_walls) return;
  std::size_t k = 0;
  while (!scene.walls.moving(k)) ++k;
  const std::string why =
      !method.moving_walls
          ? "method '" + method.name + "' does not use a wall's velocity; expected a method that does"
          : "the boundary model " + (boundary != nullptr ? boundary->info->name : std::string("(none)")) +
                " does not move walls; expected a boundary model that does";
  throw_input_error(scene.source,
                    "walls.obstacles[" + std::to_string(k) + "]." + (scene.walls.is_body(k) ? "body" : "motion"),
                    why + " (docs/walls.md, \"Moving walls\")");
}

// A body moves under the fluid's load: the run must be able to report it (core/run/method.hpp).
void check_body_loads(const Scene& scene, const MethodInfo& method) {
  for (std::size_t k = 0; k < scene.walls.obstacles.size(); ++k) {
    if (!scene.walls.is_body(k) || reports_obstacle_loads(scene, method)) continue;
    throw_input_error(
        scene.source, "walls.obstacles[" + std::to_string(k) + "].body",
        "a body needs the fluid's load on it, but " + obstacle_loads_gap(scene, method) + " (docs/bodies.md)");
  }
}

}  // namespace

Simulation::Simulation(const Scene& scene, const MethodInfo& info, PressureSystemObserver pressure_system_observer)
    : scene_(scene),
      info_(info),
      particles_(build_particles(scene, wants_wall_particles(scene, info))),
      moving_walls_(scene, particles_),
      bodies_(scene),
      obstacle_of_id_(obstacle_of_wall_particles(scene, particles_)),
      reports_loads_(mps_lab::reports_obstacle_loads(scene, info)),
      wall_particles_(wants_wall_particles(scene, info)),
      monitor_(scene, scene.stability),
      sensors_(scene) {
  for (const auto& field : info.fields) particles_.add_field(field.name);
  const MethodConfig& config = scene.method_config(info.name);
  check_moving_walls(scene, info, config);
  check_body_loads(scene, info);
  loads_.reset(scene.walls.obstacles.size());
  place_moving_walls(0.0);
  method_ = info.create(
      MethodSetup{scene, config.parameters, config.wall_treatments, &timers_, std::move(pressure_system_observer)});
  check_all_read(config.parameters, "method '" + info.name + "'");
  method_->initialise(particles_);
  monitor_.start(particles_, bodies_mechanical_energy(bodies_, scene_));
  timers_.reset();  // initialise() may have timed phases: they count as setup
  timers_.add(timers_.phase("setup"),
              std::chrono::duration<double>(PhaseTimers::Clock::now() - setup_started_).count());
}

// The wall particles of moving obstacles where they are at time t (s): a motion law's pose at t,
// a body's from its state (where the last advance() left it).
void Simulation::place_moving_walls(double t) {
  if (!scene_.walls.any_moving()) return;  // (a boundary model of wall samples has no members but moves too)
  std::vector<RigidPose> poses = moving_walls_.law_poses(t);
  bodies_.set_poses(poses);
  moving_walls_.apply(particles_, poses);
  particles_.obstacle_pose = std::move(poses);  // the boundary models of wall samples follow them
}

void Simulation::reorder_by_cell() {
  const auto timed = timers_.measure(cell_order_phase_);
  const ParticleOrder order =
      cell_order(particles_.position, particles_.type, kCellOrderSpacings * scene_.particle_spacing);
  if (order.is_identity()) return;
  permute_particles(particles_, order);
  moving_walls_.permute(order);
  method_->permute_state(order);
}

const StepReport& Simulation::advance() {
  // The schedule is a function of the step index alone, which a checkpoint holds: a resumed
  // run reorders before the same steps as the uninterrupted one.
  const long long period = scene_.run.sort_period;
  if (period > 0 && steps_ > 0 && steps_ % period == 0) reorder_by_cell();
  const double dt = method_->time_step(particles_);
  // The clock: a compensated sum of the steps. Moving walls are put where their laws have them
  // at the end of the step, the time the pressure solve is for; a body where the previous
  // step's advance() left it (docs/bodies.md, "Order in the step").
  const double increment = dt - time_compensation_;
  const double next_time = time_ + increment;
  place_moving_walls(next_time);
  try {
    report_ = method_->step(particles_, dt);
  } catch (const std::runtime_error& error) {
    // A method that meets a blown-up state in the middle of a step (the neighbour search
    // refuses non-finite or absurdly spread positions) has diverged; anything else is a
    // failure of its own (status "failed").
    monitor_.check_blow_up(particles_, steps_ + 1, time_ + dt, error.what());
    throw;
  }
  if (report_.extra.size() != info_.series_columns.size()) {
    throw std::logic_error("method '" + info_.name + "' reported " + std::to_string(report_.extra.size()) +
                           " statistics for " + std::to_string(info_.series_columns.size()) + " declared columns");
  }
  // The bodies after the method's step, under this step's fluid load (docs/bodies.md).
  sum_loads(next_time);
  bodies_.advance(dt, loads_);
  ++steps_;
  time_compensation_ = (next_time - time_) - increment;
  time_ = next_time;
  last_dt_ = dt;
  total_iterations_ += report_.solver_iterations;
  max_iterations_ = std::max(max_iterations_, report_.solver_iterations);
  const auto timed = timers_.measure(diagnostics_phase_);
  monitor_.check_step(particles_, report_, steps_, time_, dt,
                      bodies_mechanical_energy(bodies_, scene_));  // throws RunStopped
  sensors_.sample(particles_, dt);
  return report_;
}

// The loads on the obstacles of the step that ends at t (s): the fluid's pressure over their surface
// (a load of kind FluidPressure), or the method's reaction on wall particles, or with a boundary
// model of wall samples on the samples (sum_wall_sample_loads).
void Simulation::sum_loads(double t) {
  if (!reports_loads_) return;
  if (method_->obstacle_load_kind() == ObstacleLoadKind::FluidPressure) {
    start_obstacle_loads(scene_, t, loads_);
    if (!surface_loads_) surface_loads_ = std::make_unique<SurfacePressureLoads>(scene_);
    surface_loads_->add(particles_, loads_);
  } else if (wall_particles_) {
    const std::vector<Vec2>* reaction = method_->wall_reactions();
    if (reaction == nullptr || reaction->size() != particles_.size()) {
      throw std::logic_error("method '" + info_.name + "' declares obstacle_loads but reported no reaction on its " +
                             std::to_string(particles_.size()) + " particles");
    }
    sum_obstacle_loads(scene_, particles_, obstacle_of_id_, *reaction, t, loads_);
  } else {
    start_obstacle_loads(scene_, t, loads_);
    sum_wall_sample_loads();
  }
  // A body's load about where its centre of mass is in this step (the pose the fluid saw):
  // T_c = T_ref + (ref - x_c) x F.
  for (std::size_t b = 0; b < bodies_.size(); ++b) {
    const std::size_t k = bodies_.obstacle(b);
    const Vec2 centre = bodies_.state(b).position;
    const Vec2 arm = loads_.reference[k] - centre;
    loads_.torque[k] += arm.x() * loads_.force[k].y() - arm.y() * loads_.force[k].x();
    loads_.reference[k] = centre;
  }
}

// With a boundary model of wall samples (MethodInfo::sample_obstacle_loads): the method's reaction on
// each obstacle's samples.
void Simulation::sum_wall_sample_loads() {
  const WallSampleLoads* sample_loads = method_->wall_sample_loads();
  if (sample_loads == nullptr || sample_loads->force.size() != loads_.size()) {
    throw std::logic_error("method '" + info_.name + "' declares sample_obstacle_loads but reported no load on the " +
                           std::to_string(loads_.size()) + " obstacles' wall samples");
  }
  add_wall_sample_loads(*sample_loads, loads_);
}

void Simulation::run_to(double end_time) {
  while (time_ + 1e-6 * method_->time_step(particles_) < end_time) advance();
}

namespace {

void write_report(CheckpointWriter& out, const StepReport& report) {
  out.write_int(report.solver_iterations);
  out.write_double(report.solver_residual);
  out.write_bool(report.solver_converged);
  out.write_string(report.solver_note);
  out.write_size(report.speed_limited_particles);
  out.write_doubles(report.extra);
}

void read_report(CheckpointReader& in, StepReport& report) {
  report.solver_iterations = in.read_int();
  report.solver_residual = in.read_double();
  report.solver_converged = in.read_bool();
  report.solver_note = in.read_string();
  report.speed_limited_particles = in.read_size();
  report.extra = in.read_doubles();
}

void write_stability_state(CheckpointWriter& out, const StabilityState& state) {
  for (double value : {state.initial_energy, state.energy_scale, state.last_energy, state.last_courant,
                       state.last_density_error, state.min_wall_distance}) {
    out.write_double(value);
  }
  out.write_size(state.initial_fluid);
  out.write_size(state.ghosts);
  out.write_size(state.ghosts_through_walls);
  out.write_size(state.last_penetrations);
  out.write_int(state.events_total);
  out.write_size(state.counts.size());
  for (long long count : state.counts) out.write_int(count);
  out.write_size(state.log.size());
  for (const auto& event : state.log) {
    out.write_int(event.step);
    out.write_double(event.time);
    out.write_string(event.kind);
    out.write_string(event.detail);
  }
}

void read_stability_state(CheckpointReader& in, StabilityState& state) {
  for (double* value : {&state.initial_energy, &state.energy_scale, &state.last_energy, &state.last_courant,
                        &state.last_density_error, &state.min_wall_distance}) {
    *value = in.read_double();
  }
  state.initial_fluid = in.read_size();
  state.ghosts = in.read_size();
  state.ghosts_through_walls = in.read_size();
  state.last_penetrations = in.read_size();
  state.events_total = in.read_int();
  state.counts.resize(in.read_size());
  for (long long& count : state.counts) count = in.read_int();
  state.log.resize(in.read_size());
  for (auto& event : state.log) {
    event.step = in.read_int();
    event.time = in.read_double();
    event.kind = in.read_string();
    event.detail = in.read_string();
  }
}

}  // namespace

// One section per part of the state. Further state of Simulation goes into a new section,
// appended below (and read back in restore_checkpoint under the same name).
void Simulation::save_checkpoint(CheckpointWriter& out) const {
  out.begin_section("simulation");
  out.write_string(info_.name);
  out.write_double(time_);
  out.write_double(time_compensation_);
  out.write_int(steps_);
  out.write_double(last_dt_);
  write_report(out, report_);
  out.write_int(total_iterations_);
  out.write_int(max_iterations_);
  out.end_section();

  out.begin_section("particles");
  write_particles(out, particles_);
  out.end_section();

  out.begin_section("method");
  method_->save_state(out);
  out.end_section();

  out.begin_section("stability");
  write_stability_state(out, monitor_.state());
  out.end_section();

  out.begin_section("pressure_sensors");
  sensors_.save(out);
  out.end_section();

  if (!bodies_.empty()) {  // a scene without bodies writes the checkpoint it wrote before them
    out.begin_section("bodies");
    bodies_.save(out);
    out.end_section();
  }
}

void Simulation::restore_checkpoint(CheckpointReader& in) {
  in.begin_section("simulation");
  const std::string method = in.read_string();
  if (method != info_.name) in.fail("a checkpoint of method '" + method + "', this run is '" + info_.name + "'");
  time_ = in.read_double();
  time_compensation_ = in.read_double();
  steps_ = in.read_int();
  last_dt_ = in.read_double();
  read_report(in, report_);
  total_iterations_ = in.read_int();
  max_iterations_ = in.read_int();
  in.end_section();

  in.begin_section("particles");
  read_particles(in, particles_);
  in.end_section();
  // The checkpoint holds the particles in their order at that step (cell-ordered particles);
  // what this Simulation built from the scene is in the initial order, where the index is the
  // id: the moving walls' members and their prescribed motion follow the particles.
  const ParticleOrder from_initial = ParticleOrder::from_old_indices(particles_.id);
  permute_values(particles_.wall_velocity, from_initial);
  permute_values(particles_.wall_acceleration, from_initial);
  moving_walls_.permute(from_initial);

  in.begin_section("method");
  method_->restore_state(in);
  in.end_section();

  in.begin_section("stability");
  read_stability_state(in, monitor_.state());
  in.end_section();

  in.begin_section("pressure_sensors");
  sensors_.restore(in);
  in.end_section();

  if (!bodies_.empty()) {
    in.begin_section("bodies");
    bodies_.restore(in);
    in.end_section();
  }
}

namespace {

// The run.json of a run to resume, checked: a summary of mps_lab that can be continued
// (InputError naming the file otherwise).
nlohmann::json read_resumable_summary(const std::filesystem::path& directory, const std::optional<double>& end_time) {
  const std::string path = (directory / "run.json").string();
  std::ifstream file(path);
  if (!file) throw_input_error(path, "", "cannot open the run summary (is " + directory.string() + " a run folder?)");
  nlohmann::json summary;
  try {
    summary = nlohmann::json::parse(file);
  } catch (const nlohmann::json::exception&) {
    throw_input_error(path, "", "not valid JSON");
  }
  const auto require = [&](const char* key, bool valid, const char* expected) {
    if (!valid)
      throw_input_error(path, key, std::string("missing or not ") + expected + ": not a run summary of mps_lab");
  };
  require("method", summary.is_object() && summary.contains("method") && summary["method"].is_string(), "a string");
  require("scene_resolved", summary.contains("scene_resolved") && summary["scene_resolved"].is_object(), "an object");
  require("status", summary.contains("status") && summary["status"].is_string(), "a string");
  if (summary["status"] == "completed") {
    const double finished = summary.value("simulated_time", 0.0);
    if (!end_time || *end_time <= finished) {
      throw_input_error(
          path, "status",
          "the run is complete (t = " + format_double(finished) + " s); give a later --end-time to continue it");
    }
  }
  return summary;
}

// The scene of a resumed run: the document it ran (scene_resolved) with this resume's overrides.
Scene resumed_scene(const std::filesystem::path& directory, const nlohmann::json& summary,
                    const std::vector<std::string>& overrides, const MethodRegistry& methods,
                    const WallTreatmentRegistry& walls) {
  const std::string source = (directory / "run.json").string();
  nlohmann::json document = summary["scene_resolved"];
  for (const auto& assignment : overrides) apply_override(document, assignment, source);
  return parse_scene(std::move(document), source, methods, walls);
}

// What a run is: the scene (loaded, or a resumed run's with its new overrides), the overrides
// run.json records, the method, and the run.json of the run it resumes.
struct RunSetup {
  bool resuming = false;
  nlohmann::json previous;  // the resumed run's run.json
  Scene scene;
  std::vector<std::string> overrides;
  const MethodInfo* info = nullptr;
};

// This invocation's command-line options as --set assignments, so that run.json's
// scene_resolved holds them and a resumed run runs the same scene.
std::vector<std::string> invocation_overrides(const RunOptions& options, bool resuming) {
  std::vector<std::string> overrides = resuming ? std::vector<std::string>() : options.overrides;
  if (options.end_time) overrides.push_back("time.end_time=" + format_double(*options.end_time));
  if (options.checkpoint_every_steps) {
    overrides.push_back("output.checkpoint_every_steps=" + std::to_string(*options.checkpoint_every_steps));
  }
  return overrides;
}

// The registered method called `name` (InputError listing the registered ones otherwise).
const MethodInfo& find_method(const MethodRegistry& methods, const std::string& name) {
  const MethodInfo* info = methods.find(name);
  if (info == nullptr) {
    std::string known;
    for (const auto& registered : methods.names()) known += (known.empty() ? "" : ", ") + registered;
    throw_input_error("--method", name, "unknown method (registered: " + known + ")");
  }
  return *info;
}

RunSetup resolve_run(const RunOptions& options, const MethodRegistry& methods, const WallTreatmentRegistry& walls) {
  RunSetup setup;
  setup.resuming = !options.resume_directory.empty();
  const std::vector<std::string> new_overrides = invocation_overrides(options, setup.resuming);
  if (setup.resuming) setup.previous = read_resumable_summary(options.resume_directory, options.end_time);
  setup.scene = setup.resuming ? resumed_scene(options.resume_directory, setup.previous, new_overrides, methods, walls)
                               : load_scene(options.scene_path, new_overrides, methods, walls);
  setup.overrides = setup.resuming ? setup.previous.value("overrides", std::vector<std::string>()) : new_overrides;
  if (setup.resuming) setup.overrides.insert(setup.overrides.end(), new_overrides.begin(), new_overrides.end());
  const std::string method_name = setup.resuming           ? setup.previous["method"].get<std::string>()
                                  : options.method.empty() ? setup.scene.method
                                                           : options.method;
  setup.info = &find_method(methods, method_name);
  if (options.load_setting && !setup.resuming) {
    // The scene again, with the method's load setting first: the method is known only now.
    setup.overrides = with_load_setting(*setup.info, new_overrides);
    setup.scene = load_scene(options.scene_path, setup.overrides, methods, walls);
  }
  return setup;
}

std::filesystem::path run_directory(const RunOptions& options, const RunSetup& setup) {
  if (setup.resuming) return options.resume_directory;
  return options.output_directory.empty() ? std::filesystem::path(setup.scene.output.directory)
                                          : std::filesystem::path(options.output_directory);
}

// run.json "validation": the scene's experiment with the records' resolved paths, for the
// analysis (analysis/mps_lab/pressure.py reads it; the scene's own paths are relative to it).
nlohmann::json validation_summary(const ValidationControl& validation) {
  nlohmann::json records = nlohmann::json::array();
  for (const auto& record : validation.pressure_records) {
    records.push_back({{"sensor", record.sensor}, {"file", record.file}});
  }
  return {{"length_scale", validation.length_scale},
          {"impact_threshold", validation.impact_threshold},
          {"quasi_static", {validation.quasi_static.x(), validation.quasi_static.y()}},
          {"pressure_records", records}};
}

// The run.json entries of a run's invariants: scene, parameters, wall treatments, shared
// physics, the initial particles and column.
nlohmann::json new_run_summary(const RunOptions& options, const RunSetup& setup, const FlowMeasures& initial,
                               std::size_t particles) {
  const Scene& scene = setup.scene;
  const MethodInfo& info = *setup.info;
  nlohmann::json summary;
  summary["program"] = "mps_lab";
  summary["git_revision"] = git_revision();
  summary["started_at"] = utc_timestamp();
  summary["method"] = info.name;
  summary["method_description"] = info.description;
  summary["scene"] = options.scene_path;
  summary["overrides"] = setup.overrides;
  summary["scene_resolved"] = scene.document;
  summary["parameters"] = scene.method_config(info.name).parameters.to_json();
  nlohmann::json wall_summary = nlohmann::json::object();
  for (const auto& choice : scene.method_config(info.name).wall_treatments) {
    wall_summary[choice.info->name] = choice.parameters.to_json();
  }
  summary["wall_treatments"] = wall_summary;
  summary["shared"] = {{"particle_spacing", scene.particle_spacing},
                       {"density", scene.physics.density},
                       {"kinematic_viscosity", scene.physics.kinematic_viscosity},
                       {"gravity", {scene.physics.gravity.x(), scene.physics.gravity.y()}},
                       {"time_step", scene.time.time_step},
                       {"end_time", scene.time.end_time},
                       {"frame_every_steps", scene.output.frame_every_steps},
                       {"series_every_steps", scene.output.series_every_steps},
                       {"front_link_distance", scene.diagnostics.front_link_distance},
                       {"height_probe_width", scene.diagnostics.height_probe_width}};
  summary["particles"] = {{"fluid", initial.fluid}, {"wall", initial.wall}, {"total", particles}};
  summary["column"] = {{"width", initial.front}, {"height", initial.height}};
  if (scene.validation.length_scale > 0.0) summary["validation"] = validation_summary(scene.validation);
  summary["threads"] = omp_get_max_threads();
  // Spec §3 note: the original code had static arrays of 10000 particles; this core has no
  // limit, but says so when a scene goes beyond what the validation runs covered.
  summary["notes"] = nlohmann::json::array();
  if (!obstacle_loads_gap(scene, info).empty()) {  // a scene with obstacles whose loads this run cannot report
    summary["notes"].push_back("no obstacle_<k> load columns: " + obstacle_loads_gap(scene, info));
  }
  if (particles > kTestedParticles) {
    const std::string note = std::to_string(particles) +
                             " particles: beyond the 10000 of the specification's original code (spec §3) and the "
                             "validated runs of this testbed (at most 6000); no limit applies, but check the results";
    summary["notes"].push_back(note);
    if (options.progress) std::fprintf(stderr, "mps_lab: note: %s\n", note.c_str());
  }
  return summary;
}

// The resumed run's run.json with this session's scene, threads and a "resumed" entry.
nlohmann::json resumed_run_summary(const RunOptions& options, const RunSetup& setup, const Simulation& simulation) {
  const nlohmann::json& previous = setup.previous;
  nlohmann::json summary = previous;
  summary.erase("message");
  summary["overrides"] = setup.overrides;
  summary["scene_resolved"] = setup.scene.document;
  summary["shared"]["end_time"] = setup.scene.time.end_time;
  summary["threads"] = omp_get_max_threads();
  if (!summary["notes"].is_array()) summary["notes"] = nlohmann::json::array();
  if (previous.value("threads", 0) != omp_get_max_threads()) {
    const std::string note = "resumed with " + std::to_string(omp_get_max_threads()) + " threads, run before with " +
                             previous.value("threads", nlohmann::json()).dump() +
                             ": bit-for-bit continuation is guaranteed for the same thread count";
    summary["notes"].push_back(note);
    if (options.progress) std::fprintf(stderr, "mps_lab: note: %s\n", note.c_str());
  }
  summary["resumed"].push_back({{"from_step", simulation.steps()},
                                {"from_time", simulation.time()},
                                {"previous_status", previous["status"]},
                                {"at", utc_timestamp()},
                                {"end_time", setup.scene.time.end_time},
                                {"threads", omp_get_max_threads()}});
  return summary;
}

// One run (or one session of a resumed run): the simulation, its output and the driver's
// bookkeeping between steps (when the next frame and series row are due by simulated time,
// the wall time of earlier sessions, the last checkpoint).
class RunSession {
 public:
  RunSession(const RunOptions& options, const RunSetup& setup, std::filesystem::path directory,
             Clock::time_point started)
      : options_(options),
        setup_(setup),
        scene_(setup.scene),
        info_(*setup.info),
        started_(started),
        directory_(std::move(directory)),
        output_(directory_, {scene_.output.csv, scene_.output.vtk, scene_.output.vtu}, series_columns(info_, scene_)),
        output_prepared_(setup.resuming ? false : (output_.prepare(), true)),  // before the particles are built
        simulation_(scene_, info_),
        initial_(measure_flow(simulation_.particles(), scene_, flow_workspace_)),
        next_frame_time_(scene_.output.frame_interval),
        next_series_time_(scene_.output.series_interval),
        timers_(simulation_.timers()),
        output_phase_(timers_.phase("output")),
        diagnostics_phase_(timers_.phase("diagnostics")),
        governor_(ThreadGovernorSettings{omp_get_max_threads(), options.threads}) {}

  RunResult run();

 private:
  double wall_seconds() const { return earlier_wall_seconds_ + seconds_since(started_); }
  void restore_checkpoint();
  void write_starting_summary();
  std::vector<double> series_row(const FlowMeasures& measures);
  void record(bool frame);
  template <typename Dropped>
  void record_post_mortem();
  bool crossed(double interval, double& next) const;
  void write_checkpoint();
  std::string advance_to_end();
  void show_progress(long long step);
  void finish(const std::string& stop_reason, RunResult& result);
  void write_final_summary(const RunResult& result);

  const RunOptions& options_;
  const RunSetup& setup_;
  const Scene& scene_;
  const MethodInfo& info_;
  const Clock::time_point started_;
  const double started_cpu_seconds_ = process_cpu_seconds();  // s, at the session's start
  const std::filesystem::path directory_;
  RunOutput output_;
  const bool output_prepared_;
  Simulation simulation_;
  FlowWorkspace flow_workspace_;  // the measures' search storage, reused by every series row
  const FlowMeasures initial_;
  double next_frame_time_;
  double next_series_time_;
  double earlier_wall_seconds_ = 0.0;
  PhaseTimers& timers_;
  const PhaseTimers::Id output_phase_;
  const PhaseTimers::Id diagnostics_phase_;
  nlohmann::json summary_;
  long long checkpoint_step_ = -1;
  long long first_step_ = 0;
  double first_time_ = 0.0;
  bool show_progress_ = false;
  Clock::time_point last_progress_;
  ThreadGovernor governor_;
};

// checkpoint.bin of the run folder: the simulation's sections, the driver's ("run") and the
// output's bookkeeping; InputError when it is missing or ends before the new end time.
void RunSession::restore_checkpoint() {
  const auto checkpoint_path = directory_ / "checkpoint.bin";
  if (!std::filesystem::exists(checkpoint_path)) {
    throw_input_error(checkpoint_path.string(), "",
                      "no checkpoint to resume from (a run writes one with --checkpoint-every N, and when stopped "
                      "by Ctrl-C or SIGTERM)");
  }
  CheckpointReader checkpoint = CheckpointReader::from_file(checkpoint_path, git_revision());
  simulation_.restore_checkpoint(checkpoint);
  checkpoint.begin_section("run");
  next_frame_time_ = checkpoint.read_double();
  next_series_time_ = checkpoint.read_double();
  earlier_wall_seconds_ = checkpoint.read_double();
  checkpoint.end_section();
  checkpoint.begin_section("output");
  output_.restore_state(checkpoint);
  checkpoint.end_section();
  if (scene_.time.end_time < simulation_.time()) {
    throw_input_error("--end-time", format_double(scene_.time.end_time),
                      "expected at least the checkpoint's time " + format_double(simulation_.time()) + " s (" +
                          checkpoint_path.string() + ")");
  }
  output_.prepare_resume();
}

void RunSession::write_starting_summary() {
  summary_ = setup_.resuming ? resumed_run_summary(options_, setup_, simulation_)
                             : new_run_summary(options_, setup_, initial_, simulation_.particles().size());
  summary_["shared"]["checkpoint_every_steps"] = scene_.output.checkpoint_every_steps;
  summary_["status"] = "running";
  output_.write_summary(summary_);
}

// A row of series.csv (series_columns): the step, the flow measures, the solver and the
// monitor, the sensors (mean and peak since the previous row, which starts a new interval),
// then the method's columns (zeros before the first step), then the loads on the obstacles.
std::vector<double> RunSession::series_row(const FlowMeasures& measures) {
  const StepReport& report = simulation_.last_report();
  std::vector<double> row = {static_cast<double>(simulation_.steps()),
                             simulation_.time(),
                             simulation_.last_time_step(),
                             measures.front,
                             measures.front_max_x,
                             measures.height,
                             measures.kinetic_energy,
                             measures.max_speed,
                             measures.density_error,
                             static_cast<double>(measures.fluid),
                             static_cast<double>(measures.ghost),
                             static_cast<double>(report.solver_iterations),
                             report.solver_residual,
                             wall_seconds(),
                             simulation_.monitor().state().last_courant,
                             simulation_.monitor().state().last_energy,
                             static_cast<double>(simulation_.monitor().state().events_total)};
  const std::vector<double> sensors = simulation_.pressure_sensors().take_row(simulation_.particles());
  row.insert(row.end(), sensors.begin(), sensors.end());
  simulation_.bodies().append_series(row);
  if (simulation_.steps() == 0) {
    row.resize(row.size() + info_.series_columns.size(), 0.0);
  } else {
    row.insert(row.end(), report.extra.begin(), report.extra.end());
  }
  if (simulation_.reports_obstacle_loads()) {  // the last step's loads; zeros before the first step
    const ObstacleLoads& loads = simulation_.obstacle_loads();
    for (std::size_t k = 0; k < scene_.walls.obstacles.size(); ++k) {
      const bool known = k < loads.size();
      row.insert(row.end(),
                 {known ? loads.force[k].x() : 0.0, known ? loads.force[k].y() : 0.0, known ? loads.torque[k] : 0.0});
    }
  }
  return row;
}

// A series row, and a frame when asked.
void RunSession::record(bool frame) {
  const FlowMeasures measures = [&] {
    const auto timed = timers_.measure(diagnostics_phase_);
    return measure_flow(simulation_.particles(), scene_, flow_workspace_);
  }();
  const auto timed = timers_.measure(output_phase_);
  output_.add_series_row(series_row(measures));
  output_.write_series_when_due();
  if (frame) {
    output_.write_frame(simulation_.particles(), info_.fields, simulation_.time(), simulation_.steps(),
                        "mps_lab " + info_.name);
  }
}

// Output by step count (the spec's rule) and, when the scene asks, by simulated time, so
// that methods with adaptive steps are sampled at the same times as the others.
bool RunSession::crossed(double interval, double& next) const {
  if (interval <= 0.0) return false;
  if (simulation_.time() < next - 1e-6 * simulation_.last_time_step()) return false;
  while (next <= simulation_.time() + 1e-6 * simulation_.last_time_step()) next += interval;
  return true;
}

// checkpoint.bin: the simulation's sections, then the driver's ("run") and the output's
// bookkeeping; run.json then says where the run stands.
void RunSession::write_checkpoint() {
  const auto timed = timers_.measure(output_phase_);
  CheckpointWriter checkpoint;
  simulation_.save_checkpoint(checkpoint);
  checkpoint.begin_section("run");
  checkpoint.write_double(next_frame_time_);
  checkpoint.write_double(next_series_time_);
  checkpoint.write_double(wall_seconds());
  checkpoint.end_section();
  checkpoint.begin_section("output");
  output_.save_state(checkpoint);
  checkpoint.end_section();
  write_file_atomically(directory_ / "checkpoint.bin", checkpoint.file_content(git_revision()));
  checkpoint_step_ = simulation_.steps();
  summary_["checkpoint"] = {{"file", "checkpoint.bin"}, {"step", simulation_.steps()}, {"time", simulation_.time()}};
  summary_["steps"] = simulation_.steps();
  summary_["simulated_time"] = simulation_.time();
  output_.write_summary(summary_);
}

void RunSession::show_progress(long long step) {
  if (!show_progress_ || seconds_since(last_progress_) <= 0.5) return;
  last_progress_ = Clock::now();
  const double end_time = scene_.time.end_time;
  const double elapsed = seconds_since(started_);
  const double rate = static_cast<double>(step - first_step_) / elapsed;
  const double eta = elapsed * (end_time - simulation_.time()) / std::max(simulation_.time() - first_time_, 1e-12);
  std::fprintf(stderr, "\r%s  t = %.4f / %.4f s  step %lld  %.0f steps/s  ETA %.0f s   ", info_.name.c_str(),
               simulation_.time(), end_time, step, rate, eta);
  std::fflush(stderr);
}

// The time loop: a step, its series row and frame when due, a checkpoint when due, the stop
// request. Returns the stop reason (empty when the end time was reached).
std::string RunSession::advance_to_end() {
  const long long checkpoint_every = scene_.output.checkpoint_every_steps;
  std::string stop_reason;
  while (simulation_.time() + 1e-6 * simulation_.method().time_step(simulation_.particles()) < scene_.time.end_time) {
    governor_.next_team();
    const auto step_started = Clock::now();
    simulation_.advance();
    const long long step = simulation_.steps();
    const bool frame_by_time = crossed(scene_.output.frame_interval, next_frame_time_);
    const bool series_by_time = crossed(scene_.output.series_interval, next_series_time_);
    const bool frame = step % scene_.output.frame_every_steps == 0 || frame_by_time;
    if (frame || series_by_time || step % scene_.output.series_every_steps == 0) record(frame);
    if (checkpoint_every > 0 && step % checkpoint_every == 0) write_checkpoint();
    // The whole step as the run pays for it, its output included: beside a busy process, two
    // threads ran wcsph's steps no slower than one but its output 4x slower (the idle OpenMP
    // thread spinning against the frame writer; docs/performance.md, "Threads that never hurt").
    governor_.record(seconds_since(step_started));
    if (options_.stop_reason) stop_reason = options_.stop_reason();
    if (!stop_reason.empty()) break;
    show_progress(step);
  }
  return stop_reason;
}

// After the loop: a run stopped on request writes the checkpoint first, so that it lists
// only the regular output; the extra frame of this step shows where the run stands, and
// `resume` removes it (the uninterrupted run has no frame here). A completed run keeps its
// final state, so that `resume --end-time` can extend it.
void RunSession::finish(const std::string& stop_reason, RunResult& result) {
  if (!stop_reason.empty()) {
    result.status = "interrupted";
    result.message = "stopped by " + stop_reason + " at t = " + format_double(simulation_.time()) + " s (step " +
                     std::to_string(simulation_.steps()) + "); continue with: mps_lab resume " + directory_.string();
    if (checkpoint_step_ != simulation_.steps()) write_checkpoint();
    if (output_.last_frame_step() != simulation_.steps()) record(true);
  } else {
    if (output_.last_frame_step() != simulation_.steps()) record(true);
    if (scene_.output.checkpoint_every_steps > 0 && checkpoint_step_ != simulation_.steps()) write_checkpoint();
  }
}

// The state where a run broke or failed, for a post-mortem (ParaView shows where). A
// blown-up state may not be measurable (the search refuses it) or writable: then the
// exception is dropped (a runtime_error after a stop, any exception after a failure) and
// run.json still says why.
template <typename Dropped>
void RunSession::record_post_mortem() {
  try {
    record(true);
  } catch (const Dropped&) {
  }
}

void RunSession::write_final_summary(const RunResult& result) {
  // Particle counts at the end (not measure_flow: a blown-up state may not be searchable).
  std::size_t fluid_final = 0, ghost_final = 0;
  for (const ParticleType type : simulation_.particles().type) {
    fluid_final += type == ParticleType::Fluid ? 1 : 0;
    ghost_final += type == ParticleType::Ghost ? 1 : 0;
  }
  summary_["status"] = result.status;
  if (!result.message.empty()) summary_["message"] = result.message;
  summary_["steps"] = result.steps;
  summary_["simulated_time"] = result.simulated_time;
  summary_["wall_seconds"] = result.wall_seconds;
  summary_["particles"]["ghost_final"] = ghost_final;
  summary_["particles"]["fluid_final"] = fluid_final;
  summary_["frames"] = output_.frames_written();
  summary_["solver"] = {
      {"total_iterations", simulation_.total_solver_iterations()},
      {"max_iterations", simulation_.max_solver_iterations()},
      {"mean_iterations",
       result.steps > 0 ? static_cast<double>(simulation_.total_solver_iterations()) / static_cast<double>(result.steps)
                        : 0.0}};
  summary_["method_summary"] = simulation_.method().summary();
  summary_["stability"] = simulation_.monitor().summary();
  summary_["fluid_particle_steps_per_second"] =
      result.wall_seconds > 0
          ? static_cast<double>(initial_.fluid) * static_cast<double>(result.steps) / result.wall_seconds
          : 0.0;
  // This session's phases (a resumed run profiles the steps since it resumed).
  summary_["profile"] =
      profile_json(timers_, seconds_since(started_), simulation_.steps() - first_step_, initial_.fluid);
  summary_["profile"]["threads"] = governor_.summary().at("max_threads");
  // CPU seconds of this session (all threads, user + system): the cost load barely touches.
  summary_["profile"]["cpu_seconds"] = process_cpu_seconds() - started_cpu_seconds_;
  summary_["threads_used"] = governor_.summary();
  // The process's peak resident memory (the whole program: at 1e6 particles the particle
  // data dominates; for small scenes the program's own ~10 MB does).
  const std::size_t peak_memory = peak_resident_memory_bytes();
  summary_["memory"] = {
      {"peak_resident_bytes", peak_memory},
      {"bytes_per_particle", static_cast<double>(peak_memory) /
                                 static_cast<double>(std::max<std::size_t>(1, simulation_.particles().size()))}};
  output_.write_summary(summary_);
}

RunResult RunSession::run() {
  RunResult result;
  result.directory = directory_;
  if (setup_.resuming) restore_checkpoint();
  write_starting_summary();
  checkpoint_step_ = setup_.resuming ? simulation_.steps() : -1;
  show_progress_ = options_.progress && ::isatty(STDERR_FILENO) != 0;
  first_step_ = simulation_.steps();
  first_time_ = simulation_.time();
  last_progress_ = Clock::now();
  if (!setup_.resuming) record(true);
  result.status = "completed";
  try {
    finish(advance_to_end(), result);
  } catch (const OutputError&) {
    throw;
  } catch (const RunStopped& stopped) {
    result.status = stopped.status();
    result.message = stopped.what();
    record_post_mortem<std::runtime_error>();
  } catch (const std::runtime_error& error) {
    result.status = "failed";
    result.message = error.what();
    record_post_mortem<std::exception>();
  }
  if (show_progress_) std::fprintf(stderr, "\r%*s\r", 100, "");
  result.steps = simulation_.steps();
  result.simulated_time = simulation_.time();
  result.wall_seconds = wall_seconds();
  write_final_summary(result);
  result.summary = summary_;
  return result;
}

}  // namespace

RunResult run_simulation(const RunOptions& options, const MethodRegistry& methods, const WallTreatmentRegistry& walls) {
  const auto started = Clock::now();
  const RunSetup setup = resolve_run(options, methods, walls);
  RunSession session(options, setup, run_directory(options, setup), started);
  return session.run();
}

}  // namespace mps_lab
