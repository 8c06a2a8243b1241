#pragma once
// The stability monitor: on for every run, it watches each step for the ways a particle
// simulation breaks and records every event (series.csv column `stability_events`,
// run.json "stability"). By the scene's "stability" block a divergence either stops the
// run with status "diverged" (message "diverged at t = ... s (step ...), because ...") or
// is recorded and the run goes on; a non-finite state always stops the run, so a run never
// ends "completed" with NaN in its frames. Solver non-convergence is recorded and, by
// `on_solver_failure`, stops the run with status "solver_failed" or goes on.
//
// What counts as divergence (docs/stability.md derives each default):
//   non_finite     a fluid position, velocity or pressure is NaN or Inf
//   courant        max |u| dt / l0 over the fluid exceeds `courant_limit` (a particle that
//                  jumps a whole spacing in one step has left the discretisation behind)
//   speed_limited  a wall treatment (the CFL velocity clamp) capped the speed of more than
//                  `max_speed_limited_fraction` of the fluid in one step: beyond the CFL
//                  limit the clamp hides the instability and sets the flow itself
//   energy_growth  the mechanical energy E = sum(1/2 m|u|^2 - m g.x) exceeds its initial
//                  value by more than `energy_growth_limit` x E_scale: nothing in these
//                  scenes (fixed walls, no inflow) can add energy, viscosity only removes it
//   density        the common density error (diagnostics.hpp, identical for every method)
//                  exceeds `density_error_limit`; checked every `density_check_every_steps`
//   penetration    more than `max_wall_penetrations` fluid particles lie beyond the first
//                  particle line of a wall (inside it, or through it as ghosts)
//   escaped        more than `max_escaped_fraction` of the fluid has left the domain
//                  through an open side (ghosts, spec §7.3: a splash over the tank is
//                  physics); each escape is recorded as an event either way
//   solver         a pressure solver stopped at its iteration cap above its tolerance
#include <cstddef>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/base/parameters.hpp"
#include "core/base/particles.hpp"

namespace mps_lab {

class RigidBodies;

struct FlowWorkspace;

class WallGeometry;

struct Scene;
struct StepReport;

struct StabilitySettings {
  bool stop_on_divergence = true;            // "on_divergence": "stop" | "continue"
  bool stop_on_solver_failure = false;       // "on_solver_failure": "stop" | "continue"
  double courant_limit = 1.0;                // max |u| dt / l0
  double max_speed_limited_fraction = 0.05;  // of the fluid, capped by a wall treatment in one step
  double energy_growth_limit = 0.5;          // allowed (E - E0) / E_scale
  double density_error_limit = 0.2;          // mean |rho/rho_lattice - 1|
  long long density_check_every_steps = 50;
  long long max_wall_penetrations = 0;  // fluid particles beyond a wall's first particle line
  double max_escaped_fraction = 0.05;   // of the initial fluid, through open sides
  long long logged_events = 100;        // events kept in run.json (all are counted)
};

// The keys of the scene's "stability" block, for parsing and docs/scene-format.md.
std::vector<ParameterSpec> stability_keys();
StabilitySettings stability_settings(const ParameterValues& values);

struct StabilityEvent {
  long long step = 0;
  double time = 0.0;   // s
  std::string kind;    // one of stability_event_kinds()
  std::string detail;  // one line with the numbers
};

// Thrown by Simulation::advance when the monitor stops the run. `status` is "diverged" or
// "solver_failed"; what() is the one-line message for run.json and the terminal.
class RunStopped : public std::runtime_error {
 public:
  RunStopped(std::string status, const std::string& message)
      : std::runtime_error(message), status_(std::move(status)) {}
  const std::string& status() const { return status_; }

