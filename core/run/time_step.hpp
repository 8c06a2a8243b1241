#pragma once
// Time-step rules a method may offer through its own parameters, and the clock of an adaptive
// step. A method that declares time_step_parameters() reads
//   time_step_rule  "fixed": the scene's time.time_step every step;
//                   "cfl":   dt = cfl_number l0 / v_max, clamped to [min_time_step, max_time_step]
//                            (Courant-Friedrichs-Lewy with the particle spacing l0; v_max is the
//                            method's estimate of the largest fluid speed in the coming step)
//   cfl_number, min_time_step, max_time_step (s)
// and keeps a TimeStepClock, which evens out the last one or two steps so that the run ends
// exactly on time.end_time (the driver stops at end_time; a last sliver of a step would be a
// step of arbitrary size).
//
// Used by dfsph (default "cfl", [BK17] Algorithm 1), isph and eisph (default "fixed"; "cfl" as in
// Shao & Lo 2003, dt <= 0.1-0.25 h / v_max) and mps (default "fixed", the spec's dt, spec §3;
// "cfl" for scenes whose flow is slow for much of the run, docs/methods/mps.md, "Time step").
#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/base/parameters.hpp"
#include "core/base/particles.hpp"

namespace mps_lab {

class CheckpointWriter;
class CheckpointReader;

struct TimeStepSettings {
  bool cfl = false;              // false: the scene's time.time_step
  double fixed_time_step = 0.0;  // s, the scene's time.time_step
  double cfl_number = 0.4;       // dt = cfl_number l0 / v_max
  double min_time_step = 0.0;    // s
  double max_time_step = 0.0;    // s
};

// The four declarations, with a method's defaults; cfl_source and bounds_source cite where the
// defaults come from (shown by `mps_lab methods --parameters`).
struct TimeStepDefaults {
  std::string rule = "fixed";  // "fixed" | "cfl"
  double cfl_number = 0.4;
  double min_time_step = 1.0e-4;  // s
  double max_time_step = 5.0e-3;  // s
  std::string cfl_source;         // e.g. "BK17: 0.4"
  std::string bounds_source;      // e.g. "SPlisHSPlasH default"
};
std::vector<ParameterSpec> time_step_parameters(const TimeStepDefaults& defaults);

// Reads the four parameters; `fixed_time_step` is the scene's time.time_step. Throws an
// InputError naming `source` (the scene file) and the key when min_time_step > max_time_step.
TimeStepSettings time_step_settings(const ParameterValues& parameters, double fixed_time_step,
                                    const std::string& source);

// The simulated time of a method with its own step, summed as the driver sums it (Kahan), and
// the smallest, largest and mean step for the run summary.
class TimeStepClock {
 public:
  // Before the first step: `first_estimate` (s) is what last() returns until a step is taken.
  void start(double first_estimate) { last_ = first_estimate; }

  // The next step under `settings`; `max_speed` (m/s, >= 0) is the method's estimate of the
  // largest fluid speed; 0 gives max_time_step. A fixed rule returns the scene's step as is.
  double next(const TimeStepSettings& settings, double max_speed, double spacing, double end_time) const;

  void advance(double dt);

  double elapsed() const { return elapsed_; }  // s
  double last() const { return last_; }        // s, the last step taken (or the first estimate)
  long long steps() const { return steps_; }

  // {"rule", "min", "max", "mean"} (s; 0 before the first step).
  nlohmann::json summary(const TimeStepSettings& settings) const;

  void save(CheckpointWriter& out) const;
  void restore(CheckpointReader& in);

 private:
  double elapsed_ = 0.0, compensation_ = 0.0;                                  // s
  double last_ = 0.0;                                                          // s
  double smallest_ = std::numeric_limits<double>::infinity(), largest_ = 0.0;  // s
  long long steps_ = 0;
};

// max_i |u_i| over the fluid particles, m/s: the speed of a CFL step rule.
double largest_fluid_speed(const ParticleSet& particles);

// v_max of the CFL rule for a method that keeps no per-particle acceleration between steps
// (mps, isph, eisph): max_i |u_i| over the fluid plus |g| dt_prev, the speed a particle can
// gain under gravity in the coming step (viscosity only slows it). At rest before the first step
// it is 0, and the first step is max_time_step. m/s.
double largest_speed_with_gravity(const ParticleSet& particles, const Vec2& gravity, const TimeStepClock& clock);

}  // namespace mps_lab
