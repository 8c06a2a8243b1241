#pragma once
// Wall treatments: one interface for every way a method keeps fluid out of walls.
//
// A wall treatment is a strategy object with hooks at fixed points of a time step. A
// method declares the hooks its step calls (MethodInfo::wall_hooks); a treatment overrides
// only the hooks where it acts and declares them (WallTreatmentInfo::hooks). Two roles
// (docs/walls.md):
//   measure   corrects particles at a hook: the spec's four anti-penetration measures
//             (spec §6: CFL clamp, repulsion, position clamp, collision). Any number per run.
//   boundary  how the wall enters the operators: wall particles whose pressure the method
//             computes by a wall-particle model it implements (a WallParticleModel: solved in
//             the PPE, Adami extrapolation, Akinci mirroring), or wall samples that every method
//             with MethodInfo::wall_samples sums over like neighbours (dummy_layers,
//             mirror_particles, distance_function; core/walls/wall_samples.hpp). Exactly one per run.
// Whether a method may use a treatment is computed from these declarations alone
// (wall_treatment_supports, core/run/method.hpp): no treatment names a method.
//
// Adding a treatment: add core/walls/<name>.cpp defining
//   void mps_lab_register_wall_treatment_<name>(mps_lab::WallTreatmentRegistry&);
// CMake finds the file and the registration function is called by builtin_wall_treatments().
#include <functional>
#include <initializer_list>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/base/parameters.hpp"
#include "core/base/particles.hpp"
#include "core/run/profile.hpp"
#include "core/search/neighbour_search.hpp"
#include "core/walls/wall_samples.hpp"

namespace mps_lab {

class CheckpointReader;  // core/io/checkpoint.hpp

struct Scene;

// The points of a time step where a method calls the wall treatments (WallTreatment below).
enum class WallHook : unsigned {
  AfterExplicitVelocity = 1u << 0,  // after_explicit_velocity
  AfterExplicitPosition = 1u << 1,  // after_explicit_position
  AfterNeighbourSearch = 1u << 2,   // after_neighbour_search
  AfterCorrection = 1u << 3,        // after_correction
};
constexpr WallHook kAllWallHooks[] = {WallHook::AfterExplicitVelocity, WallHook::AfterExplicitPosition,
                                      WallHook::AfterNeighbourSearch, WallHook::AfterCorrection};
const char* wall_hook_name(WallHook hook);  // "after_explicit_velocity", ...

// A set of hooks: those a method calls, those where a treatment acts.
class WallHooks {
 public:
  constexpr WallHooks() = default;
  constexpr WallHooks(std::initializer_list<WallHook> hooks) {
    for (const WallHook hook : hooks) bits_ |= static_cast<unsigned>(hook);
  }
  static constexpr WallHooks all() {
    return {WallHook::AfterExplicitVelocity, WallHook::AfterExplicitPosition, WallHook::AfterNeighbourSearch,
            WallHook::AfterCorrection};
  }
  constexpr bool contains(WallHook hook) const { return (bits_ & static_cast<unsigned>(hook)) != 0; }
  constexpr bool contains(WallHooks other) const { return (other.bits_ & ~bits_) == 0; }
  constexpr bool intersects(WallHooks other) const { return (bits_ & other.bits_) != 0; }
  constexpr bool empty() const { return bits_ == 0; }
  constexpr WallHooks without(WallHooks other) const { return WallHooks(bits_ & ~other.bits_); }
  constexpr bool operator==(WallHooks other) const { return bits_ == other.bits_; }
  constexpr bool operator!=(WallHooks other) const { return bits_ != other.bits_; }
  std::string names() const;  // "after_explicit_velocity, after_correction"; "none" when empty

 private:
  constexpr explicit WallHooks(unsigned bits) : bits_(bits) {}
  unsigned bits_ = 0;
};

// The models of wall particles: what a method's operators do with the wall particles of the
// ParticleSet. A boundary model of wall particles is one of them; a method lists those it
// implements (MethodInfo::wall_particle_models).
enum class WallParticlePressure {
  SolvedInPpe,        // wall particles in every sum, the layers nearest the fluid PPE unknowns (MPS spec §4, §8)
  AdamiExtrapolated,  // pressure = kernel average of the fluid's plus the hydrostatic head (Adami et al. 2012)
  AkinciMirrored,     // boundary mass Psi_b, the fluid particle's own pressure mirrored (Akinci et al. 2012)
};
const char* wall_particle_pressure_name(WallParticlePressure model);  // "solved_in_ppe", ...

// The volume V_b a wall particle stands for in the sums of a wall-particle model.
enum class WallParticleVolume {
  Lattice,    // V_b = the fluid particle's volume, the lattice cell (l0^2 at m = rho0 l0^2)
  KernelSum,  // V_b = 1 / sum_k W_bk over the wall particles (Akinci et al. 2012, eq. 4)
};

// What the hooks see: the particles, the current neighbour list (may be null before the
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

  // The driver reordered the particles between two steps (core/search/cell_order.hpp): a
  // treatment that keeps per-particle data from one step to the next moves it with
  // permute_values (core/base/particle_order.hpp). None of the present ones does (their
  // per-particle arrays are rebuilt within a hook); the default does nothing.
  virtual void permute_state(const ParticleOrder&) {}
};

