#pragma once
// The pose of a moving obstacle: a rigid motion from where the scene puts it (a motion law's,
// core/walls/wall_motion.hpp, or a rigid body's, core/bodies/rigid_bodies.hpp). The wall
// particles (core/walls/moving_walls.hpp) and the wall samples (core/walls/wall_geometry.hpp)
// of the obstacle move with it.
#include <cmath>

#include "core/base/types.hpp"

namespace mps_lab {

// Where a moving obstacle is, relative to its scene position: the displacement d of its
// reference point x_c0 (its surface's area centroid) and an angle theta.
struct RigidPose {
  Vec2 displacement = Vec2::Zero();   // d = x_c - x_c0, m
  double angle = 0.0;                 // theta, rad, counter-clockwise
  Vec2 velocity = Vec2::Zero();       // u_c, m/s
  double angular_velocity = 0.0;      // omega, rad/s
  Vec2 acceleration = Vec2::Zero();   // a_c, m/s^2
  double angular_acceleration = 0.0;  // alpha, rad/s^2
};

// R(theta) r0: an arm from the reference point, rotated by the pose.
inline Vec2 rotated_arm(const RigidPose& pose, const Vec2& arm) {
  const double c = std::cos(pose.angle), s = std::sin(pose.angle);
  return {c * arm.x() - s * arm.y(), s * arm.x() + c * arm.y()};
}

// The velocity of the body's point at arm r = x - x_c (already rotated), m/s: u_c + omega x r.
inline Vec2 rigid_point_velocity(const RigidPose& pose, const Vec2& r) {
  return pose.velocity + pose.angular_velocity * Vec2(-r.y(), r.x());
}

// Its acceleration, m/s^2: a_c + alpha x r - omega^2 r.
inline Vec2 rigid_point_acceleration(const RigidPose& pose, const Vec2& r) {
  return pose.acceleration + pose.angular_acceleration * Vec2(-r.y(), r.x()) -
         pose.angular_velocity * pose.angular_velocity * r;
}

}  // namespace mps_lab
