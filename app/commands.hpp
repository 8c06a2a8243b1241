#pragma once
// Sub-commands of the mps_lab front end. Each returns the process exit code:
// 0 success, 1 the run failed (diverged, solver failure), 2 bad input, 3 output error.
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
  bool quiet = false;
};

struct CompareCommand {
  std::string scene;
  std::vector<std::string> methods;
  std::string out;
  std::vector<std::string> set;
  std::optional<double> end_time;
  bool analysis = true;
  bool quiet = false;
};

int run_command(const RunCommand& command);
int compare_command(const CompareCommand& command);
int methods_command(bool with_parameters);

}  // namespace mps_lab::app
