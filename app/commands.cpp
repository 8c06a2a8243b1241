#include "app/commands.hpp"

#include <cstdio>
#include <iostream>

#include <unistd.h>

#include "core/driver.hpp"
#include "core/error.hpp"
#include "core/method.hpp"
#include "core/wall_treatment.hpp"

namespace mps_lab::app {

int run_command(const RunCommand& command) {
  const MethodRegistry methods = builtin_methods();
  const WallTreatmentRegistry walls = builtin_wall_treatments();
  RunOptions options;
  options.scene_path = command.scene;
  options.method = command.method;
  options.output_directory = command.out;
  options.overrides = command.set;
  options.end_time = command.end_time;
  options.progress = !command.quiet;
  const RunResult result = run_simulation(options, methods, walls);
  if (result.status != "completed") {
    std::fprintf(stderr, "mps_lab: run %s at t = %.6g s after %lld steps: %s (see %s/run.json)\n",
                 result.status.c_str(), result.simulated_time, result.steps, result.message.c_str(),
                 result.directory.c_str());
    return 1;
  }
  if (!command.quiet) {
    const auto& summary = result.summary;
    std::printf("%s: %lld steps to t = %.4g s in %.2f s wall (%d threads), mean solver iterations %.1f -> %s/\n",
                summary["method"].get<std::string>().c_str(), result.steps, result.simulated_time,
                result.wall_seconds, summary["threads"].get<int>(),
                summary["solver"]["mean_iterations"].get<double>(), result.directory.c_str());
  }
  return 0;
}

int methods_command(bool with_parameters) {
  const MethodRegistry methods = builtin_methods();
  const WallTreatmentRegistry walls = builtin_wall_treatments();
  std::size_t width = 0;
  for (const auto* info : methods.all()) width = std::max(width, info->name.size());
  for (const auto* info : methods.all()) {
    std::printf("%-*s  %s\n", static_cast<int>(width), info->name.c_str(), info->description.c_str());
    if (!with_parameters) continue;
    for (const auto& spec : info->parameters) {
      std::printf("    methods.%s.%s = %s %s  (%s) %s\n", info->name.c_str(), spec.name.c_str(),
                  spec.default_value.dump().c_str(), spec.unit.c_str(), spec.range_text().c_str(),
                  spec.description.c_str());
    }
    for (const auto* wall : walls.all()) {
      bool supported = false;
      for (const auto& name : wall->methods) supported = supported || name == info->name;
      if (!supported) continue;
      bool default_on = false;
      for (const auto& name : info->default_wall_treatments) default_on = default_on || name == wall->name;
      std::printf("    wall treatment %s (%s): %s\n", wall->name.c_str(), default_on ? "on by default" : "off by default",
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
