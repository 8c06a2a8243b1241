#pragma once
// Helpers shared by the tests: registries, scenes from the scenes/ folder with overrides,
// temporary folders, running the built binary.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/base/error.hpp"
#include "core/base/particles.hpp"
#include "core/io/scene.hpp"
#include "core/run/method.hpp"
#include "core/walls/wall_samples.hpp"
#include "core/walls/wall_treatment.hpp"

namespace mps_lab::testing {

struct Registries {
  MethodRegistry methods = builtin_methods();
  WallTreatmentRegistry walls = builtin_wall_treatments();
};

inline const Registries& registries() {
  static const Registries instance;  // immutable after construction
  return instance;
}

inline std::string scene_path(const std::string& name) { return std::string(MPS_LAB_SOURCE_DIR) + "/scenes/" + name; }

inline Scene load(const std::string& name, const std::vector<std::string>& overrides = {}) {
  return load_scene(scene_path(name), overrides, registries().methods, registries().walls);
}

// Every boundary model (a wall treatment of role Boundary) that `method` supports, from the
// registry's declared capabilities (wall_treatment_supports).
inline std::vector<const WallTreatmentInfo*> boundary_models(const MethodInfo& method) {
  std::vector<const WallTreatmentInfo*> models;
  for (const auto* wall : registries().walls.all()) {
    if (wall->role == WallTreatmentRole::Boundary && wall_treatment_supports(*wall, method)) models.push_back(wall);
  }
  return models;
}

// The method's load setting (MethodInfo::load_setting) with `boundary_model` (empty: its default),
// as `mps_lab run --load-setting --set methods.M.wall_treatments={"MODEL":{}}` applies it.
inline std::vector<std::string> load_setting_with(const MethodInfo& method, const std::string& boundary_model) {
  std::vector<std::string> invocation;
  if (!boundary_model.empty()) {
    invocation.push_back("methods." + method.name + ".wall_treatments={\"" + boundary_model + "\":{}}");
  }
  return with_load_setting(method, invocation);
}

// The one-line error of scenes/<name> with `overrides`, "" if the scene loads.
// The scene overrides that make `model` the boundary model of `method` in the scene file `name`:
// "method=...", the model enabled, the scene's other enabled boundary model of that method off
// (the measures keep the scene's settings).
inline std::vector<std::string> boundary_model_overrides(const std::string& name, const std::string& method,
                                                         const std::string& model) {
  std::vector<std::string> overrides = {"method=" + method,
                                        "methods." + method + ".wall_treatments." + model + ".enabled=true"};
  const Scene scene = load(name, {"method=" + method});
  for (const WallTreatmentChoice& choice : scene.method_config(method).wall_treatments) {
    if (choice.enabled && choice.info->role == WallTreatmentRole::Boundary && choice.info->name != model) {
      overrides.push_back("methods." + method + ".wall_treatments." + choice.info->name + ".enabled=false");
    }
  }
  return overrides;
}

inline std::string scene_error(const std::string& name, const std::vector<std::string>& overrides) {
  try {
    load(name, overrides);
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

inline Scene parse(const std::string& json_text, const std::string& source = "inline.json") {
  return parse_scene(nlohmann::json::parse(json_text), source, registries().methods, registries().walls);
}

// A fresh empty folder for one test's output, under the build folder's test-output/
// (MPS_LAB_TEST_OUTPUT_DIR), so that test runs of different build folders never share one.
inline std::filesystem::path fresh_directory(const std::string& name) {
  const auto path = std::filesystem::path(MPS_LAB_TEST_OUTPUT_DIR) / name;
  std::filesystem::remove_all(path);
  std::filesystem::create_directories(path);
  return path;
}

inline std::string read_text(const std::filesystem::path& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

inline void write_text(const std::filesystem::path& path, const std::string& text) {
  std::ofstream file(path);
  file << text;
}

struct CommandResult {
  int exit_code = -1;
  std::string stdout_text;
  std::string stderr_text;
};

// Runs build/mps_lab with the given arguments (already shell-quoted where needed).
inline CommandResult run_mps_lab(const std::string& arguments, const std::string& tag) {
  const auto dir = fresh_directory("cli_" + tag);
  const std::string command =
      std::string(MPS_LAB_BINARY) + " " + arguments + " > " + (dir / "out").string() + " 2> " + (dir / "err").string();
  const int status = std::system(command.c_str());
  CommandResult result;
  result.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.stdout_text = read_text(dir / "out");
  result.stderr_text = read_text(dir / "err");
  return result;
}

// Every file of a run folder by name (frames, frame index), except those that differ between an interrupted and an
// uninterrupted run by design (run.json: timestamps, "resumed"; series.csv: wall_seconds) or
// exist only with checkpoints.
inline std::map<std::string, std::string> run_folder_files(const std::filesystem::path& folder) {
  std::map<std::string, std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (name == "run.json" || name == "series.csv" || name == "checkpoint.bin") continue;
    files[name] = read_text(entry.path());
  }
  return files;
}

// The lines of series.csv (as text) without their wall_seconds cell.
inline std::vector<std::string> series_rows_without_wall_seconds(const std::filesystem::path& folder) {
  std::istringstream text(read_text(folder / "series.csv"));
  std::string line;
  std::vector<std::string> rows;
  std::size_t wall = std::string::npos;
  while (std::getline(text, line)) {
    std::vector<std::string> cells;
    std::istringstream cells_text(line);
    std::string cell;
    while (std::getline(cells_text, cell, ',')) cells.push_back(cell);
    if (wall == std::string::npos) {
      wall = static_cast<std::size_t>(std::find(cells.begin(), cells.end(), "wall_seconds") - cells.begin());
      if (wall >= cells.size()) throw std::runtime_error((folder / "series.csv").string() + ": no wall_seconds column");
    }
    cells.erase(cells.begin() + static_cast<std::ptrdiff_t>(wall));
    std::string row;
    for (const auto& kept : cells) row += kept + ",";
    rows.push_back(row);
  }
  return rows;
}

// Centre of mass of the fluid particles (equal masses), m.
inline Vec2 fluid_centroid(const ParticleSet& particles) {
  Vec2 sum = Vec2::Zero();
  std::size_t count = 0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] != ParticleType::Fluid) continue;
    sum += particles.position[i];
    ++count;
  }
  return sum / static_cast<double>(count);
}

