#include "core/base/particles.hpp"

#include <algorithm>
#include <stdexcept>

namespace mps_lab {

void ParticleSet::add(const Vec2& x, const Vec2& v, ParticleType kind, std::uint8_t layer) {
  position.push_back(x);
  velocity.push_back(v);
  pressure.push_back(0.0);
  type.push_back(kind);
  wall_layer.push_back(layer);
  for (auto& [name, values] : scalar_fields) values.push_back(0.0);
}

std::size_t ParticleSet::count(ParticleType kind) const {
  return static_cast<std::size_t>(std::count(type.begin(), type.end(), kind));
}

std::vector<double>& ParticleSet::add_field(const std::string& name) {
  auto& values = scalar_fields[name];
  values.resize(size(), 0.0);
  return values;
}

std::vector<double>& ParticleSet::field(const std::string& name) {
  auto found = scalar_fields.find(name);
  if (found == scalar_fields.end()) throw std::logic_error("particle field '" + name + "' was not declared");
  return found->second;
}

const std::vector<double>& ParticleSet::field(const std::string& name) const {
  auto found = scalar_fields.find(name);
  if (found == scalar_fields.end()) throw std::logic_error("particle field '" + name + "' was not declared");
  return found->second;
}

void hold_walls_at_prescribed_velocity(ParticleSet& particles) {
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] == ParticleType::Wall) particles.velocity[i] = particles.prescribed_wall_velocity(i);
  }
}

}  // namespace mps_lab
