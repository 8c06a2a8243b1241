#pragma once
// Per-phase wall-clock timers of a run (issue 7: know where the time goes).
//
// A PhaseTimers holds named phases; code times a phase with a scope:
//   const auto solve = timers.phase("pressure_solve");      // once, at construction
//   { auto timed = timers.measure(solve); ...work... }       // every step
// Phases are exclusive: a timed scope must not contain another one, so that the phases add up
// to the time of the steps ("other" in the report is what no phase covers). The names in use
// (docs/performance.md): neighbour_search, wall_treatment, operators, matrix_assembly,
// pressure_solve, divergence_solve, density_solve, integration (methods and the wall-treatment
// set), diagnostics and output (the driver). A scope costs two clock reads (about 50 ns).
//
// A Method receives the run's PhaseTimers through MethodSetup; a null pointer (a method built
// outside a run, in a test) times nothing.
#include <chrono>
#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace mps_lab {

class PhaseTimers {
 public:
  using Clock = std::chrono::steady_clock;
  using Id = std::size_t;

  struct Phase {
    std::string name;
    double seconds = 0.0;
    long long calls = 0;
  };

  // Measures from construction to destruction; does nothing for a null PhaseTimers.
  class Scope {
   public:
    Scope(PhaseTimers* timers, Id id) : timers_(timers), id_(id) {
      if (timers_ != nullptr) start_ = Clock::now();
    }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;
    ~Scope() {
      if (timers_ != nullptr) timers_->add(id_, std::chrono::duration<double>(Clock::now() - start_).count());
    }

   private:
    PhaseTimers* timers_;
    Id id_;
    Clock::time_point start_;
  };

  // The phase called `name`, registered on first use (the same name gives the same id).
  Id phase(const std::string& name);
  void add(Id id, double seconds) {
    phases_[id].seconds += seconds;
    ++phases_[id].calls;
  }
  Scope measure(Id id) { return Scope(this, id); }

  const std::vector<Phase>& phases() const { return phases_; }
  // The totals of the phase called `name` (zero when there is none).
  double seconds(const std::string& name) const;
  long long calls(const std::string& name) const;
  double total_seconds() const;  // over all phases
  void reset();                  // zero every phase, keep the names

 private:
  std::vector<Phase> phases_;
};

// Times `id` of a possibly null PhaseTimers (what methods hold).
inline PhaseTimers::Scope measure(PhaseTimers* timers, PhaseTimers::Id id) { return PhaseTimers::Scope(timers, id); }
inline PhaseTimers::Id phase_id(PhaseTimers* timers, const std::string& name) {
  return timers != nullptr ? timers->phase(name) : 0;
}

// run.json's "profile": for every phase its seconds, calls, share of the run's wall time and
// milliseconds per step, then "other" = wall_seconds - all phases (what no scope covers: the
// time-step choice, bookkeeping); fluid particle-steps per second over the whole run.
nlohmann::json profile_json(const PhaseTimers& timers, double wall_seconds, long long steps,
                            std::size_t fluid_particles);

// The one-screen table of `mps_lab run --profile`, from profile_json().
std::string profile_table(const nlohmann::json& profile);

// CPU time this process has used so far, s: user + system of every thread (getrusage
// RUSAGE_SELF). For a one-thread run the difference over the run is its cost in CPU seconds,
// which other processes sharing the cores barely change (unlike the wall time).
double process_cpu_seconds();

// Resident memory of this process now (bytes; /proc/self/statm) and its peak (ru_maxrss).
std::size_t resident_memory_bytes();
std::size_t peak_resident_memory_bytes();

}  // namespace mps_lab