// A boundary model of wall particles: the strategy object the method asks what to do with the
// wall particles of the ParticleSet (walls.layers layers along the tank sides and inside the
// obstacles, core/io/geometry.hpp). The method implements the model in its operators and reads
// here its settings, typed, instead of the model's parameters by key.
class WallParticleModel : public WallTreatment {
 public:
  virtual WallParticlePressure pressure() const = 0;
  // Wall layers, counted from the fluid (ParticleSet::wall_layer 1, 2, ...), whose particles take
  // part in the pressure: PPE unknowns (SolvedInPpe), boundary particles (AkinciMirrored); the
  // outer layers only fill the sums or are ignored. A negative value: every layer.
  virtual int pressure_layers() const { return -1; }
  virtual WallParticleVolume volume() const { return WallParticleVolume::Lattice; }
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
  std::string description;                // one line
  std::vector<ParameterSpec> parameters;  // "enabled" is added by the registry
  // Order among treatments acting at the same hook: lower runs first.
  int order = 0;
  std::function<std::unique_ptr<WallTreatment>(const WallTreatmentSetup&)> create;
  WallTreatmentRole role = WallTreatmentRole::Measure;
  // The hooks where it acts (the WallTreatment methods it overrides). A method must call each
  // of them, except those in `optional_hooks`: hooks it acts at when the method has that point
  // in its step, and may go without (a position clamp after an explicit position update that
  // a method without one does not make). A measure needs at least one hook.
  WallHooks hooks = {};
  WallHooks optional_hooks = {};
  // Boundary models only: the model of wall particles it is (the WallTreatment it creates is
  // then a WallParticleModel), or none for a boundary model of wall samples.
  std::optional<WallParticlePressure> wall_particle_model = std::nullopt;
  // Boundary models only: its wall follows the obstacles that move (walls.obstacles[k].motion,
  // core/walls/moving_walls.hpp). A scene with a moving obstacle needs a boundary model that does.
  bool moving_walls = false;
  // Derived, set by WallTreatmentRegistry::add: a boundary model of wall particles (the
  // ParticleSet holds walls.layers layers of them) rather than wall samples.
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
  // (core/run/profile.hpp) when it is not null. `called`: the hooks the method declares
  // (MethodInfo::wall_hooks); a treatment that needs another one, or a call of a hook not
  // declared, is a std::logic_error.
  WallTreatmentSet(const std::vector<WallTreatmentChoice>& choices, const Scene& scene, PhaseTimers* timers = nullptr,
                   WallHooks called = WallHooks::all());
  void after_explicit_velocity(WallContext& context);
  void after_explicit_position(WallContext& context);
  void after_neighbour_search(WallContext& context);
  void after_correction(WallContext& context);
  // The boundary model's samples (clears `samples` for a model of wall particles).
  void build_wall_samples(const WallContext& context, WallSampleList& samples);
  // Every member's permute_state; a method calls it from its own Method::permute_state.
  void permute_state(const ParticleOrder& order);
  std::vector<std::string> names() const;
  bool empty() const { return members_.empty(); }
  // The enabled boundary model: its name (for run.json), whether it is made of wall particles,
  // and, for a model of wall particles, the strategy object the method reads it from (null for
  // wall samples or no boundary model).
  const std::string& boundary_name() const { return boundary_name_; }
  bool wall_particles() const { return wall_particles_; }
  const WallParticleModel* wall_particle_model() const { return wall_particle_model_; }

 private:
  std::vector<std::pair<std::string, std::unique_ptr<WallTreatment>>> members_;
  PhaseTimers* timers_ = nullptr;
  PhaseTimers::Id phase_ = 0;
  void check_called(WallHook hook) const;
  WallHooks called_ = WallHooks::all();
  WallTreatment* boundary_ = nullptr;
  const WallParticleModel* wall_particle_model_ = nullptr;
  std::string boundary_name_;
  bool wall_particles_ = true;
};

// The once-per-step search of a method with one operator support (m): every particle's
// neighbours within `support` from the cell list (timed as `search_phase` of `timers`), then the
// boundary model's wall samples within it (none for wall particles), handed to the wall
// treatments in `context` (context.samples, context.support).
void search_neighbours_and_wall_samples(const ParticleSet& particles, double support, PhaseTimers* timers,
                                        PhaseTimers::Id search_phase, CellList& cells, NeighbourList& neighbours,
                                        WallTreatmentSet& walls, WallContext& context, WallSampleList& samples);

// A method's restored search state (core/io/checkpoint.hpp) must fit the scene: a neighbour list
// of `particle_count` particles, and wall samples exactly when the boundary model has no wall
// particles, with one offset per particle; otherwise `in.fail` names `method` and what does not fit.
void check_restored_search(CheckpointReader& in, const std::string& method, const NeighbourList& neighbours,
                           const WallSampleList& samples, const WallTreatmentSet& walls, std::size_t particle_count);

// The enabled boundary model among a method's choices; null for a method that runs without one
// (the scene loader allows that only for a method with no default boundary model).
const WallTreatmentChoice* boundary_choice(const std::vector<WallTreatmentChoice>& choices);

}  // namespace mps_lab
