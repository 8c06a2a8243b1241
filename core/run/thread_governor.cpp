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
  if (settings_.fixed_threads == 0 && settings_.max_threads > 1) probing_ = 0;
  fastest_.fill(std::numeric_limits<double>::infinity());
}

ThreadGovernor::~ThreadGovernor() { omp_set_num_threads(settings_.max_threads); }

int ThreadGovernor::next_team() {
  current_ = probing_ >= 0 ? candidates_[static_cast<std::size_t>(probing_)] : chosen_;
  omp_set_num_threads(current_);
  return current_;
}

void ThreadGovernor::record(double step_seconds) {
  ++steps_by_team_[current_];
  if (probing_ < 0) {
    if (settings_.fixed_threads == 0 && settings_.max_threads > 1 && ++steps_since_choice_ >= settings_.period_steps) {
      probing_ = 0;
      probe_steps_done_ = 0;
      fastest_.fill(std::numeric_limits<double>::infinity());
    }
    return;
  }
  auto& fastest = fastest_[static_cast<std::size_t>(probing_)];
  fastest = std::min(fastest, step_seconds);
  if (++probe_steps_done_ < settings_.probe_steps) return;
  probe_steps_done_ = 0;
  if (++probing_ < static_cast<int>(candidates_.size())) return;
  choose_after_probe();
}

// The faster candidate by its fastest step (the least disturbed one); a tie keeps one thread,
// which leaves a core to the rest of the machine. After the first choice, the other candidate
// replaces the current one only when faster by more than settings_.switch_margin.
void ThreadGovernor::choose_after_probe() {
  if (choices_ == 0) {
    chosen_ = fastest_[1] < fastest_[0] ? candidates_[1] : candidates_[0];
  } else {
    const std::size_t current = chosen_ == candidates_[1] ? 1 : 0;
    const std::size_t other = 1 - current;
    if (fastest_[other] < (1.0 - settings_.switch_margin) * fastest_[current]) chosen_ = candidates_[other];
  }
  probing_ = -1;
  steps_since_choice_ = 0;
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
    summary["switch_margin"] = settings_.switch_margin;
    summary["last_choice"] = chosen_;
  }
  return summary;
}

}  // namespace mps_lab
