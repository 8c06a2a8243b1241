// Per-phase timers (core/run/profile.hpp), the run's profile in run.json and on screen
// (--profile), and the benchmark harness behind `mps_lab bench` (lab/benchmark.hpp).
#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <thread>

#include "core/run/driver.hpp"
#include "core/run/profile.hpp"
#include "lab/benchmark.hpp"
#include "support.hpp"

namespace mps_lab::testing {

TEST_CASE("phase timers: ids by name - accumulation - reset and the profile's other share", "[profile]") {
  PhaseTimers timers;
  const auto search = timers.phase("neighbour_search");
  const auto solve = timers.phase("pressure_solve");
  CHECK(timers.phase("neighbour_search") == search);
  CHECK(solve != search);
  timers.add(search, 0.25);
  timers.add(search, 0.5);
  timers.add(solve, 1.0);
  {
    const auto timed = timers.measure(solve);
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  CHECK(timers.phases()[search].seconds == 0.75);
  CHECK(timers.phases()[search].calls == 2);
  CHECK(timers.phases()[solve].calls == 2);
  CHECK(timers.phases()[solve].seconds >= 1.002);

  const double wall = 4.0;
  const auto profile = profile_json(timers, wall, 10, 1000);
  double shares = 0.0;
  for (const auto& item : profile["phases"].items()) shares += item.value()["share"].get<double>();
  CHECK(shares == Approx(1.0).epsilon(1e-12));  // the phases and "other" cover the wall time
  CHECK(profile["phases"]["neighbour_search"]["milliseconds_per_step"].get<double>() == Approx(75.0));
  CHECK(profile["fluid_particle_steps_per_second"].get<double>() == Approx(2500.0));
  CHECK_THAT(profile_table(profile), Catch::Contains("pressure_solve") && Catch::Contains("other"));

  timers.reset();
  CHECK(timers.phases().size() == 2);
  CHECK(timers.total_seconds() == 0.0);
  // A null PhaseTimers (a method outside a run) times nothing and does not crash.
  { const auto timed = measure(nullptr, 0); }
  CHECK(phase_id(nullptr, "anything") == 0);
}

// Each method times its steps: the named phases appear with one call per step where the
// method does the phase once per step, and together with the monitor's "diagnostics" they
// cover most of the stepping time. What no phase covers is per-step bookkeeping (the time-step
// choice, series statistics): measured 0.4-0.5 % of the step at l0 = 0.025 for every method
// (mps_lab bench, docs/data/performance.md: "other" 0.9-2.1 us of 208-577 us per step); 25 %
// leaves room for a busy machine, where a scope's clock reads cost relatively more.
TEST_CASE("every method times its phases - and they cover the stepping time", "[profile]") {
  for (const auto* info : registries().methods.all()) {
    DYNAMIC_SECTION(info->name) {
      const Scene scene = load("dambreak.json");
      long long systems = 0;  // linear pressure systems the method solved (MethodSetup::pressure_system_observer)
      Simulation simulation(
          scene, *info,
          [&systems](const CsrMatrix&, const std::vector<double>&, const ProjectionSolverSettings&) { ++systems; });
      CHECK(simulation.timers().calls("setup") == 1);
      simulation.timers().reset();
      const long long steps = 40;
      const auto start = PhaseTimers::Clock::now();
      for (long long step = 0; step < steps; ++step) simulation.advance();
      const double seconds = std::chrono::duration<double>(PhaseTimers::Clock::now() - start).count();
      const auto& timers = simulation.timers();
      const auto calls = [&](const std::string& name) { return timers.calls(name); };
      CHECK(calls("neighbour_search") >= steps);
      CHECK(calls("operators") >= steps);
      CHECK(calls("integration") >= steps);
      CHECK(calls("wall_treatment") >= steps);
      CHECK(calls("diagnostics") == steps);
      // A method that solves a linear pressure system assembles and solves it once per step; an
      // iterative solve (dfsph's density solve) is one phase per step; an explicit method has neither.
      if (systems > 0) {
        CHECK(systems == steps);
        CHECK(calls("matrix_assembly") == steps);
        CHECK(calls("pressure_solve") == steps);
      }
      if (calls("density_solve") > 0) CHECK(calls("density_solve") == steps);
      CHECK(timers.total_seconds() <= seconds);
      CHECK(timers.total_seconds() >= 0.75 * seconds);
    }
  }
}

TEST_CASE("run.json has the profile and the memory of every run", "[profile]") {
  const auto out = fresh_directory("profile_run");
  RunOptions options;
  options.scene_path = scene_path("dambreak.json");
  options.method = "mps";
  options.output_directory = out.string();
  options.end_time = 0.01;  // 20 steps
  const RunResult result = run_simulation(options, registries().methods, registries().walls);
  REQUIRE(result.status == "completed");
  const auto run = nlohmann::json::parse(read_text(out / "run.json"));
  const auto& profile = run.at("profile");
  CHECK(profile.at("steps").get<long long>() == 20);
  CHECK(profile.at("fluid_particles").get<std::size_t>() == 171);
  for (const char* phase :
       {"setup", "neighbour_search", "operators", "pressure_solve", "output", "diagnostics", "other"}) {
    CHECK(profile.at("phases").contains(phase));
  }
  CHECK(profile.at("phases").at("setup").at("calls").get<long long>() == 1);
  // Frames at steps 0, 10, 20 (output.frame_every_steps = 100 and the 0.05 s interval do not
  // fire before 0.01 s: steps 0 and 20 only).
  CHECK(profile.at("phases").at("output").at("calls").get<long long>() >= 2);
  double total = 0.0;
  for (const auto& item : profile.at("phases").items()) total += item.value().at("seconds").get<double>();
  CHECK(total == Approx(profile.at("wall_seconds").get<double>()).epsilon(1e-9));
  // CPU seconds of the session: > 0, and at most threads x wall seconds (a thread cannot use
  // more CPU time than passes; + 0.02 s for the kernel's accounting granularity).
  const double cpu = profile.at("cpu_seconds").get<double>();
  CHECK(cpu > 0.0);
  CHECK(cpu <= profile.at("threads").get<double>() * profile.at("wall_seconds").get<double>() + 0.02);
  CHECK(run.at("memory").at("peak_resident_bytes").get<std::size_t>() > 1000000);  // at least the program
  CHECK(run.at("memory").at("bytes_per_particle").get<double>() > 0.0);
}

namespace {
bool picks_own_time_step(const MethodInfo& info) {
  for (const auto& spec : info.parameters) {
    if (spec.name == "time_step_rule") return spec.default_value == "cfl";
  }
  return false;
}
}  // namespace

TEST_CASE("the benchmark harness measures kernels and whole steps of each method", "[profile]") {
  BenchmarkOptions options;
  options.scene_path = scene_path("dambreak.json");
  options.spacings = {0.05};
  options.warmup_steps = 1;
  options.steps = 3;
  const auto results = run_benchmarks(options, registries().methods, registries().walls);
  const auto& cases = results.at("cases");
  REQUIRE(cases.size() == 1 + registries().methods.all().size());
  CHECK(cases[0].at("kind") == "kernels");
  CHECK(cases[0].at("particle_spacing").get<double>() == 0.05);
  CHECK(cases[0].at("neighbour_search_ns_per_particle").get<double>() > 0.0);
  for (std::size_t c = 1; c < cases.size(); ++c) {
    const auto& one = cases[c];
    INFO(one.dump());
    REQUIRE(one.at("status") == "completed");
    // The scene's time step follows the spacing, 0.02 s/m x 0.05 m, unless the method picks its
    // own: a time_step_rule whose default is "cfl" (dfsph, eisph; core/run/time_step.hpp).
    if (!picks_own_time_step(*registries().methods.find(one.at("method").get<std::string>())))
      CHECK(one.at("time_step").get<double>() == Approx(1e-3).epsilon(1e-12));
    const double fluid = one.at("fluid_particles").get<double>();
    CHECK(one.at("fluid_particle_steps_per_second").get<double>() ==
          Approx(fluid * 3.0 / one.at("seconds").get<double>()).epsilon(1e-12));
    // A method that iterates a solver reports the time of one iteration; an explicit one none.
    if (one.at("mean_solver_iterations").get<double>() > 0.0) {
      CHECK(one.at("solver_iteration_microseconds").get<double>() > 0.0);
    }
  }
  CHECK_THAT(benchmark_table(results), Catch::Contains("p-steps/s") && Catch::Contains("search ns/part"));
}

TEST_CASE("mps_lab run --profile prints the table - mps_lab bench prints and writes its measurements", "[cli]") {
  const auto dir = fresh_directory("profile_cli");
  const auto run = run_mps_lab(
      "run " + scene_path("dambreak.json") + " --end-time 0.005 -q --profile --out " + (dir / "run").string(),
      "profile_run");
  CHECK(run.exit_code == 0);
  CHECK_THAT(run.stdout_text, Catch::StartsWith("profile: 10 steps, 171 fluid particles") &&
                                  Catch::Contains("pressure_solve") && Catch::Contains("neighbour_search"));
  const auto json = dir / "bench.json";
  const auto bench =
      run_mps_lab("bench " + scene_path("dambreak.json") +
                      " --methods mps --spacings 0.05 --steps 2 --warmup-steps 0 -q --json " + json.string(),
                  "profile_bench");
  CHECK(bench.exit_code == 0);
  CHECK_THAT(bench.stdout_text, Catch::StartsWith("OMP_PROC_BIND=true") && Catch::Contains("mps "));
  const auto results = nlohmann::json::parse(read_text(json));
  CHECK(results.at("cases").size() == 2);
  const auto bad = run_mps_lab("bench " + scene_path("dambreak.json") + " --methods nope -q", "profile_bench_bad");
  CHECK(bad.exit_code == 2);
  CHECK_THAT(bad.stderr_text, Catch::Contains("--methods") && Catch::Contains("nope"));
}

}  // namespace mps_lab::testing
