#pragma once
// Methods are plugins. A method registers a MethodInfo: its name, a one-line
// description, the parameters it reads (its block in the scene, "methods.<name>"), the
// per-particle fields it needs, the solver statistics it reports, the wall treatments it
// uses by default, its capabilities (the wall hooks its step calls, whether its operators sum
// over wall samples, the wall-particle models it implements) and a factory. The driver runs whatever the scene and
// --method name; the method touches the core only through ParticleSet, the neighbour search, the kernels, the
// wall-treatment hooks and the helpers declared in core/.
//
// Adding a method: add a folder methods/<name>/ whose sources define
//   void mps_lab_register_method_<name>(mps_lab::MethodRegistry&);
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/base/memory_bytes.hpp"
#include "core/base/parameters.hpp"
#include "core/base/particles.hpp"
#include "core/linalg/projection_solver.hpp"
#include "core/run/profile.hpp"
#include "core/walls/wall_sample_reactions.hpp"
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {

struct Scene;
class CheckpointWriter;
class CheckpointReader;

// A per-particle scalar the method needs; written to the VTK frames when `written`.
struct FieldSpec {
  std::string name;
  std::string unit;
  std::string description;
  bool written = true;
};

// What one step reports. `solver_iterations`/`solver_residual` fill the common series
// columns (the main pressure solve); `extra` holds one value per declared series column.
struct StepReport {
  long long solver_iterations = 0;
  double solver_residual = 0.0;
  // False when a solver of this step stopped at its iteration cap above its tolerance; the
  // stability monitor records it and, by the scene's `stability.on_solver_failure`, stops
  // the run or goes on. `solver_note` says which solve (e.g. "PPE residual 3e-5 > 1e-8").
  bool solver_converged = true;
  std::string solver_note;
  // Fluid particles whose speed a wall treatment capped in this step (WallContext).
  std::size_t speed_limited_particles = 0;
  std::vector<double> extra;
};

// What a method's load on obstacles is (Method::obstacle_load_kind):
//   PairReaction     the reaction of its wall pair terms (on wall particles or wall samples): the
//                    fluid receives exactly the opposite, to rounding;
//   SurfacePressure  its wall particles' pressure over the wetted surface they stand for (the
//                    method computes it: Method::wall_reactions);
//   FluidPressure    the fluid's own pressure carried to the obstacles' surface (Adami et al. 2012
//                    eq. 27) and integrated over it by the driver, with any boundary model
//                    (core/walls/surface_pressure_loads.hpp); pressure only, no shear.
enum class ObstacleLoadKind { PairReaction, SurfacePressure, FluidPressure };

class Method {
 public:
  virtual ~Method() = default;
  // Called once with the initial particles (fields already allocated).
  virtual void initialise(ParticleSet& particles) = 0;
  // The time step for the next step, s. May depend on the state (CFL-adaptive methods).
  virtual double time_step(const ParticleSet& particles) const = 0;
  // Advances the particles by dt.
  virtual StepReport step(ParticleSet& particles, double dt) = 0;
  // Method-specific constants and totals for run.json (e.g. n0, lambda, mean iterations).
  virtual nlohmann::json summary() const { return nlohmann::json::object(); }
  // Checkpoints (core/io/checkpoint.hpp, docs/checkpoints.md): everything the method keeps
  // between steps that is not in the ParticleSet (a neighbour list reused by the next step,
  // warm-start values, its clock, the totals of summary()), so that a run restored after
  // initialise() continues bit for bit. restore_state reads what save_state wrote, in order.
  // The defaults suit a method that keeps nothing between steps.
  virtual void save_state(CheckpointWriter&) const {}
  virtual void restore_state(CheckpointReader&) {}
  // Cell-ordered particles (core/search/cell_order.hpp, docs/architecture.md): between two
  // steps the driver has reordered the ParticleSet by `order` (permute_particles). The method
  // moves every per-particle array it keeps from one step to the next the same way: what
  // save_state writes per particle, per-particle constants of initialise(), a kept neighbour
  // list (permute_neighbour_list) or wall samples (permute_wall_samples), and calls its
  // WallTreatmentSet's permute_state. The contract suite checks every method's run with
  // reordering against the same run without. The default suits a method that keeps nothing per
  // particle between steps.
  virtual void permute_state(const ParticleOrder&) {}
  // Loads on obstacles (MethodInfo::obstacle_loads, docs/walls.md "Loads on obstacles"): the force
  // the fluid put on each wall particle in the last step, N/m, one entry per particle in the
  // current order (zero for fluid): minus the sum over its fluid neighbours i of m_i times the
  // acceleration its pair terms (pressure and viscosity) gave i (or, by obstacle_load_kind, its
  // pressure's share of the wetted surface). Computed in every step of a scene with obstacles and a
  // boundary model of wall particles; null otherwise (the default).
  virtual const std::vector<Vec2>* wall_reactions() const { return nullptr; }
  // The same with a boundary model of wall samples (MethodInfo::sample_obstacle_loads): the reaction
  // of the last step's wall terms on each obstacle's samples (core/walls/wall_sample_reactions.hpp),
  // where the method's load is its pair terms' reaction (obstacle_load_kind() PairReaction). With a
  // load of kind FluidPressure neither is needed (null): the driver integrates the fluid's pressure
  // over the obstacles' surface (core/walls/surface_pressure_loads.hpp).
  virtual const WallSampleLoads* wall_sample_loads() const { return nullptr; }
  // What the load is (ObstacleLoadKind above; docs/walls.md, "Loads on obstacles"): PairReaction,
  // SurfacePressure (wall_reactions() holds the wall particles' pressure over the surface, not the
  // exact opposite of the fluid's wall terms) or FluidPressure (the driver's integral).
  virtual ObstacleLoadKind obstacle_load_kind() const { return ObstacleLoadKind::PairReaction; }
  // The heap the method holds between steps, by structure (core/base/memory_bytes.hpp: the
  // capacity of its big containers): `mps_lab bench` reports it beside the resident memory.
  // Empty by default (the bench then reports the particles and the total only).
  virtual MemoryBreakdown memory_breakdown() const { return {}; }
};

struct MethodSetup {
  const Scene& scene;
  const ParameterValues& parameters;
  std::vector<WallTreatmentChoice> wall_treatments;
  // The run's per-phase timers (core/run/profile.hpp); null outside a run. A method times its
  // phases with them and hands them to its WallTreatmentSet.
  PhaseTimers* timers = nullptr;
  // Sees every pressure system the method's projection solver receives (core/linalg/
  // projection_solver.hpp); empty in a run. Methods that solve a linear pressure system hand it
  // to their ProjectionSolver; the solver comparison (lab/solver_comparison/) sets it.
  PressureSystemObserver pressure_system_observer{};
};

// A method's setting for wall loads (docs/validation.md, "Each method's load setting"): values
// of its own parameters to take when the pressure on the walls is what a run is for, and the
// still-water accuracy it then promises. `mps_lab run --load-setting` and `mps_lab compare
// --load-setting` apply it; the contract suite runs each method with it and every boundary model
// it supports on scenes/hydrostatic.json and holds it to its promise.
struct LoadSetting {
  // {parameter, value as JSON} of the method's block, e.g. {"free_surface_offset", "0.5"}.
  std::vector<std::pair<std::string, std::string>> parameters;
  // The promise: |mean / (rho g h) - 1| at the still-water tank's three wall sensors (h = 0.075,
  // 0.15, 0.225 m; means over [0.5, 3] s), with every boundary model, at g and at 1.5 g. 0: none.
  double still_water_tolerance = 0.0;
  std::string basis;  // one line: what the promise rests on (what was measured, where documented)
  // {dotted key inside the method's block, value as JSON}, taken where neither the scene nor a
  // --set gives the key: settings of the wall treatments the method runs with, e.g.
  // {"wall_treatments.particle_collision.distance", "0.9"}. Applied after the invocation's
  // overrides as "key?=value" (apply_override), so that a --set that names the boundary model by
  // replacing the whole wall_treatments block keeps them, and one that gives the key wins.
  std::vector<std::pair<std::string, std::string>> defaults;
};

struct MethodInfo {
  std::string name;
  std::string description;  // one line, for `mps_lab methods`
  std::vector<ParameterSpec> parameters;
  std::vector<FieldSpec> fields;
  std::vector<std::string> series_columns;           // method-specific statistics in series.csv
  std::vector<std::string> default_wall_treatments;  // enabled unless the scene says otherwise
  // Capabilities: which wall treatments the method may use follows from these alone
  // (wall_treatment_supports below).
  // The wall hooks its step calls (WallTreatmentSet checks each call against them).
  WallHooks wall_hooks;
  // True when every operator of the method also sums over wall samples (core/walls/wall_samples.hpp):
  // the method then runs with every boundary model of wall samples, present and future.
  bool wall_samples = false;
  // The models of wall particles its operators implement (WallParticleModel): it runs with
  // every boundary model of wall particles that is one of them.
  std::vector<WallParticlePressure> wall_particle_models;
  // True when its operators use the prescribed velocity and acceleration of moving wall
  // particles (ParticleSet::wall_velocity, wall_acceleration; core/walls/moving_walls.hpp): a
  // scene with a moving obstacle runs only with such a method and a boundary model that moves
  // its walls (WallTreatmentInfo::moving_walls).
  bool moving_walls = false;
  // True when, with every boundary model of wall particles it implements, its step computes the
  // fluid's reaction on each wall particle (Method::wall_reactions), or its load is the fluid's
  // pressure (obstacle_load_kind FluidPressure, integrated by the driver): the driver then has the
  // load on every obstacle (core/walls/obstacle_loads.hpp) and writes it to series.csv.
  bool obstacle_loads = false;
  // True when, with every boundary model of wall samples, its step computes the fluid's reaction on
  // each obstacle's samples (Method::wall_sample_loads) or its load there is the fluid's pressure,
  // which the driver integrates over the surface (obstacle_load_kind FluidPressure): the loads on
  // obstacles are then reported with those models too, and bodies move under them (docs/walls.md).
  bool sample_obstacle_loads = false;
  // Its setting for wall loads (LoadSetting above); empty parameters: the defaults are it.
  LoadSetting load_setting;
  std::function<std::unique_ptr<Method>(const MethodSetup&)> create;
};

class MethodRegistry {
 public:
  void add(MethodInfo info);  // throws std::logic_error on a duplicate name
  const MethodInfo* find(const std::string& name) const;
  std::vector<const MethodInfo*> all() const;  // by name
  std::vector<std::string> names() const;

 private:
  std::map<std::string, MethodInfo> entries_;
};

// Whether a method may use a wall treatment, from the declarations of both alone:
//  - a boundary model of wall samples needs a method whose operators sum over them
//    (MethodInfo::wall_samples); a boundary model of wall particles needs a method that
//    implements its wall-particle model (MethodInfo::wall_particle_models);
//  - the method calls every hook where the treatment acts (WallTreatmentInfo::hooks), except
//    the treatment's optional hooks, and at least one of them.
bool wall_treatment_supports(const WallTreatmentInfo& wall, const MethodInfo& method);
// Why not, in a phrase for an error message ("it acts at after_explicit_velocity, which 'x'
// does not call"); empty when the method may use the treatment.
std::string wall_treatment_support_gap(const WallTreatmentInfo& wall, const MethodInfo& method);

// Whether a run of `method` on `scene` reports the loads on its obstacles: the scene has obstacles
// and the method declares obstacle_loads for the scene's boundary model, if it is made of wall
// particles, or sample_obstacle_loads, if it is a boundary model of wall samples.
bool reports_obstacle_loads(const Scene& scene, const MethodInfo& method);
// Why a scene with obstacles gets no loads from `method`, in a phrase; empty when it does or has none.
std::string obstacle_loads_gap(const Scene& scene, const MethodInfo& method);

// The method's load setting as --set assignments: "methods.<name>.<parameter>=<value>".
std::vector<std::string> load_setting_overrides(const MethodInfo& method);
// Its defaults (LoadSetting::defaults) as assignments "methods.<name>.<key>?=<value>".
std::vector<std::string> load_setting_defaults(const MethodInfo& method);
// What a run with the load setting applies, in this order: load_setting_overrides, then
// `invocation` (the --set of the command line, which win over the setting), then
// load_setting_defaults (taken only where nothing before gave the key).
std::vector<std::string> with_load_setting(const MethodInfo& method, const std::vector<std::string>& invocation);

// Every method compiled into this build (generated from methods/*/).
MethodRegistry builtin_methods();

}  // namespace mps_lab
