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
  id.push_back(static_cast<std::uint32_t>(id.size()));
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

void permute_particles(ParticleSet& particles, const ParticleOrder& order) {
  if (order.size() != particles.size()) {
    throw std::logic_error("particle order of " + std::to_string(order.size()) + " particles for a set of " +
                           std::to_string(particles.size()));
  }
  permute_values(particles.position, order);
  permute_values(particles.velocity, order);
  permute_values(particles.pressure, order);
  permute_values(particles.type, order);
  permute_values(particles.wall_layer, order);
  permute_values(particles.wall_velocity, order);
  permute_values(particles.wall_acceleration, order);
  permute_values(particles.id, order);
  for (auto& [name, values] : particles.scalar_fields) permute_values(values, order);
}

std::vector<std::uint32_t> indices_in_id_order(const ParticleSet& particles) {
  // The ids are a permutation of 0..N-1 (add() numbers them, permute_particles moves them).
  std::vector<std::uint32_t> indices(particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i) indices[particles.id[i]] = static_cast<std::uint32_t>(i);
  return indices;
}

void hold_walls_at_prescribed_velocity(ParticleSet& particles) {
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] == ParticleType::Wall) particles.velocity[i] = particles.prescribed_wall_velocity(i);
  }
}

}  // namespace mps_lab
