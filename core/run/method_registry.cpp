// The method registry (core/run/method.hpp) and which wall treatments a method may use.
#include <algorithm>
#include <stdexcept>

#include "core/io/scene.hpp"
#include "core/run/method.hpp"
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {

void MethodRegistry::add(MethodInfo info) {
  if (info.name.empty() || !info.create) throw std::logic_error("a method needs a name and a factory");
  const std::string name = info.name;
  if (!entries_.emplace(name, std::move(info)).second) {
    throw std::logic_error("method '" + name + "' registered twice");
  }
}

const MethodInfo* MethodRegistry::find(const std::string& name) const {
  auto found = entries_.find(name);
  return found == entries_.end() ? nullptr : &found->second;
}

std::vector<const MethodInfo*> MethodRegistry::all() const {
  std::vector<const MethodInfo*> out;
  for (const auto& [name, info] : entries_) out.push_back(&info);
  return out;
}

std::vector<std::string> MethodRegistry::names() const {
  std::vector<std::string> out;
  for (const auto& [name, info] : entries_) out.push_back(name);
  return out;
}

namespace {

// The boundary part of the support rule: what the method's operators do with the wall.
std::string boundary_gap(const WallTreatmentInfo& wall, const MethodInfo& method) {
  if (wall.role != WallTreatmentRole::Boundary) return "";
  if (!wall.wall_particle_model) {
    return method.wall_samples
               ? ""
               : "it is a boundary model of wall samples, which '" + method.name + "' does not sum over";
  }
  const auto& models = method.wall_particle_models;
  if (std::find(models.begin(), models.end(), *wall.wall_particle_model) != models.end()) return "";
  return std::string("its wall particles need the wall-particle model ") +
         wall_particle_pressure_name(*wall.wall_particle_model) + ", which '" + method.name + "' does not implement";
}

// The hook part: the method calls every hook where the treatment acts (but its optional ones).
std::string hook_gap(const WallTreatmentInfo& wall, const MethodInfo& method) {
  const WallHooks missing = wall.hooks.without(wall.optional_hooks).without(method.wall_hooks);
  if (!missing.empty()) return "it acts at " + missing.names() + ", which '" + method.name + "' does not call";
  if (!wall.hooks.empty() && !wall.hooks.intersects(method.wall_hooks)) {
    return "it acts at " + wall.hooks.names() + ", none of which '" + method.name + "' calls";
  }
  return "";
}

}  // namespace

std::string wall_treatment_support_gap(const WallTreatmentInfo& wall, const MethodInfo& method) {
  const std::string boundary = boundary_gap(wall, method);
  return boundary.empty() ? hook_gap(wall, method) : boundary;
}

bool wall_treatment_supports(const WallTreatmentInfo& wall, const MethodInfo& method) {
  return wall_treatment_support_gap(wall, method).empty();
}

std::string obstacle_loads_gap(const Scene& scene, const MethodInfo& method) {
  if (scene.walls.obstacles.empty()) return "";
  const WallTreatmentChoice* boundary = boundary_choice(scene.method_config(method.name).wall_treatments);
  if (boundary == nullptr) return "the boundary model (none) has no wall particles to carry the reaction";
  if (boundary->info->wall_particles) {
    if (!method.obstacle_loads) return "method '" + method.name + "' does not compute the reaction on wall particles";
    return "";
  }
  if (!method.sample_obstacle_loads) {
    return "method '" + method.name + "' does not compute the load on the wall samples of the boundary model " +
           boundary->info->name;
  }
  return "";
}

namespace {

// "methods.<name>.<key><op><value>" for each {key, value} of a load setting.
std::vector<std::string> block_assignments(const MethodInfo& method,
                                           const std::vector<std::pair<std::string, std::string>>& entries,
                                           const std::string& op) {
  std::vector<std::string> assignments;
  for (const auto& [key, value] : entries) assignments.push_back("methods." + method.name + "." + key + op + value);
  return assignments;
}

}  // namespace

std::vector<std::string> load_setting_overrides(const MethodInfo& method) {
  return block_assignments(method, method.load_setting.parameters, "=");
}

std::vector<std::string> load_setting_defaults(const MethodInfo& method) {
  return block_assignments(method, method.load_setting.defaults, "?=");
}

std::vector<std::string> with_load_setting(const MethodInfo& method, const std::vector<std::string>& invocation) {
  std::vector<std::string> assignments = load_setting_overrides(method);
  assignments.insert(assignments.end(), invocation.begin(), invocation.end());
  const std::vector<std::string> defaults = load_setting_defaults(method);
  assignments.insert(assignments.end(), defaults.begin(), defaults.end());
  return assignments;
}

bool reports_obstacle_loads(const Scene& scene, const MethodInfo& method) {
  return !scene.walls.obstacles.empty() && obstacle_loads_gap(scene, method).empty();
}

}  // namespace mps_lab
