// The wall particles of moving obstacles (core/walls/moving_walls.hpp).
#include "core/walls/moving_walls.hpp"

#include <cmath>

#include "core/walls/wall_polygon.hpp"

namespace mps_lab {

namespace {

// Whether x is a point of the tank's walls: on or beyond a walled side of the domain.
bool tank_wall_point(const Vec2& x, const Scene& scene, double eps) {
  const TankWalls& w = scene.walls;
  const Box& d = scene.domain;
  return (w.left && x.x() <= d.min.x() + eps) || (w.right && x.x() >= d.max.x() - eps) ||
         (w.bottom && x.y() <= d.min.y() + eps) || (w.top && x.y() >= d.max.y() - eps);
}

bool in_closed_box(const Vec2& x, const Box& box, double eps) {
  return x.x() >= box.min.x() - eps && x.x() <= box.max.x() + eps && x.y() >= box.min.y() - eps &&
         x.y() <= box.max.y() + eps;
}

// Whether the scene's obstacle k holds the wall point x: inside or on its polygon, or its box.
bool obstacle_holds(const Vec2& x, const Scene& scene, std::size_t k, double eps) {
  if (scene.walls.is_polygon(k)) {
    const Polygon& polygon = scene.walls.polygons[k];
    return inside_polygon(x, polygon) || distance_to_polygon(x, polygon) <= eps;
  }
  return in_closed_box(x, scene.walls.obstacles[k], eps);
}

}  // namespace

RigidPose law_pose(const WallMotion& motion, double t) {
  RigidPose pose;
  pose.displacement = motion.displacement(t);
  pose.velocity = motion.velocity_at(t);
  pose.acceleration = motion.acceleration_at(t);
  return pose;
}

Vec2 obstacle_reference(const Scene& scene, std::size_t k) {
  if (scene.walls.is_circle(k)) return scene.walls.circles[k].centre;
  if (scene.walls.is_polygon(k)) {
    // Area centroid, (1 / 6A) sum (x_k + x_{k+1}) c_k (core/bodies/mass_properties.hpp).
    const Polygon& polygon = scene.walls.polygons[k];
    double twice_area = 0.0;
    Vec2 first = Vec2::Zero();
    for (std::size_t i = 0; i < polygon.size(); ++i) {
      const Vec2 a = polygon[i] - polygon[0], b = polygon[(i + 1) % polygon.size()] - polygon[0];
      const double c = a.x() * b.y() - b.x() * a.y();
      twice_area += c;
      first += (a + b) * c;
    }
    return polygon[0] + first / (3.0 * twice_area);
  }
  const Box& box = scene.walls.obstacles[k];
  return 0.5 * (box.min + box.max);
}

MovingWalls::MovingWalls(const Scene& scene, const ParticleSet& initial) : motions_(scene.walls.motions) {
  if (!scene.walls.any_moving()) return;
  const double eps = 1e-6 * scene.particle_spacing;
  for (std::size_t i = 0; i < initial.size(); ++i) {
    if (initial.type[i] != ParticleType::Wall) continue;
    const Vec2& x = initial.position[i];
    if (tank_wall_point(x, scene, eps)) continue;
    for (std::size_t k = 0; k < scene.walls.obstacles.size(); ++k) {
      if (!obstacle_holds(x, scene, k, eps)) continue;
      // The first obstacle that holds the point owns it; it moves only if that obstacle moves.
      if (scene.walls.moving(k)) {
        members_.push_back(
            {static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(k), x, x - obstacle_reference(scene, k)});
      }
      break;
    }
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
