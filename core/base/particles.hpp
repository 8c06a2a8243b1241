#pragma once
// Particle storage: structure of arrays, no fixed particle or neighbour limits.
// Core fields every method shares (position, velocity, pressure, type, wall layer) plus
// named scalar fields that a method declares (e.g. "number_density"); declared fields can
// be written to the VTK frames.
#include <cstddef>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/base/particle_order.hpp"
#include "core/base/rigid_pose.hpp"
#include "core/base/types.hpp"

namespace mps_lab {

struct ParticleSet {
  std::vector<Vec2> position;    // m
  std::vector<Vec2> velocity;    // m/s
  std::vector<double> pressure;  // Pa
  std::vector<ParticleType> type;
  // 0 for fluid; for walls, 1 = the layer facing the fluid, 2, 3, ... = outer layers
  // (Chebyshev distance from the fluid region in units of l0, plus one).
  std::vector<std::uint8_t> wall_layer;
  // The prescribed motion of wall particles (core/walls/moving_walls.hpp): empty while every
  // wall is at rest (fixed walls cost nothing), else one entry per particle (zero for fluid and
  // fixed walls). The driver sets them each step from the motion laws; a method holds a wall
  // particle's velocity at prescribed_wall_velocity(i) and may read its acceleration.
  std::vector<Vec2> wall_velocity;      // m/s
  std::vector<Vec2> wall_acceleration;  // m/s^2
  Vec2 prescribed_wall_velocity(std::size_t i) const { return wall_velocity.empty() ? Vec2::Zero() : wall_velocity[i]; }
  Vec2 prescribed_wall_acceleration(std::size_t i) const {
    return wall_acceleration.empty() ? Vec2::Zero() : wall_acceleration[i];
  }
  // The pose of every obstacle (walls.obstacles[k], core/base/rigid_pose.hpp) at the time the
  // step solves for: empty while every wall is at rest, else one per obstacle (zero for a fixed
  // one). Set by the driver with wall_velocity; the boundary models of wall samples move their
  // wall with it (core/walls/wall_geometry.hpp). Not per particle: a reordering leaves it.
  std::vector<RigidPose> obstacle_pose;
  // Method-declared per-particle scalars, keyed by name (std::map: references stay valid).
  std::map<std::string, std::vector<double>> scalar_fields;
  // The persistent particle id: the index at which add() created the particle. The particles
  // are reordered by cell every run.sort_period steps (core/search/cell_order.hpp), their ids
  // with them; frames are written in id order, so a row of a frame is the same particle in
  // every frame whatever the order in memory (docs/architecture.md, "Cell-ordered particles").
  std::vector<std::uint32_t> id;

  std::size_t size() const { return position.size(); }
  void add(const Vec2& x, const Vec2& v, ParticleType kind, std::uint8_t layer = 0);
  std::size_t count(ParticleType kind) const;

  // Adds (zero-filled) or returns a declared scalar field.
  std::vector<double>& add_field(const std::string& name);
  std::vector<double>& field(const std::string& name);
  const std::vector<double>& field(const std::string& name) const;
};

// Moves every per-particle array of the set (the core arrays, the ids, the prescribed wall
// motion when in use, every named field) by `order` (core/base/particle_order.hpp).
void permute_particles(ParticleSet& particles, const ParticleOrder& order);

// The indices of the particles in increasing id: k-th entry = the index of the particle with
// the k-th smallest id (for writing frames in id order).
std::vector<std::uint32_t> indices_in_id_order(const ParticleSet& particles);

// Every wall particle's velocity to its prescribed one: zero for a fixed wall (spec §7), the
// motion law's for a moving obstacle's (core/walls/moving_walls.hpp). The methods call it after
// each velocity update, so that the viscous term sees the wall's own velocity.
void hold_walls_at_prescribed_velocity(ParticleSet& particles);

}  // namespace mps_lab