 private:
  std::string status_;
};

// The monitor's state is plain data, so a checkpoint can save and restore it (every field
// is written by write_stability_state in core/run/driver.cpp: a new field goes there too).
struct StabilityState {
  double initial_energy = 0.0;      // J/m, E at t = 0
  double energy_scale = 0.0;        // J/m, E_scale (see stability_energy_scale)
  double last_energy = 0.0;         // J/m, E after the last step
  double last_courant = 0.0;        // max |u| dt / l0 of the last step
  double last_density_error = 0.0;  // at the last density check
  // The smallest distance of a fluid particle from a wall surface over the run, m
  // (core/walls/wall_geometry.hpp; negative: that far past the surface).
  double min_wall_distance = 0.0;
  std::size_t initial_fluid = 0;
  std::size_t ghosts = 0;                // ghosts after the last step
  std::size_t ghosts_through_walls = 0;  // of those, left through a wall
  std::size_t last_penetrations = 0;     // fluid beyond a wall line + ghosts through walls
  long long events_total = 0;
  std::vector<long long> counts;    // per kind, in the order of stability_event_kinds()
  std::vector<StabilityEvent> log;  // the first `logged_events`
};

const std::vector<std::string>& stability_event_kinds();

// Mechanical energy per metre of depth: sum over fluid of 1/2 m |u|^2 + m g_hat.(x - x_low)
// with potential measured from the domain corner lowest in the gravity field, J/m.
double mechanical_energy(const ParticleSet& particles, const Scene& scene);
// The rigid bodies' part of it (J/m): sum of 1/2 m |u|^2 + 1/2 I omega^2 - m g.(x_c - x_low), with the
// fluid's reference corner x_low: a body that sinks hands its potential energy to the water, which is
// no energy from nowhere (docs/stability.md).
double bodies_mechanical_energy(const RigidBodies& bodies, const Scene& scene);

// E_scale = E0 + 1/2 M u_ref^2 with u_ref = 0.01 l0 / dt: the initial energy plus, for a
// scene without any (zero gravity, fluid at rest), the kinetic energy of the whole fluid
// moving a hundredth of a spacing per step.
double stability_energy_scale(double initial_energy, double fluid_mass, double particle_spacing, double time_step);

class StabilityMonitor {
 public:
  StabilityMonitor(const Scene& scene, StabilitySettings settings);

  // Records the state at t = 0. `body_energy`: the rigid bodies' mechanical energy (J/m,
  // bodies_mechanical_energy), part of the energy the monitor watches.
  void start(const ParticleSet& particles, double body_energy = 0.0);
  // Checks the state after a step; records events; throws RunStopped when the settings say
  // stop (always for a non-finite state).
  void check_step(const ParticleSet& particles, const StepReport& report, long long step, double time, double dt,
                  double body_energy = 0.0);

  // Called when a method's step threw: if the state has blown up (a non-finite value, or a
  // fluid particle more than 1e6 domain sizes away), records it and throws RunStopped
  // ("diverged ... because <what the method said>"); otherwise returns.
  void check_blow_up(const ParticleSet& particles, long long step, double time, const std::string& what);

  const StabilitySettings& settings() const { return settings_; }
  const StabilityState& state() const { return state_; }
  StabilityState& state() { return state_; }       // for checkpoint restore
  long long count(const std::string& kind) const;  // events of one kind so far
  // run.json "stability": settings, counts per kind, first event per kind, the event log.
  nlohmann::json summary() const;

 private:
  // What one pass over the particles finds (scan_particles).
  struct ParticleScan {
    double max_speed2 = 0.0;  // m^2/s^2
    std::size_t ghosts = 0;
    std::size_t beyond_walls = 0;          // fluid beyond a wall's first particle line
    double min_wall_distance = 0.0;        // m
    std::ptrdiff_t first_non_finite = -1;  // -1: every particle finite
  };
  ParticleScan scan_particles(const ParticleSet& particles) const;
  void check_speed(const StepReport& report, double max_speed2, long long step, double time, double dt);
  void check_energy(const ParticleSet& particles, double body_energy, long long step, double time);
  void check_ghosts(const ParticleSet& particles, std::size_t ghosts, long long step, double time);
  void check_penetrations(std::size_t beyond_walls, long long step, double time);
  void check_density_and_solver(const ParticleSet& particles, const StepReport& report, long long step, double time);
  bool beyond_a_wall(const Vec2& x) const;
  void record(long long step, double time, std::size_t kind, const std::string& detail);
  [[noreturn]] void stop(const std::string& status, long long step, double time, const std::string& reason) const;

  const Scene& scene_;
  std::shared_ptr<const WallGeometry> geometry_;  // core/walls/wall_geometry.hpp
  StabilitySettings settings_;
  StabilityState state_;
  // The density check's search storage, reused (core/run/diagnostics.hpp; held by pointer because
  // diagnostics.hpp includes scene.hpp, which includes this file).
  std::shared_ptr<FlowWorkspace> density_workspace_;
};

}  // namespace mps_lab
