#pragma once
// Moving walls: the wall particles of the obstacles that move - a motion law
// (walls.obstacles[k].motion, core/walls/wall_motion.hpp) or a rigid body
// (walls.obstacles[k].body, core/bodies/rigid_bodies.hpp) - moved by the driver every step.
//
// Each moving obstacle has a pose: a rigid motion from where the scene puts it, the
// displacement d of its reference point x_c0 (its surface's area centroid) and an angle theta.
// A wall particle's position is recomputed from its scene position x_b0, never integrated:
//   r0 = x_b0 - x_c0,  r = R(theta) r0
//   x_b = x_b0 + d + (r - r0)              (= x_c + R(theta) (x_b0 - x_c0))
//   u_b = u_c + omega x r                  (omega x r = omega (-r_y, r_x))
//   a_b = a_c + alpha x r - omega^2 r
// With theta = omega = alpha = 0 (every motion law) this is x_b0 + d, u_c, a_c to the bit.
// A pose is a function of the law's time or of the body's state, which a checkpoint holds, so
// a resumed run puts the walls exactly where the uninterrupted run has them. Which wall
// particles belong to obstacle k is read from the initial particles: those on or inside its
// box or polygon that are not tank walls (a point both hold, e.g. where a gate stands on the
// bed, stays with the fixed tank).
// Wall particles carried out of the domain (a gate lifted out of the tank) stay walls: the
// ghost rule (spec §7.3) turns only fluid into ghosts.
#include <cstdint>
#include <vector>

#include "core/base/particles.hpp"
#include "core/base/rigid_pose.hpp"
#include "core/io/scene.hpp"

namespace mps_lab {

// The pose of a motion law at time t (s): a translation, theta = 0.
RigidPose law_pose(const WallMotion& motion, double t);

class MovingWalls {
 public:
  // `initial`: the particles as build_particles made them (same order as the run's).
  MovingWalls(const Scene& scene, const ParticleSet& initial);
  bool empty() const { return members_.empty(); }
  // The pose of every obstacle at time t (s) by its motion law (at rest without one: a body's
  // pose is set by the caller).
  std::vector<RigidPose> law_poses(double t) const;
  // Wall particles of moving obstacles to their positions, velocities and accelerations by
  // `poses` (one per obstacle); sets particles.wall_velocity / wall_acceleration. Does nothing
  // when empty().
  void apply(ParticleSet& particles, const std::vector<RigidPose>& poses) const;
  // The same with the motion laws' poses at time t (s).
  void apply(ParticleSet& particles, double t) const { apply(particles, law_poses(t)); }
  // The particles were reordered (core/search/cell_order.hpp): each member follows its particle.
  void permute(const ParticleOrder& order);
  // How many wall particles obstacle k moves.
  std::size_t count(std::size_t k) const;

 private:
  struct Member {
    std::uint32_t index;  // in the ParticleSet
    std::uint32_t body;   // walls.obstacles[body]
    Vec2 rest;            // x_b0, m
    Vec2 arm;             // r0 = x_b0 - x_c0, m
  };
  std::vector<Member> members_;
  std::vector<WallMotion> motions_;
};

}  // namespace mps_lab