// Two fluid particles for hand-computed operator sums: A at the origin and B at (spacing, 0), with
// pressures p_a and p_b (Pa).
inline ParticleSet fluid_pair(double spacing, double p_a, double p_b) {
  ParticleSet particles;
  particles.add(Vec2(0.0, 0.0), Vec2::Zero(), ParticleType::Fluid);
  particles.add(Vec2(spacing, 0.0), Vec2::Zero(), ParticleType::Fluid);
  particles.pressure = {p_a, p_b};
  return particles;
}

// Wall samples of the first of two particles (fluid_pair) at `positions`: fixed tank points of
// volume 1 whose source is that particle; the second has none.
inline WallSampleList samples_of_first(const std::vector<Vec2>& positions) {
  WallSampleList samples;
  const auto count = static_cast<std::uint32_t>(positions.size());
  samples.offsets = {0, count, count};
  for (const Vec2& position : positions) {
    WallSample wall;
    wall.position = position;
    wall.source = 0;
    samples.samples.push_back(wall);
  }
  return samples;
}

// Highest fluid particle centre, m.
inline double fluid_top(const ParticleSet& particles) {
  double top = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] == ParticleType::Fluid) top = std::max(top, particles.position[i].y());
  }
  return top;
}

// Kinetic energy of the fluid per metre of depth, sum 1/2 rho l0^2 |u|^2, J/m.
inline double fluid_kinetic_energy(const ParticleSet& particles, double density, double spacing) {
  double energy = 0.0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] == ParticleType::Fluid)
      energy += 0.5 * density * spacing * spacing * particles.velocity[i].squaredNorm();
  }
  return energy;
}

// Reads a CSV with a header into named columns of doubles.
struct Table {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  std::vector<double> column(const std::string& name) const {
    std::size_t index = 0;
    while (index < header.size() && header[index] != name) ++index;
    if (index == header.size()) throw std::runtime_error("no column " + name);
    std::vector<double> values;
    for (const auto& row : rows) values.push_back(row.at(index));
    return values;
  }
};

inline Table read_table(const std::filesystem::path& path) {
  std::ifstream file(path);
  std::string line;
  Table table;
  while (std::getline(file, line)) {
    std::vector<std::string> cells;
    std::stringstream stream(line);
    std::string cell;
    while (std::getline(stream, cell, ',')) cells.push_back(cell);
    if (table.header.empty()) {
      table.header = cells;
      continue;
    }
    std::vector<double> row;
    for (const auto& text : cells) row.push_back(std::stod(text));
    table.rows.push_back(row);
  }
  return table;
}

}  // namespace mps_lab::testing
