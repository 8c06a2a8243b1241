#pragma once
// Wall treatments: one interface for every way a method keeps fluid out of walls.
//
// A wall treatment is a strategy object with hooks at fixed points of a time step. A
// method calls the hooks it has (see docs/architecture.md for which method calls which);
// a treatment overrides only the hooks where it acts. The spec's four anti-penetration
// measures (spec §6) are four treatments in core/walls/, one file each.
//
// Adding a treatment: add core/walls/<name>.cpp defining
//   void mps_lab_register_wall_treatment_<name>(mps_lab::WallTreatmentRegistry&);
// CMake finds the file and the registration function is called by builtin_wall_treatments().
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/neighbour_search.hpp"
#include "core/parameters.hpp"
#include "core/particles.hpp"

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
  WallTreatmentSet(const std::vector<WallTreatmentChoice>& choices, const Scene& scene);
  void after_explicit_velocity(WallContext& context);
  void after_explicit_position(WallContext& context);
  void after_neighbour_search(WallContext& context);
  void after_correction(WallContext& context);
  std::vector<std::string> names() const;
  bool empty() const { return members_.empty(); }

 private:
  std::vector<std::pair<std::string, std::unique_ptr<WallTreatment>>> members_;
};

}  // namespace mps_lab
