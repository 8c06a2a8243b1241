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

TEST_CASE("The thread governor counts a single disturbed probe step out: each probe's slowest step is left out",
          "[unit][threads]") {
  mps_lab::ThreadGovernor governor({2, 0, 3, 100});
  int step = 0;
  // One thread: 1.0 s each. Two threads: 0.6 s, except one step that lost its core (5 s).
  auto cost = [&step](int team) { return team == 1 ? 1.0 : (++step == 2 ? 5.0 : 0.6); };
  run_steps(governor, 6, cost);
  CHECK(governor.chosen_team() == 2);
}

TEST_CASE("A probe of short steps lasts probe_seconds and sees how often the second core is taken", "[unit][threads]") {
  // Beside a busy process, with steps much shorter than a scheduler slice: two threads run a
  // step in 0.12 ms while the other process is off the second core and wait 2 ms for it every
  // fifth step (mean 0.496 ms); one thread takes 0.2 ms every step. Three steps would have seen
  // only the fast ones (0.12 < 0.2: two threads, the choice of 2026-11-28 that ran wcsph 1.4-1.7x
  // slower); a 20 ms probe sees the waits and keeps one thread.
  mps_lab::ThreadGovernor governor({2, 0, 3, 200, 0.1, /*probe_seconds=*/0.02});
  long long two_thread_steps = 0;
  const auto cost = [&two_thread_steps](int team) {
    if (team == 1) return 0.2e-3;
    return ++two_thread_steps % 5 == 0 ? 2.0e-3 : 0.12e-3;
  };
  const int one_thread_probe = 100;  // 0.02 s / 0.2 ms
  run_steps(governor, one_thread_probe, cost);
  CHECK(governor.chosen_team() == 2);  // the first probe (one thread) is not over: nothing chosen yet
  int steps = one_thread_probe;
  while (governor.summary().at("choices") == 0 && steps < 10000) {
    run_steps(governor, 1, cost);
    ++steps;
  }
  CHECK(governor.chosen_team() == 1);
  // The two-thread probe ran until its steps added up to 0.02 s: 40 steps make 19.84 ms, the
  // 42nd passes 20 ms (34 fast steps and 8 slow ones).
  CHECK(two_thread_steps == 42);
  // Its typical step is the mean without its slowest: 7 slow and 34 fast steps over 41,
  // 0.441 ms against one thread's 0.2 ms.
  const double typical = governor.summary().at("last_probe_seconds_per_step").at("2").get<double>();
  CHECK(typical == Approx((34 * 0.12e-3 + 7 * 2.0e-3) / 41.0));
}

TEST_CASE("The period doubles while the team holds and is short again after a change", "[unit][threads]") {
  // Steps of 1/2048 s with two threads, 1/1024 s with one (sums exact in binary). Periods of at
  // least 200 steps and 0.25 s, doubled to at most 1 s while the probes keep two threads.
  mps_lab::ThreadGovernor governor({2, 0, 3, 200, 0.1, /*probe_seconds=*/0.0, /*period_seconds=*/0.25,
                                    /*longest_period_seconds=*/1.0});
  const auto two_faster = [](int team) { return team == 2 ? 1.0 / 2048 : 1.0 / 1024; };
  const auto choices = [&governor] { return governor.summary().at("choices").get<long long>(); };
  run_steps(governor, 6, two_faster);  // the first probes: 3 + 3 steps
  REQUIRE(governor.chosen_team() == 2);
  for (const int period_steps : {512, 1024, 2048, 2048}) {  // 0.25, 0.5, 1 and again 1 s
    const long long before = choices();
    run_steps(governor, period_steps - 1, two_faster);
    CHECK(choices() == before);              // not yet
    run_steps(governor, 1 + 6, two_faster);  // the period's last step, then a probe that keeps two
    CHECK(choices() == before + 1);
    CHECK(governor.chosen_team() == 2);
  }
  // One thread becomes faster: the next probe changes team, and the period is 0.25 s again
  // (256 one-thread steps of 1/1024 s, and at least 200).
  const auto one_faster = [](int team) { return team == 2 ? 1.0 / 256 : 1.0 / 1024; };
  run_steps(governor, 2048, two_faster);  // the 1 s period
  run_steps(governor, 6, one_faster);     // and the probe that finds one thread faster
  REQUIRE(governor.chosen_team() == 1);
  const long long after_change = choices();
  run_steps(governor, 255, one_faster);
  CHECK(choices() == after_change);
  run_steps(governor, 1 + 6, one_faster);
  CHECK(choices() == after_change + 1);
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
