#pragma once
// How many OpenMP threads the next step uses, chosen by measurement (docs/performance.md,
// "Threads that never hurt").
//
// On a machine shared with other processes, or for a scene too small to share out, a step
// with every thread can be many times slower than with one: a thread that loses its core to
// another process stalls every barrier of the team. No static rule (a particle count, the
// load average) predicts it well, so the governor measures: it runs a few steps with each
// candidate team (one thread, every thread), keeps the fastest of each, runs `period_steps`
// steps with the faster team, and measures again; after the first choice it changes team only
// for a clearly faster one (`switch_margin`). The results do not depend on the team
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
  int probe_steps = 3;           // steps timed per candidate team; the fastest one counts
  long long period_steps = 200;  // steps run with the chosen team before measuring again
  // After the first choice, the other team must be faster by more than this fraction to be
  // taken: a 3-step probe is noisy, and without it isph at 1,176 particles once switched to the
  // slower team on a re-measurement and ran 1.38 times slower (docs/performance.md).
  double switch_margin = 0.1;
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
  void choose_after_probe();

  ThreadGovernorSettings settings_;
  std::array<int, 2> candidates_{};  // one thread, every thread
  std::array<double, 2> fastest_{};  // s, the fastest probe step of each candidate
  int probing_ = -1;                 // candidate being probed, -1 while running
  int probe_steps_done_ = 0;
  long long steps_since_choice_ = 0;
  int chosen_ = 1;
  int current_ = 1;
  long long choices_ = 0;
  std::map<int, long long> steps_by_team_;
};

}  // namespace mps_lab
