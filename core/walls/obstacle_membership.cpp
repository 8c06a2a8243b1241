// Obstacle membership of wall particles and the loads on obstacles (core/walls/obstacle_membership.hpp).
#include "core/walls/obstacle_membership.hpp"

#include "core/walls/wall_polygon.hpp"
#include "core/walls/wall_sample_reactions.hpp"

namespace mps_lab {

bool on_tank_wall(const Vec2& x, const Scene& scene, double eps) {
  const TankWalls& w = scene.walls;
  const Box& d = scene.domain;
  return (w.left && x.x() <= d.min.x() + eps) || (w.right && x.x() >= d.max.x() - eps) ||
         (w.bottom && x.y() <= d.min.y() + eps) || (w.top && x.y() >= d.max.y() - eps);
}

bool obstacle_holds(const Scene& scene, std::size_t k, const Vec2& x, double eps) {
  if (scene.walls.is_polygon(k)) {
    const Polygon& polygon = scene.walls.polygons[k];
    return inside_polygon(x, polygon) || distance_to_polygon(x, polygon) <= eps;
  }
  const Box& box = scene.walls.obstacles[k];
  return x.x() >= box.min.x() - eps && x.x() <= box.max.x() + eps && x.y() >= box.min.y() - eps &&
         x.y() <= box.max.y() + eps;
}

std::vector<std::int32_t> obstacle_of_wall_particles(const Scene& scene, const ParticleSet& initial) {
  std::vector<std::int32_t> owner(initial.size(), kNoObstacle);
  const double eps = 1e-6 * scene.particle_spacing;
  for (std::size_t i = 0; i < initial.size(); ++i) {
    if (initial.type[i] != ParticleType::Wall || on_tank_wall(initial.position[i], scene, eps)) continue;
    for (std::size_t k = 0; k < scene.walls.obstacles.size(); ++k) {
      if (!obstacle_holds(scene, k, initial.position[i], eps)) continue;
      owner[i] = static_cast<std::int32_t>(k);
      break;
    }
  }
  return owner;
}

Vec2 obstacle_rest_centroid(const Scene& scene, std::size_t k) {
  if (scene.walls.is_circle(k)) return scene.walls.circles[k].centre;
  if (scene.walls.is_polygon(k)) {
    // Area centroid of a lamina, (1 / 6A) sum over edges (x_a + x_b) (x_a x x_b), taken about
    // the first vertex to keep rounding small (core/bodies/mass_properties.hpp).
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

void start_obstacle_loads(const Scene& scene, double time, ObstacleLoads& loads) {
  const std::size_t obstacles = scene.walls.obstacles.size();
  loads.reset(obstacles);
  for (std::size_t k = 0; k < obstacles; ++k) {
    const bool moves = k < scene.walls.motions.size() && scene.walls.motions[k].moves();
    loads.reference[k] =
        obstacle_rest_centroid(scene, k) + (moves ? scene.walls.motions[k].displacement(time) : Vec2::Zero());
  }
}

void sum_obstacle_loads(const Scene& scene, const ParticleSet& particles,
                        const std::vector<std::int32_t>& obstacle_of_id, const std::vector<Vec2>& reaction, double time,
                        ObstacleLoads& loads) {
  start_obstacle_loads(scene, time, loads);
  for (std::size_t j = 0; j < particles.size(); ++j) {
    const std::int32_t k = obstacle_of_id[particles.id[j]];
    if (k == kNoObstacle) continue;
    const Vec2& f = reaction[j];
    const Vec2 arm = particles.position[j] - loads.reference[k];
    loads.force[k] += f;
    loads.torque[k] += arm.x() * f.y() - arm.y() * f.x();
  }
}

void add_wall_sample_loads(const WallSampleLoads& sample_loads, ObstacleLoads& loads) {
  for (std::size_t k = 0; k < loads.size() && k < sample_loads.force.size(); ++k) {
    const Vec2& f = sample_loads.force[k];
    const Vec2& c = loads.reference[k];
    loads.force[k] += f;
    loads.torque[k] += sample_loads.moment[k] - (c.x() * f.y() - c.y() * f.x());  // T_c = T_0 - c x F
  }
}

}  // namespace mps_lab
