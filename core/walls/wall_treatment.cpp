// The wall-treatment registry and the ordered set of one run's treatments
// (core/walls/wall_treatment.hpp).
#include <algorithm>
#include <stdexcept>

#include "core/io/scene.hpp"
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {

void WallTreatmentRegistry::add(WallTreatmentInfo info) {
  if (info.name.empty() || !info.create) throw std::logic_error("a wall treatment needs a name and a factory");
  const std::string name = info.name;
  for (const auto& spec : info.parameters) {
    if (spec.name == "enabled") throw std::logic_error("wall treatment '" + name + "': 'enabled' is reserved");
  }
  if (!entries_.emplace(name, std::move(info)).second) {
    throw std::logic_error("wall treatment '" + name + "' registered twice");
  }
}

const WallTreatmentInfo* WallTreatmentRegistry::find(const std::string& name) const {
  auto found = entries_.find(name);
  return found == entries_.end() ? nullptr : &found->second;
}

std::vector<const WallTreatmentInfo*> WallTreatmentRegistry::all() const {
  std::vector<const WallTreatmentInfo*> out;
  for (const auto& [name, info] : entries_) out.push_back(&info);
  return out;
}

WallTreatmentSet::WallTreatmentSet(const std::vector<WallTreatmentChoice>& choices, const Scene& scene,
                                   PhaseTimers* timers)
    : timers_(timers), phase_(phase_id(timers, "wall_treatment")) {
  std::vector<const WallTreatmentChoice*> enabled;
  for (const auto& choice : choices) {
    if (choice.enabled) enabled.push_back(&choice);
  }
  std::stable_sort(enabled.begin(), enabled.end(), [](const auto* a, const auto* b) {
    return a->info->order < b->info->order;
  });
  for (const auto* choice : enabled) {
    members_.emplace_back(choice->info->name, choice->info->create({scene, choice->parameters}));
    check_all_read(choice->parameters, "wall treatment '" + choice->info->name + "'");
    if (choice->info->role == WallTreatmentRole::Boundary) {
      boundary_ = members_.back().second.get();
      boundary_name_ = choice->info->name;
      wall_particles_ = choice->info->wall_particles;
      boundary_parameters_ = choice->parameters;
    }
  }
}

void WallTreatmentSet::build_wall_samples(const WallContext& context, WallSampleList& samples) {
  const auto timed = measure(timers_, phase_);
  if (boundary_ == nullptr || wall_particles_) {
    samples.clear();
    return;
  }
  boundary_->build_wall_samples(context, samples);
}

const WallTreatmentChoice* boundary_choice(const std::vector<WallTreatmentChoice>& choices) {
  for (const auto& choice : choices) {
    if (choice.enabled && choice.info->role == WallTreatmentRole::Boundary) return &choice;
  }
  return nullptr;
}

void WallTreatmentSet::after_explicit_velocity(WallContext& context) {
  const auto timed = measure(timers_, phase_);
  for (auto& member : members_) member.second->after_explicit_velocity(context);
}
void WallTreatmentSet::after_explicit_position(WallContext& context) {
  const auto timed = measure(timers_, phase_);
  for (auto& member : members_) member.second->after_explicit_position(context);
}
void WallTreatmentSet::after_neighbour_search(WallContext& context) {
  const auto timed = measure(timers_, phase_);
  for (auto& member : members_) member.second->after_neighbour_search(context);
}
void WallTreatmentSet::after_correction(WallContext& context) {
  const auto timed = measure(timers_, phase_);
  for (auto& member : members_) member.second->after_correction(context);
}

std::vector<std::string> WallTreatmentSet::names() const {
  std::vector<std::string> out;
  for (const auto& member : members_) out.push_back(member.first);
  return out;
}

}  // namespace mps_lab
