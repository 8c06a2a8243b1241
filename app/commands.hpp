#pragma once
// Sub-commands of the mps_lab front end. Each returns the process exit code:
// 0 success, 1 the run failed (diverged, solver failure), 2 bad input, 3 output error,
// 128 + the signal number (130 SIGINT, 143 SIGTERM) when stopped by a signal.
#include <optional>
#include <string>
#include <vector>

namespace mps_lab::app {

struct RunCommand {
  std::string scene;
  std::string method;
  std::string out;
  std::vector<std::string> set;
  std::optional<double> end_time;
  std::optional<long long> checkpoint_every;
  int threads = 0;            // 0: chosen by measurement (core/run/thread_governor.hpp)
  bool load_setting = false;  // the method's setting for wall loads (MethodInfo::load_setting)
  bool quiet = false;
  bool profile = false;  // print the per-phase profile (run.json "profile") at the end
};

struct ResumeCommand {
  std::string directory;
  std::optional<double> end_time;
  std::optional<long long> checkpoint_every;
  int threads = 0;  // 0: chosen by measurement (core/run/thread_governor.hpp)
  bool quiet = false;
  bool profile = false;  // print the per-phase profile (run.json "profile") at the end
};

struct CompareCommand {
  std::string scene;
  std::vector<std::string> methods;
  std::string out;
  std::vector<std::string> set;
  std::optional<double> end_time;
  bool load_setting = false;  // each method's setting for wall loads (MethodInfo::load_setting)
  bool analysis = true;
  bool quiet = false;
};

struct BenchCommand {
  std::string scene = "scenes/dambreak.json";
  std::vector<std::string> methods;
  std::vector<double> spacings;  // m
  std::vector<int> threads;
  std::vector<std::string> set;
  std::vector<std::string> per_spacing;  // "key=factor": key = factor * l0
  double time_step_per_spacing = 0.02;   // s/m
  double start_time = 0.0;               // s
  long long warmup_steps = 5;
  long long steps = 20;
  bool kernels = true;
  std::string json;  // also write the results here
  bool quiet = false;
};

int run_command(const RunCommand& command);
int bench_command(const BenchCommand& command, char** argv);
int resume_command(const ResumeCommand& command);
int compare_command(const CompareCommand& command);
int methods_command(bool with_parameters);

}  // namespace mps_lab::app
