// The wall-treatment registry and the ordered set of one run's treatments
// (core/walls/wall_treatment.hpp).
#include <algorithm>
#include <stdexcept>

#include "core/io/checkpoint.hpp"
#include "core/io/scene.hpp"
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {

const char* wall_hook_name(WallHook hook) {
  switch (hook) {
    case WallHook::AfterExplicitVelocity:
      return "after_explicit_velocity";
    case WallHook::AfterExplicitPosition:
      return "after_explicit_position";
    case WallHook::AfterNeighbourSearch:
      return "after_neighbour_search";
    case WallHook::AfterCorrection:
      return "after_correction";
  }
  return "unknown hook";
}

std::string WallHooks::names() const {
  std::string out;
  for (const WallHook hook : kAllWallHooks) {
    if (!contains(hook)) continue;
    out += (out.empty() ? "" : ", ") + std::string(wall_hook_name(hook));
  }
  return out.empty() ? "none" : out;
}

const char* wall_particle_pressure_name(WallParticlePressure model) {
  switch (model) {
    case WallParticlePressure::SolvedInPpe:
      return "solved_in_ppe";
    case WallParticlePressure::AdamiExtrapolated:
      return "adami_extrapolated";
    case WallParticlePressure::AkinciMirrored:
      return "akinci_mirrored";
  }
  return "unknown wall-particle model";
}

namespace {

// The declarations of a treatment agree with each other (a programming error otherwise).
void check_declarations(const WallTreatmentInfo& info) {
  const std::string name = "wall treatment '" + info.name + "': ";
  for (const auto& spec : info.parameters) {
    if (spec.name == "enabled") throw std::logic_error(name + "'enabled' is reserved");
  }
  if (!info.hooks.contains(info.optional_hooks)) throw std::logic_error(name + "optional hooks it does not act at");
  if (info.role == WallTreatmentRole::Measure && info.hooks.empty()) {
    throw std::logic_error(name + "a measure declares the hooks where it acts");
  }
  if (info.role == WallTreatmentRole::Measure && info.wall_particle_model) {
    throw std::logic_error(name + "a measure is no model of wall particles");
  }
}

}  // namespace

void WallTreatmentRegistry::add(WallTreatmentInfo info) {
  if (info.name.empty() || !info.create) throw std::logic_error("a wall treatment needs a name and a factory");
  const std::string name = info.name;
  check_declarations(info);
  info.wall_particles = info.wall_particle_model.has_value();
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
                                   PhaseTimers* timers, WallHooks called)
    : timers_(timers), phase_(phase_id(timers, "wall_treatment")), called_(called) {
  std::vector<const WallTreatmentChoice*> enabled;
  for (const auto& choice : choices) {
    if (choice.enabled) enabled.push_back(&choice);
  }
  std::stable_sort(enabled.begin(), enabled.end(),
                   [](const auto* a, const auto* b) { return a->info->order < b->info->order; });
  for (const auto* choice : enabled) {
    const WallTreatmentInfo& info = *choice->info;
    const WallHooks missing = info.hooks.without(info.optional_hooks).without(called_);
    if (!missing.empty()) {  // the scene loader refuses it (wall_treatment_supports); a set built by hand
      throw std::logic_error("wall treatment '" + info.name + "' acts at " + missing.names() +
                             ", which the method does not call");
    }
    members_.emplace_back(info.name, info.create({scene, choice->parameters}));
    check_all_read(choice->parameters, "wall treatment '" + info.name + "'");
    if (info.role == WallTreatmentRole::Boundary) {
      boundary_ = members_.back().second.get();
      boundary_name_ = info.name;
      wall_particles_ = info.wall_particles;
      wall_particle_model_ = info.wall_particles ? dynamic_cast<const WallParticleModel*>(boundary_) : nullptr;
      if (info.wall_particles && wall_particle_model_ == nullptr) {
        throw std::logic_error("wall treatment '" + info.name +
                               "' declares wall particles but is no WallParticleModel");
      }
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

void search_neighbours_and_wall_samples(const ParticleSet& particles, double support, PhaseTimers* timers,
                                        PhaseTimers::Id search_phase, CellList& cells, NeighbourList& neighbours,
                                        WallTreatmentSet& walls, WallContext& context, WallSampleList& samples) {
  {
    const auto timed = measure(timers, search_phase);
    cells.build(particles.position, particles.type, support);
    cells.find_neighbours(particles.position, particles.type, support, neighbours);
  }
  context.samples = &samples;
  context.support = support;
  walls.build_wall_samples(context, samples);
}

void check_restored_search(CheckpointReader& in, const std::string& method, const NeighbourList& neighbours,
                           const WallSampleList& samples, const WallTreatmentSet& walls, std::size_t particle_count) {
  if (neighbours.particle_count() != particle_count) {
    in.fail(method + " state for " + std::to_string(neighbours.particle_count()) + " particles, the scene has " +
            std::to_string(particle_count));
  }
  if (samples.has_samples() != !walls.wall_particles() ||
      (samples.has_samples() && samples.offsets.size() != particle_count + 1)) {
    in.fail(method + " wall samples that do not fit the boundary model " + walls.boundary_name() + " and " +
            std::to_string(particle_count) + " particles");
  }
}

const WallTreatmentChoice* boundary_choice(const std::vector<WallTreatmentChoice>& choices) {
  for (const auto& choice : choices) {
    if (choice.enabled && choice.info->role == WallTreatmentRole::Boundary) return &choice;
  }
  return nullptr;
}

// A method calls only the hooks it declares (MethodInfo::wall_hooks): a treatment's support
// was computed from them.
void WallTreatmentSet::check_called(WallHook hook) const {
  if (!called_.contains(hook)) {
    throw std::logic_error(std::string("a method called the wall hook ") + wall_hook_name(hook) +
                           " it does not declare (MethodInfo::wall_hooks)");
  }
}

void WallTreatmentSet::after_explicit_velocity(WallContext& context) {
  check_called(WallHook::AfterExplicitVelocity);
  const auto timed = measure(timers_, phase_);
  for (auto& member : members_) member.second->after_explicit_velocity(context);
}
void WallTreatmentSet::after_explicit_position(WallContext& context) {
  check_called(WallHook::AfterExplicitPosition);
  const auto timed = measure(timers_, phase_);
  for (auto& member : members_) member.second->after_explicit_position(context);
}
void WallTreatmentSet::after_neighbour_search(WallContext& context) {
  check_called(WallHook::AfterNeighbourSearch);
  const auto timed = measure(timers_, phase_);
  for (auto& member : members_) member.second->after_neighbour_search(context);
}
void WallTreatmentSet::after_correction(WallContext& context) {
  check_called(WallHook::AfterCorrection);
  const auto timed = measure(timers_, phase_);
  for (auto& member : members_) member.second->after_correction(context);
}

void WallTreatmentSet::permute_state(const ParticleOrder& order) {
  for (auto& [name, treatment] : members_) treatment->permute_state(order);
}

std::vector<std::string> WallTreatmentSet::names() const {
  std::vector<std::string> out;
  for (const auto& member : members_) out.push_back(member.first);
  return out;
}

}  // namespace mps_lab
