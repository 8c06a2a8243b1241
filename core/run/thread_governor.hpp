#pragma once
// How many OpenMP threads the next step uses, chosen by measurement (docs/performance.md,
// "Threads that never hurt").
//
// On a machine shared with other processes, or for a scene too small to share out, a step
// with every thread can be many times slower than with one: a thread that loses its core to
// another process stalls every barrier of the team. No static rule (a particle count, the
// load average) predicts it well, so the governor measures: it runs each candidate team (one
// thread, every thread) for a probe of at least `probe_steps` steps and `probe_seconds`, compares
// their mean step times with each probe's slowest step left out, runs the faster team for a
// period, and measures again; after the first choice it changes team only for a clearly faster
// one (`switch_margin`). A period is at least `period_steps` steps and `period_seconds`, doubled
// each time a probe keeps the team, up to `longest_period_seconds`, and short again after a
// change: a probe beside a busy process can misjudge (the first steps of a team that was idle
// can run while the other process is off the second core), so a new choice is checked soon,
// and a choice that holds is checked ever less often. A step's time is the whole of it as the
// run pays for it, its output included (core/run/driver.cpp): beside a busy process, two
// threads ran wcsph's steps no slower than one, but its output 4x slower (docs/performance.md,
// "Threads that never hurt"). The results do not depend on the team
// (core/base/parallel.hpp: every sum in a fixed order; the contract suite checks byte-identical
// frames for 1 and 2 threads), so the choice changes the speed only, never the bits.
//
// A fixed team (`mps_lab run --threads N`) turns the measurement off.
#include <array>
#include <map>

#include <nlohmann/json.hpp>

namespace mps_lab {

struct ThreadGovernorSettings {
  int max_threads = 1;           // the largest team (OMP_NUM_THREADS or the cores)
  int fixed_threads = 0;         // > 0: always this team, nothing measured
  int probe_steps = 3;           // at least this many steps timed per candidate team
  long long period_steps = 200;  // at least this many steps run with the chosen team before measuring again
  // After the first choice, the other team must be faster by more than this fraction to be
  // taken: a 3-step probe is noisy, and without it isph at 1,176 particles once switched to the
  // slower team on a re-measurement and ran 1.38 times slower (docs/performance.md).
  double switch_margin = 0.1;
  double probe_seconds = 0.02;          // s: a probe also lasts at least this long (several scheduler slices)
  double period_seconds = 0.1;          // s: the first period after a change of team lasts at least this long
  double longest_period_seconds = 1.0;  // s: the longest period, reached by doubling while the team holds
};

class ThreadGovernor {
 public:
  explicit ThreadGovernor(const ThreadGovernorSettings& settings);
  // Gives the process its largest team back (the choice is the process's OpenMP setting).
  ~ThreadGovernor();
  ThreadGovernor(const ThreadGovernor&) = delete;
  ThreadGovernor& operator=(const ThreadGovernor&) = delete;

  // The team for the next step; also sets it (omp_set_num_threads).
  int next_team();
  // The wall time of the step just run with next_team()'s team, s.
  void record(double step_seconds);

  int chosen_team() const { return chosen_; }
  // For run.json: the policy, the candidates' last timings and the steps run with each team.
  nlohmann::json summary() const;

 private:
  void start_probe();
  void choose_after_probe();

  // A candidate's probe: its steps, their total and slowest time (s).
  struct Probe {
    long long steps = 0;
    double seconds = 0.0;
    double slowest = 0.0;
    // The mean step time without the slowest step (one disturbed step does not decide); all
    // of them for a probe of fewer than 3 steps. s.
    double typical() const;
  };

  ThreadGovernorSettings settings_;
  std::array<int, 2> candidates_{};  // one thread, every thread
  std::array<Probe, 2> probes_{};    // the last probe of each candidate
  int probing_ = -1;                 // candidate being probed, -1 while running
  long long steps_since_choice_ = 0;
  double seconds_since_choice_ = 0.0;
  double period_ = 0.0;  // s, the current period's least length
  int chosen_ = 1;
  int current_ = 1;
  long long choices_ = 0;
  std::map<int, long long> steps_by_team_;
};

}  // namespace mps_lab
