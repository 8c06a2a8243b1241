// The thread governor (core/run/thread_governor.hpp): it measures each candidate team, keeps the
// faster, measures again after its period, and a fixed team or a single thread measures nothing.
#include <omp.h>
#include <catch2/catch.hpp>

#include "core/run/thread_governor.hpp"

namespace {

// Runs `steps` steps whose time is `seconds_with(team)`; returns the team of the last step.
template <typename Cost>
int run_steps(mps_lab::ThreadGovernor& governor, int steps, Cost seconds_with) {
  int team = 0;
  for (int k = 0; k < steps; ++k) {
    team = governor.next_team();
    governor.record(seconds_with(team));
  }
  return team;
}

}  // namespace

TEST_CASE("The thread governor keeps the faster team and measures again after its period", "[unit][threads]") {
  const int before = omp_get_max_threads();
  {
    mps_lab::ThreadGovernor governor({/*max_threads=*/2, /*fixed_threads=*/0, /*probe_steps=*/3, /*period_steps=*/10});
    // Two threads twice as fast (an idle machine, a large scene): probed 3 + 3 steps, then 2.
    auto idle = [](int team) { return team == 2 ? 0.5 : 1.0; };
    CHECK(run_steps(governor, 6, idle) == 2);  // the sixth step is the last probe of 2 threads
    CHECK(governor.chosen_team() == 2);
    CHECK(omp_get_max_threads() == 2);
    // The machine gets busy: two threads now 4x slower. After the period (10 steps) it measures
    // again (6 steps) and falls back to one thread.
    auto busy = [](int team) { return team == 2 ? 4.0 : 1.0; };
    run_steps(governor, 10 + 6, busy);
    CHECK(governor.chosen_team() == 1);
    CHECK(governor.next_team() == 1);
    CHECK(omp_get_max_threads() == 1);
    const auto summary = governor.summary();
    CHECK(summary.at("policy") == "measured");
    CHECK(summary.at("choices") == 2);
    CHECK(summary.at("steps_by_team").at("1").get<long long>() + summary.at("steps_by_team").at("2").get<long long>() ==
          22);
  }
  CHECK(omp_get_max_threads() == 2);  // the destructor gives the process its largest team back
  omp_set_num_threads(before);
}

TEST_CASE("The thread governor counts a single disturbed probe step out by taking each team's fastest",
          "[unit][threads]") {
  mps_lab::ThreadGovernor governor({2, 0, 3, 100});
  int step = 0;
  // One thread: 1.0 s each. Two threads: 0.6 s, except one step that lost its core (5 s).
  auto cost = [&step](int team) { return team == 1 ? 1.0 : (++step == 2 ? 5.0 : 0.6); };
  run_steps(governor, 6, cost);
  CHECK(governor.chosen_team() == 2);
}

TEST_CASE("After its first choice the thread governor changes team only for a clearly faster one", "[unit][threads]") {
  // switch_margin 0.1: one thread chosen first (1.0 s against 1.2 s), then two threads look 5 %
  // faster on a re-measurement (a noisy probe): it keeps one thread; 20 % faster: it switches.
  mps_lab::ThreadGovernor governor({2, 0, 3, 10, 0.1});
  run_steps(governor, 6, [](int team) { return team == 2 ? 1.2 : 1.0; });
  CHECK(governor.chosen_team() == 1);
  run_steps(governor, 10 + 6, [](int team) { return team == 2 ? 0.95 : 1.0; });
  CHECK(governor.chosen_team() == 1);
  CHECK(governor.summary().at("choices") == 2);
  run_steps(governor, 10 + 6, [](int team) { return team == 2 ? 0.8 : 1.0; });
  CHECK(governor.chosen_team() == 2);
}

TEST_CASE("A fixed team and a single thread measure nothing", "[unit][threads]") {
  const int before = omp_get_max_threads();
  {
    mps_lab::ThreadGovernor fixed({2, 1, 3, 10});
    CHECK(run_steps(fixed, 30, [](int team) { return team == 2 ? 0.1 : 1.0; }) == 1);  // never tries 2
    CHECK(fixed.summary().at("policy") == "fixed");
    CHECK(fixed.summary().at("steps_by_team").at("1") == 30);
  }
  {
    mps_lab::ThreadGovernor single({1, 0, 3, 10});
    CHECK(run_steps(single, 5, [](int) { return 1.0; }) == 1);
    CHECK(single.summary().at("steps_by_team").size() == 1);
  }
  omp_set_num_threads(before);
}
