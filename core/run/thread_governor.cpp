#include "core/run/thread_governor.hpp"

#include <cstdlib>

#include <omp.h>

#include <algorithm>
#include <limits>
#include <string>

namespace mps_lab {

ThreadGovernor::ThreadGovernor(const ThreadGovernorSettings& settings) : settings_(settings) {
  settings_.max_threads = std::max(1, settings_.max_threads);
  candidates_ = {1, settings_.max_threads};
  chosen_ = settings_.fixed_threads > 0 ? settings_.fixed_threads : settings_.max_threads;
  // Nothing to choose from with one thread or a fixed team; otherwise measure from the start.
  if (settings_.fixed_threads == 0 && settings_.max_threads > 1) start_probe();
}

ThreadGovernor::~ThreadGovernor() { omp_set_num_threads(settings_.max_threads); }

int ThreadGovernor::next_team() {
  current_ = probing_ >= 0 ? candidates_[static_cast<std::size_t>(probing_)] : chosen_;
  omp_set_num_threads(current_);
  return current_;
}

double ThreadGovernor::Probe::typical() const {
  if (steps < 3) return steps > 0 ? seconds / static_cast<double>(steps) : std::numeric_limits<double>::infinity();
  return (seconds - slowest) / static_cast<double>(steps - 1);
}

void ThreadGovernor::start_probe() {
  probing_ = 0;
  probes_.fill(Probe{});
}

void ThreadGovernor::record(double step_seconds) {
  ++steps_by_team_[current_];
  if (probing_ < 0) {
    seconds_since_choice_ += step_seconds;
    ++steps_since_choice_;
    if (settings_.fixed_threads == 0 && settings_.max_threads > 1 && steps_since_choice_ >= settings_.period_steps &&
        seconds_since_choice_ >= period_) {
      start_probe();
    }
    return;
  }
  Probe& probe = probes_[static_cast<std::size_t>(probing_)];
  ++probe.steps;
  probe.seconds += step_seconds;
  probe.slowest = std::max(probe.slowest, step_seconds);
  if (probe.steps < settings_.probe_steps || probe.seconds < settings_.probe_seconds) return;
  if (++probing_ < static_cast<int>(candidates_.size())) return;
  choose_after_probe();
}

// The faster candidate by its probe's typical step (Probe::typical); a tie keeps one thread,
// which leaves a core to the rest of the machine. After the first choice, the other candidate
// replaces the current one only when faster by more than settings_.switch_margin.
void ThreadGovernor::choose_after_probe() {
  const double one = probes_[0].typical(), every = probes_[1].typical();
  const int before = chosen_;
  if (choices_ == 0) {
    chosen_ = every < one ? candidates_[1] : candidates_[0];
  } else {
    const std::size_t current = chosen_ == candidates_[1] ? 1 : 0;
    const double current_time = current == 1 ? every : one, other_time = current == 1 ? one : every;
    if (other_time < (1.0 - settings_.switch_margin) * current_time) chosen_ = candidates_[1 - current];
  }
  // A new team is checked again after the shortest period; one that held, after twice the last.
  const bool held = choices_ > 0 && chosen_ == before;
  period_ = held ? std::min(2.0 * period_, settings_.longest_period_seconds) : settings_.period_seconds;
  probing_ = -1;
  steps_since_choice_ = 0;
  seconds_since_choice_ = 0.0;
  ++choices_;
}

nlohmann::json ThreadGovernor::summary() const {
  nlohmann::json steps = nlohmann::json::object();
  for (const auto& [team, count] : steps_by_team_) steps[std::to_string(team)] = count;
  nlohmann::json summary = {{"policy", settings_.fixed_threads > 0 ? "fixed" : "measured"},
                            {"max_threads", settings_.max_threads},
                            {"steps_by_team", steps}};
  // How waiting threads wait: the OpenMP runtime's settings as the run found them (a bounded
  // spin was measured and not made the default: docs/performance.md, "Threads that never hurt").
  const char* spin = std::getenv("GOMP_SPINCOUNT");
  const char* policy = std::getenv("OMP_WAIT_POLICY");
  summary["gomp_spincount"] = spin != nullptr ? spin : "libgomp default";
  summary["omp_wait_policy"] = policy != nullptr ? policy : "unset";
  if (settings_.fixed_threads == 0 && settings_.max_threads > 1) {
    summary["choices"] = choices_;
    summary["period_steps"] = settings_.period_steps;
    summary["probe_steps"] = settings_.probe_steps;
    summary["probe_seconds"] = settings_.probe_seconds;
    summary["period_seconds"] = settings_.period_seconds;
    summary["longest_period_seconds"] = settings_.longest_period_seconds;
    // The last probe's typical step of each team (mean without its slowest step), s.
    summary["last_probe_seconds_per_step"] = {{std::to_string(candidates_[0]), probes_[0].typical()},
                                              {std::to_string(candidates_[1]), probes_[1].typical()}};
    summary["switch_margin"] = settings_.switch_margin;
    summary["last_choice"] = chosen_;
  }
  return summary;
}

}  // namespace mps_lab
