// The wall particles of moving obstacles (core/walls/moving_walls.hpp).
#include "core/walls/moving_walls.hpp"

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

}  // namespace

MovingWalls::MovingWalls(const Scene& scene, const ParticleSet& initial) : motions_(scene.walls.motions) {
  if (!scene.walls.any_moving()) return;
  const double eps = 1e-6 * scene.particle_spacing;
  for (std::size_t i = 0; i < initial.size(); ++i) {
    if (initial.type[i] != ParticleType::Wall) continue;
    const Vec2& x = initial.position[i];
    if (tank_wall_point(x, scene, eps)) continue;
    for (std::size_t k = 0; k < scene.walls.obstacles.size(); ++k) {
      if (!in_closed_box(x, scene.walls.obstacles[k], eps)) continue;
      // The first box that holds the point owns it; it moves only if that box moves.
      if (motions_[k].moves()) {
        members_.push_back({static_cast<std::uint32_t>(i), static_cast<std::uint32_t>(k), x});
      }
      break;
    }
  }
}

void MovingWalls::permute(const ParticleOrder& order) {
  for (Member& m : members_) m.index = order.new_index[m.index];
}

void MovingWalls::apply(ParticleSet& particles, double t) const {
  if (members_.empty()) return;
  particles.wall_velocity.resize(particles.size(), Vec2::Zero());
  particles.wall_acceleration.resize(particles.size(), Vec2::Zero());
  // One evaluation of each law per call, then x_b = x_b(0) + d(t).
  std::vector<Vec2> displacement(motions_.size()), velocity(motions_.size()), acceleration(motions_.size());
  for (std::size_t k = 0; k < motions_.size(); ++k) {
    displacement[k] = motions_[k].displacement(t);
    velocity[k] = motions_[k].velocity_at(t);
    acceleration[k] = motions_[k].acceleration_at(t);
  }
  for (const Member& m : members_) {
    particles.position[m.index] = m.rest + displacement[m.body];
    particles.velocity[m.index] = velocity[m.body];
    particles.wall_velocity[m.index] = velocity[m.body];
    particles.wall_acceleration[m.index] = acceleration[m.body];
  }
}

std::size_t MovingWalls::count(std::size_t k) const {
  std::size_t n = 0;
  for (const Member& m : members_) n += m.body == k ? 1 : 0;
  return n;
}

}  // namespace mps_lab
