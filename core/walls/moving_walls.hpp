#pragma once
// Moving walls: the wall particles of the obstacles that have a motion law
// (walls.obstacles[k].motion, core/walls/wall_motion.hpp), moved by the driver every step.
//
// The law is a function of time, so a wall particle's position is recomputed, never integrated:
// x_b(t) = x_b(0) + d_k(t), u_b = u_k(t), a_b = a_k(t), with x_b(0) the lattice point the scene
// gives it (core/io/geometry.cpp). A run resumed from a checkpoint therefore puts the walls
// exactly where the uninterrupted run has them. Which wall particles belong to obstacle k is
// read from the initial particles: those on or inside its box that are not tank walls (a
// point both hold, e.g. where a gate stands on the bed, stays with the fixed tank).
// Wall particles carried out of the domain (a gate lifted out of the tank) stay walls: the
// ghost rule (spec §7.3) turns only fluid into ghosts.
#include <cstdint>
#include <vector>

#include "core/base/particles.hpp"
#include "core/io/scene.hpp"

namespace mps_lab {

class MovingWalls {
 public:
  // `initial`: the particles as build_particles made them (same order as the run's).
  MovingWalls(const Scene& scene, const ParticleSet& initial);
  bool empty() const { return members_.empty(); }
  // Wall particles of moving obstacles to their positions, velocities and accelerations at
  // time t (s); sets particles.wall_velocity / wall_acceleration. Does nothing when empty().
  void apply(ParticleSet& particles, double t) const;
  // The particles were reordered (core/search/cell_order.hpp): each member follows its particle.
  void permute(const ParticleOrder& order);
  // How many wall particles obstacle k moves.
  std::size_t count(std::size_t k) const;

 private:
  struct Member {
    std::uint32_t index;  // in the ParticleSet
    std::uint32_t body;   // walls.obstacles[body]
    Vec2 rest;            // x_b(0), m
  };
  std::vector<Member> members_;
  std::vector<WallMotion> motions_;
};

}  // namespace mps_lab
