#include "app/commands.hpp"
#include "lab/data_directory.hpp"

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>

#include <signal.h>
#include <unistd.h>

#include <omp.h>

#include "core/base/error.hpp"
#include "core/io/output.hpp"
#include "core/run/driver.hpp"
#include "core/run/method.hpp"
#include "core/walls/wall_treatment.hpp"
#include "lab/benchmark.hpp"
#include "lab/compare.hpp"

namespace mps_lab::app {

namespace {

// The one piece of global mutable state of the program: a signal handler may only talk to
// the rest of it through a `volatile std::sig_atomic_t` of static storage duration (C++17
// [support.signal]). It holds the first SIGINT or SIGTERM received, 0 before; the run polls
// it between steps through RunOptions::stop_reason, so core/ has no global state.
volatile std::sig_atomic_t received_stop_signal = 0;

extern "C" void on_stop_signal(int signal_number) { received_stop_signal = signal_number; }

// SIGINT and SIGTERM ask the run to stop cleanly after the current step. SA_RESETHAND
// restores the default action after the first one: a second signal ends the process at
// once (every file is written atomically, so the folder still holds only complete files).
void install_stop_handlers() {
  struct sigaction action {};
  action.sa_handler = on_stop_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

std::string stop_reason() {
  const int signal_number = received_stop_signal;
  if (signal_number == 0) return "";
  if (signal_number == SIGINT) return "SIGINT";
  if (signal_number == SIGTERM) return "SIGTERM";
  return "signal " + std::to_string(signal_number);
}

// The teams that ran the steps, from run.json's threads_used: "1 thread" or "2 threads" when one
// team ran them all, else each team with its steps, "1 thread 84 steps, 2 threads 379 steps".
std::string teams_used(const nlohmann::json& threads_used) {
  const auto& steps_by_team = threads_used.at("steps_by_team");
  std::string text;
  for (const auto& [team, steps] : steps_by_team.items()) {
    if (!text.empty()) text += ", ";
    text += team + (team == "1" ? " thread" : " threads");
    if (steps_by_team.size() > 1) text += " " + std::to_string(steps.get<long long>()) + " steps";
  }
  return text.empty() ? "no steps" : text;
}

// The exit code of a finished run (or resumed run), with its one line on stderr or stdout.
int report_run(const RunResult& result, bool quiet, bool profile) {
  if (profile && result.summary.contains("profile")) {
    std::fputs(profile_table(result.summary["profile"]).c_str(), stdout);
  }
  if (result.status == "interrupted") {
    std::fprintf(stderr, "mps_lab: run %s; state in %s/checkpoint.bin\n", result.message.c_str(),
                 result.directory.c_str());
    return 128 + static_cast<int>(received_stop_signal);
  }
  if (result.status != "completed") {
    std::fprintf(stderr, "mps_lab: run %s at t = %.6g s after %lld steps: %s (see %s/run.json)\n",
                 result.status.c_str(), result.simulated_time, result.steps, result.message.c_str(),
                 result.directory.c_str());
    return 1;
  }
  if (!quiet) {
    const auto& summary = result.summary;
    std::printf("%s: %lld steps to t = %.4g s in %.2f s wall (%s), mean solver iterations %.1f -> %s/\n",
                summary["method"].get<std::string>().c_str(), result.steps, result.simulated_time, result.wall_seconds,
                teams_used(summary["threads_used"]).c_str(), summary["solver"]["mean_iterations"].get<double>(),
                result.directory.c_str());
  }
  return 0;
}

// A run or a resumed run: the registries, the stop handlers, the run, its report.
int run_with_options(RunOptions options, bool quiet, bool profile) {
  const MethodRegistry methods = builtin_methods();
  const WallTreatmentRegistry walls = builtin_wall_treatments();
  options.progress = !quiet;
  options.stop_reason = stop_reason;
  install_stop_handlers();
  return report_run(run_simulation(options, methods, walls), quiet, profile);
}

}  // namespace

int run_command(const RunCommand& command) {
  RunOptions options;
  options.scene_path = command.scene;
  options.method = command.method;
  options.output_directory = command.out;
  options.overrides = command.set;
  options.end_time = command.end_time;
  options.checkpoint_every_steps = command.checkpoint_every;
  options.threads = command.threads;
  options.load_setting = command.load_setting;
  return run_with_options(options, command.quiet, command.profile);
}

int bench_command(const BenchCommand& command, char** argv) {
  // Unpinned OpenMP threads on this machine class slow down many-fold when another process
  // runs (docs/performance.md). OMP_PROC_BIND is read when the OpenMP runtime starts, so the
  // bench sets it and starts itself again (once: the variable is then set).
  if (std::getenv("OMP_PROC_BIND") == nullptr) {
    ::setenv("OMP_PROC_BIND", "true", 1);
    ::execv("/proc/self/exe", argv);
    std::fprintf(stderr, "mps_lab: note: could not restart with OMP_PROC_BIND=true; threads are not pinned\n");
  }
  const MethodRegistry methods = builtin_methods();
  const WallTreatmentRegistry walls = builtin_wall_treatments();
  BenchmarkOptions options;
  options.scene_path = command.scene;
  options.methods = command.methods;
  options.spacings = command.spacings;
  options.threads = command.threads;
  options.overrides = command.set;
  options.per_spacing = command.per_spacing;
  options.time_step_per_spacing = command.time_step_per_spacing;
  options.start_time = command.start_time;
  options.warmup_steps = command.warmup_steps;
  options.steps = command.steps;
  options.kernels = command.kernels;
  options.progress = !command.quiet;
  const nlohmann::json results = run_benchmarks(options, methods, walls);
  if (!command.json.empty()) write_file_atomically(command.json, results.dump(1) + "\n");
  std::printf("OMP_PROC_BIND=%s, %d threads available\n", std::getenv("OMP_PROC_BIND"), omp_get_num_procs());
  std::fputs(benchmark_table(results).c_str(), stdout);
  return 0;
}

int resume_command(const ResumeCommand& command) {
  RunOptions options;
  options.resume_directory = command.directory;
  options.end_time = command.end_time;
  options.checkpoint_every_steps = command.checkpoint_every;
  options.threads = command.threads;
  return run_with_options(options, command.quiet, command.profile);
}

namespace {

// The analysis scripts need numpy and matplotlib; MPS_LAB_PYTHON is the interpreter CMake
// found (Debian's /usr/bin/python3 by default). Returns "" when it cannot run them.
std::string analysis_python() {
  const std::string python = MPS_LAB_PYTHON;
  if (python.empty()) return "";
  const std::string probe = "'" + python + "' -c 'import numpy, matplotlib' > /dev/null 2>&1";
  return std::system(probe.c_str()) == 0 ? python : "";
}

}  // namespace

int compare_command(const CompareCommand& command) {
  const MethodRegistry methods = builtin_methods();
  const WallTreatmentRegistry walls = builtin_wall_treatments();
  CompareOptions options;
  options.scene_path = command.scene;
  options.methods = command.methods;
  std::string out = command.out;
  if (out.empty()) out = "runs/" + std::filesystem::path(command.scene).stem().string();
  options.output_directory = out;
  options.overrides = command.set;
  options.end_time = command.end_time;
  options.load_setting = command.load_setting;
  options.progress = !command.quiet;
  options.stop_reason = stop_reason;
  install_stop_handlers();
  const auto rows = compare_methods(options, methods, walls);
  if (!rows.empty() && rows.back().status == "interrupted") {
    std::fprintf(stderr, "mps_lab: compare stopped by %s after %s (%s); the methods after it were not run\n",
                 stop_reason().c_str(), rows.back().method.c_str(), (out + "/" + rows.back().method).c_str());
    return 128 + static_cast<int>(received_stop_signal);
  }

  bool all_completed = true;
  if (!command.quiet) {
    std::printf("%-8s %-10s %7s %9s %8s %10s %10s %12s %10s\n", "method", "status", "steps", "wall [s]", "iter",
                "front RMS", "shift", "RMS shifted", "height RMS");
  }
  for (const auto& row : rows) {
    all_completed = all_completed && row.status == "completed";
    if (!command.quiet) {
      std::printf("%-8s %-10s %7lld %9.2f %8.1f %10.3f %+10.3f %12.3f %10.3f\n", row.method.c_str(), row.status.c_str(),
                  row.steps, row.wall_seconds, row.mean_solver_iterations, row.front_rms, row.front_shift,
                  row.front_rms_shifted, row.height_rms);
    }
  }
  if (command.analysis) {
    const std::string python = analysis_python();
    if (python.empty()) {
      std::fprintf(stderr,
                   "mps_lab: figures and report skipped: %s cannot import numpy and matplotlib "
                   "(apt-get install python3-numpy python3-matplotlib)\n",
                   MPS_LAB_PYTHON);
    } else {
      const std::string script = data_directory() + "/analysis/compare.py";
      const std::string call = "'" + python + "' '" + script + "' '" + out + "'" + (command.quiet ? " --quiet" : "");
      if (std::system(call.c_str()) != 0) {
        std::fprintf(stderr, "mps_lab: the analysis script failed: %s\n", call.c_str());
        return 1;
      }
      if (!command.quiet) std::printf("report: %s/report.md\n", out.c_str());
    }
  } else if (!command.quiet) {
    std::printf("summary: %s/summary.csv\n", out.c_str());
  }
  return all_completed ? 0 : 1;
}

namespace {

// What the method declares (MethodInfo): the basis of which wall treatments it may use.
void print_capabilities(const MethodInfo& info) {
  std::string models;
  for (const auto model : info.wall_particle_models) {
    models += (models.empty() ? "" : ", ") + std::string(wall_particle_pressure_name(model));
  }
  std::printf("    capabilities: wall hooks %s; wall samples %s; wall-particle models %s\n",
              info.wall_hooks.names().c_str(), info.wall_samples ? "yes" : "no",
              models.empty() ? "none" : models.c_str());
}

// Its setting for wall loads (MethodInfo::load_setting): what --load-setting applies, and its promise.
void print_load_setting(const MethodInfo& info) {
  std::string assignments;
  for (const auto& assignment : load_setting_overrides(info)) assignments += " --set " + assignment;
  for (const auto& assignment : load_setting_defaults(info)) assignments += " --set " + assignment;
  if (assignments.empty()) assignments = " (the defaults)";
  std::printf("    load setting (--load-setting):%s; promise: still water within %g %% of rho g h (%s)\n",
              assignments.c_str(), 100.0 * info.load_setting.still_water_tolerance, info.load_setting.basis.c_str());
}

// Where a treatment acts for this method, and the optional hooks the method does not call
// (so that a treatment never loses a hook silently).
std::string hooks_note(const WallTreatmentInfo& wall, const MethodInfo& method) {
  if (wall.hooks.empty()) return "";
  const WallHooks skipped = wall.hooks.without(method.wall_hooks);
  std::string note = ", acts " + wall.hooks.without(skipped).names();
  if (!skipped.empty()) note += "; not " + skipped.names() + ", which " + method.name + " does not call";
  return note;
}

}  // namespace

int methods_command(bool with_parameters) {
  const MethodRegistry methods = builtin_methods();
  const WallTreatmentRegistry walls = builtin_wall_treatments();
  std::size_t width = 0;
  for (const auto* info : methods.all()) width = std::max(width, info->name.size());
  for (const auto* info : methods.all()) {
    std::printf("%-*s  %s\n", static_cast<int>(width), info->name.c_str(), info->description.c_str());
    if (!with_parameters) continue;
    print_capabilities(*info);
    print_load_setting(*info);
    for (const auto& spec : info->parameters) {
      std::printf("    methods.%s.%s = %s %s  (%s) %s\n", info->name.c_str(), spec.name.c_str(),
                  spec.default_value.dump().c_str(), spec.unit.c_str(), spec.range_text().c_str(),
                  spec.description.c_str());
    }
    for (const auto* wall : walls.all()) {
      if (!wall_treatment_supports(*wall, *info)) continue;
      bool default_on = false;
      for (const auto& name : info->default_wall_treatments) default_on = default_on || name == wall->name;
      std::printf("    wall treatment %s (%s, %s%s): %s\n", wall->name.c_str(),
                  wall->role == WallTreatmentRole::Boundary ? "boundary model" : "measure",
                  default_on ? "on by default" : "off by default", hooks_note(*wall, *info).c_str(),
                  wall->description.c_str());
      for (const auto& spec : wall->parameters) {
        std::printf("        .%s = %s %s  (%s) %s\n", spec.name.c_str(), spec.default_value.dump().c_str(),
                    spec.unit.c_str(), spec.range_text().c_str(), spec.description.c_str());
      }
    }
  }
  return 0;
}

}  // namespace mps_lab::app
