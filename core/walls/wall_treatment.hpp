#pragma once
// Wall treatments: one interface for every way a method keeps fluid out of walls.
//
// A wall treatment is a strategy object with hooks at fixed points of a time step. A
// method calls the hooks it has (see docs/architecture.md for which method calls which);
// a treatment overrides only the hooks where it acts. Two roles (docs/walls.md):
//   measure   corrects particles at a hook: the spec's four anti-penetration measures
//             (spec §6: CFL clamp, repulsion, position clamp, collision). Any number per run.
//   boundary  how the wall enters the operators: wall particles the method handles itself
//             (spec_wall_particles for mps, adami_wall_particles for isph, akinci_boundary
//             for dfsph), or wall samples that every method sums over like neighbours
//             (dummy_layers, mirror_particles, distance_function; core/walls/wall_samples.hpp).
//             Exactly one per run.
//
// Adding a treatment: add core/walls/<name>.cpp defining
//   void mps_lab_register_wall_treatment_<name>(mps_lab::WallTreatmentRegistry&);
// CMake finds the file and the registration function is called by builtin_wall_treatments().
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/search/neighbour_search.hpp"
#include "core/base/parameters.hpp"
#include "core/base/particles.hpp"
#include "core/run/profile.hpp"
#include "core/walls/wall_samples.hpp"

namespace mps_lab {

struct Scene;

// What a hook sees: the particles, the current neighbour list (may be null before the
// first search of a step), the time step and the scene (geometry, spacing, physics).
// A treatment that caps particle speeds counts them in `speed_limited`; the method passes
// the count on (StepReport), and the stability monitor reports a step whose flow is set
// by the cap rather than by the equations.
struct WallContext {
  ParticleSet& particles;
  const NeighbourList* neighbours;
  double dt;  // s
  const Scene& scene;
  std::size_t speed_limited = 0;  // fluid particles whose speed was capped in this step
  // The wall samples of this step (null or empty for a boundary model of wall particles);
  // a measure that acts near walls (repulsion) reads them where there are no wall particles.
  const WallSampleList* samples = nullptr;
  // The method's operator support, m: build_wall_samples gives each fluid particle the wall
  // samples closer than this. The neighbour list passed with it has at least this radius.
  double support = 0.0;
};

class WallTreatment {
 public:
  virtual ~WallTreatment() = default;
  // After the explicit velocity update u* = u^n + dt a (MPS spec §5.1-4).
  virtual void after_explicit_velocity(WallContext&) {}
  // After the explicit position update r* = r^n + dt u* (MPS spec §5.1-7).
  virtual void after_explicit_position(WallContext&) {}
  // After the neighbour search at the provisional positions, before the pressure solve
  // (MPS spec §5.2-2, 5.2-3).
  virtual void after_neighbour_search(WallContext&) {}
  // After the pressure correction (MPS spec §5.2-10).
  virtual void after_correction(WallContext&) {}

  // Boundary models of wall samples: right after each neighbour search, the samples of every
  // fluid particle within context.support (core/walls/wall_samples.hpp). `samples.offsets` gets
  // size N + 1; particles that are not fluid get no samples.
  virtual void build_wall_samples(const WallContext&, WallSampleList&) {}
};

enum class WallTreatmentRole {
  Measure,   // corrects particles at the hooks
  Boundary,  // represents the wall in the operators; exactly one per run
};

struct WallTreatmentSetup {
  const Scene& scene;
  const ParameterValues& parameters;
};

struct WallTreatmentInfo {
  std::string name;
  std::string description;                  // one line
  std::vector<std::string> methods;         // methods that may use it
  std::vector<ParameterSpec> parameters;    // "enabled" is added by the registry
  // Order among treatments acting at the same hook: lower runs first.
  int order = 0;
  std::function<std::unique_ptr<WallTreatment>(const WallTreatmentSetup&)> create;
  WallTreatmentRole role = WallTreatmentRole::Measure;
  // Boundary models only: true when the wall is made of particles in the ParticleSet
  // (walls.layers layers along the tank sides and inside the obstacles, core/io/geometry.hpp),
  // which the method treats in its own operators; false for wall samples.
  bool wall_particles = false;
};

class WallTreatmentRegistry {
 public:
  void add(WallTreatmentInfo info);  // throws std::logic_error on a duplicate name
  const WallTreatmentInfo* find(const std::string& name) const;
  std::vector<const WallTreatmentInfo*> all() const;  // by name

 private:
  std::map<std::string, WallTreatmentInfo> entries_;
};

// Every treatment compiled into this build (generated from core/walls/*.cpp).
WallTreatmentRegistry builtin_wall_treatments();

// A treatment as resolved from a scene: its info, its parameters, enabled or not.
struct WallTreatmentChoice {
  const WallTreatmentInfo* info = nullptr;
  ParameterValues parameters;
  bool enabled = false;
};

// The ordered set of enabled treatments of one run; calls each hook on every member.
class WallTreatmentSet {
 public:
  WallTreatmentSet() = default;
  // Every hook and build_wall_samples are timed as the phase "wall_treatment" of `timers`
  // (core/run/profile.hpp) when it is not null.
  WallTreatmentSet(const std::vector<WallTreatmentChoice>& choices, const Scene& scene,
                   PhaseTimers* timers = nullptr);
  void after_explicit_velocity(WallContext& context);
  void after_explicit_position(WallContext& context);
  void after_neighbour_search(WallContext& context);
  void after_correction(WallContext& context);
  // The boundary model's samples (clears `samples` for a model of wall particles).
  void build_wall_samples(const WallContext& context, WallSampleList& samples);
  std::vector<std::string> names() const;
  bool empty() const { return members_.empty(); }
  // The enabled boundary model: its name, whether it is made of wall particles, and its
  // parameters (a method reads those of the particle models it implements itself, e.g. the
  // Akinci volume rule of dfsph).
  const std::string& boundary_name() const { return boundary_name_; }
  bool wall_particles() const { return wall_particles_; }
  const ParameterValues& boundary_parameters() const { return boundary_parameters_; }

 private:
  std::vector<std::pair<std::string, std::unique_ptr<WallTreatment>>> members_;
  PhaseTimers* timers_ = nullptr;
  PhaseTimers::Id phase_ = 0;
  WallTreatment* boundary_ = nullptr;
  std::string boundary_name_;
  bool wall_particles_ = true;
  ParameterValues boundary_parameters_;
};

// The enabled boundary model among a method's choices; null for a method that runs without one
// (the scene loader allows that only for a method with no default boundary model).
const WallTreatmentChoice* boundary_choice(const std::vector<WallTreatmentChoice>& choices);

}  // namespace mps_lab
