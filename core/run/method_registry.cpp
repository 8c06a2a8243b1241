// The method registry (core/run/method.hpp) and which wall treatments a method may use.
#include <algorithm>
#include <stdexcept>

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

bool wall_treatment_supports(const WallTreatmentInfo& wall, const MethodInfo& method) {
  if (wall.role == WallTreatmentRole::Boundary && !wall.wall_particles && method.wall_samples) return true;
  return std::find(wall.methods.begin(), wall.methods.end(), method.name) != wall.methods.end();
}

}  // namespace mps_lab
