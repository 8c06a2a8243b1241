#include "lab/compare.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>

#include <nlohmann/json.hpp>

#include "core/base/error.hpp"
#include "core/io/output.hpp"
#include "core/run/driver.hpp"
#include "lab/validation.hpp"

namespace mps_lab {

namespace fs = std::filesystem;

namespace {

std::map<std::string, std::vector<double>> read_series(const fs::path& path) {
  std::ifstream file(path);
  if (!file) throw_input_error(path.string(), "", "cannot open the series");
  std::string line;
  std::vector<std::string> header;
  std::map<std::string, std::vector<double>> columns;
  while (std::getline(file, line)) {
    const std::vector<std::string> cells = split_csv_line(line);
    if (header.empty()) {
      header = cells;
      continue;
    }
    for (std::size_t k = 0; k < header.size() && k < cells.size(); ++k)
      columns[header[k]].push_back(std::stod(cells[k]));
  }
  return columns;
}

}  // namespace

RunEvaluation evaluate_run(const fs::path& folder) {
  std::ifstream file(folder / "run.json");
  if (!file) throw_input_error((folder / "run.json").string(), "", "cannot open the run summary");
  const nlohmann::json run = nlohmann::json::parse(file);
  const auto series = read_series(folder / "series.csv");

  RunEvaluation out;
  out.method = run.at("method");
  out.status = run.at("status");
  out.steps = run.value("steps", 0LL);
  out.wall_seconds = run.value("wall_seconds", 0.0);
  out.particle_steps_per_second = run.value("fluid_particle_steps_per_second", 0.0);
  out.mean_solver_iterations = run.contains("solver") ? run["solver"].value("mean_iterations", 0.0) : 0.0;
  out.ghosts = run.contains("particles") ? run["particles"].value("ghost_final", 0LL) : 0LL;

  const double a = run.at("column").at("width");
  const double h = run.at("column").at("height");
  const auto& g = run.at("shared").at("gravity");
  const double gravity = std::hypot(g.at(0).get<double>(), g.at(1).get<double>());
  const auto& time = series.at("time");

  const Curve front = front_curve(time, series.at("front"), a, h, gravity);
  const Curve table2 =
      read_curve_csv(validation_data_path("martin_moyce_1952_n2_front.csv"), "T_n_t_sqrt_g_over_a", "Z_x_over_a");
  const CurveError front_error = curve_error(front, table2);
  const CurveError shifted = best_shift_error(front, table2, 0.3, 0.001);
  out.front_rms = front_error.rms;
  out.front_max = front_error.max;
  out.front_points = front_error.points;
  out.front_shift = shifted.shift;
  out.front_rms_shifted = shifted.rms;

  const Curve height = height_curve(time, series.at("height"), a, h, gravity);
  const Curve table6 =
      read_curve_csv(validation_data_path("martin_moyce_1952_n2_height.csv"), "tau_t_sqrt_g_over_a", "H_h_over_n2a");
  const CurveError height_error = curve_error(height, table6);
  out.height_rms = height_error.rms;
  out.height_max = height_error.max;
  out.height_points = height_error.points;

  const auto& density = series.at("density_error");
  double sum = 0.0;
  for (std::size_t k = 1; k < density.size(); ++k) {  // row 0 is the initial lattice
    sum += density[k];
    out.density_error_max = std::max(out.density_error_max, density[k]);
  }
  out.density_error_mean = density.size() > 1 ? sum / static_cast<double>(density.size() - 1) : 0.0;
  return out;
}

std::string summary_csv(const std::vector<RunEvaluation>& rows) {
  std::string text =
      "method,status,steps,wall_seconds,particle_steps_per_second,mean_solver_iterations,front_rms,front_max,"
      "front_points,front_best_shift,front_rms_shifted,height_rms,height_max,height_points,density_error_mean,"
      "density_error_max,ghosts\n";
  for (const auto& row : rows) {
    const std::vector<std::string> cells = {row.method,
                                            row.status,
                                            std::to_string(row.steps),
                                            format_double(row.wall_seconds),
                                            format_double(row.particle_steps_per_second),
                                            format_double(row.mean_solver_iterations),
                                            format_double(row.front_rms),
                                            format_double(row.front_max),
                                            std::to_string(row.front_points),
                                            format_double(row.front_shift),
                                            format_double(row.front_rms_shifted),
                                            format_double(row.height_rms),
                                            format_double(row.height_max),
                                            std::to_string(row.height_points),
                                            format_double(row.density_error_mean),
                                            format_double(row.density_error_max),
                                            std::to_string(row.ghosts)};
    for (std::size_t k = 0; k < cells.size(); ++k) text += (k ? "," : "") + cells[k];
    text += '\n';
  }
  return text;
}

std::vector<RunEvaluation> compare_methods(const CompareOptions& options, const MethodRegistry& methods,
                                           const WallTreatmentRegistry& walls) {
  std::vector<std::string> names = options.methods.empty() ? methods.names() : options.methods;
  for (const auto& name : names) {
    if (methods.find(name) == nullptr) {
      std::string known;
      for (const auto& entry : methods.names()) known += (known.empty() ? "" : ", ") + entry;
      throw_input_error("--methods", name, "unknown method (registered: " + known + ")");
    }
  }
  std::error_code error;
  fs::create_directories(options.output_directory, error);
  if (error || !fs::is_directory(options.output_directory)) {
    throw OutputError(options.output_directory.string() + ": cannot create the output folder");
  }
  std::vector<RunEvaluation> rows;
  for (const auto& name : names) {
    RunOptions run;
    run.scene_path = options.scene_path;
    run.method = name;
    run.output_directory = (options.output_directory / name).string();
    run.overrides = options.overrides;
    run.end_time = options.end_time;
    run.load_setting = options.load_setting;
    run.progress = options.progress;
    run.stop_reason = options.stop_reason;
    const RunResult result = run_simulation(run, methods, walls);
    if (options.progress) {
      std::fprintf(stderr, "%s: %s, %lld steps, %.2f s wall\n", name.c_str(), result.status.c_str(), result.steps,
                   result.wall_seconds);
    }
    rows.push_back(evaluate_run(run.output_directory));
    write_file_atomically(options.output_directory / "summary.csv", summary_csv(rows));
    if (result.status == "interrupted") break;
  }
  return rows;
}

}  // namespace mps_lab
