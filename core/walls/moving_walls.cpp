// The wall particles of moving obstacles (core/walls/moving_walls.hpp).
#include "core/walls/moving_walls.hpp"

#include <cmath>

#include "core/walls/obstacle_membership.hpp"

namespace mps_lab {

RigidPose law_pose(const WallMotion& motion, double t) {
  RigidPose pose;
  pose.displacement = motion.displacement(t);
  pose.velocity = motion.velocity_at(t);
  pose.acceleration = motion.acceleration_at(t);
  return pose;
}

MovingWalls::MovingWalls(const Scene& scene, const ParticleSet& initial) : motions_(scene.walls.motions) {
  if (!scene.walls.any_moving()) return;
  // The obstacle that owns each wall particle (core/walls/obstacle_membership.hpp: the first
  // that holds it, tank walls excepted); it moves only if that obstacle moves.
  const std::vector<std::int32_t> owner = obstacle_of_wall_particles(scene, initial);
  for (std::size_t i = 0; i < initial.size(); ++i) {
    if (owner[i] == kNoObstacle) continue;
    const auto k = static_cast<std::size_t>(owner[i]);
    if (!scene.walls.moving(k)) continue;
    const Vec2& x = initial.position[i];
    members_.push_back(
        {static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(k), x, x - obstacle_rest_centroid(scene, k)});
  }
}

void MovingWalls::permute(const ParticleOrder& order) {
  for (Member& m : members_) m.index = order.new_index[m.index];
}

std::vector<RigidPose> MovingWalls::law_poses(double t) const {
  std::vector<RigidPose> poses(motions_.size());
  for (std::size_t k = 0; k < motions_.size(); ++k) poses[k] = law_pose(motions_[k], t);
  return poses;
}

void MovingWalls::apply(ParticleSet& particles, const std::vector<RigidPose>& poses) const {
  if (members_.empty()) return;
  particles.wall_velocity.resize(particles.size(), Vec2::Zero());
  particles.wall_acceleration.resize(particles.size(), Vec2::Zero());
  std::vector<double> cosine(poses.size()), sine(poses.size());
  for (std::size_t k = 0; k < poses.size(); ++k) {
    cosine[k] = std::cos(poses[k].angle);
    sine[k] = std::sin(poses[k].angle);
  }
  for (const Member& m : members_) {
    const RigidPose& pose = poses[m.body];
    const Vec2 r(cosine[m.body] * m.arm.x() - sine[m.body] * m.arm.y(),
                 sine[m.body] * m.arm.x() + cosine[m.body] * m.arm.y());  // R(theta) r0
    const Vec2 across(-r.y(), r.x());                                     // e_z x r
    const Vec2 velocity = pose.velocity + pose.angular_velocity * across;
    particles.position[m.index] = m.rest + pose.displacement + (r - m.arm);
    particles.velocity[m.index] = velocity;
    particles.wall_velocity[m.index] = velocity;
    particles.wall_acceleration[m.index] =
        pose.acceleration + pose.angular_acceleration * across - pose.angular_velocity * pose.angular_velocity * r;
  }
}

std::size_t MovingWalls::count(std::size_t k) const {
  std::size_t n = 0;
  for (const Member& m : members_) n += m.body == k ? 1 : 0;
  return n;
}

}  // namespace mps_lab
