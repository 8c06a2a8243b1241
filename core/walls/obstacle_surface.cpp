// The surface elements of obstacles' wall particles (core/walls/obstacle_surface.hpp).
#include "core/walls/obstacle_surface.hpp"

#include <algorithm>
#include <cmath>

#include "core/walls/obstacle_membership.hpp"
#include "core/walls/wall_polygon.hpp"

namespace mps_lab {

namespace {

// Where a surface particle's foot lies on an edge: the distance along the edge from its start, m.
struct EdgeFoot {
  double along;
  std::uint32_t id;
};

// The feet of the particle at x on the edges nearest to it (two at a mitred corner: equally near
// within 1e-3 l0), each clamped to its edge.
void add_feet(const Polygon& polygon, const Vec2& x, std::uint32_t id, double l0,
              std::vector<std::vector<EdgeFoot>>& feet) {
  const double d_min = distance_to_polygon(x, polygon);
  for (std::size_t e = 0; e < polygon.size(); ++e) {
    const Vec2 a = polygon[e], b = polygon[(e + 1) % polygon.size()];
    const double length = (b - a).norm();
    const Vec2 tangent = (b - a) / length;
    const double along = std::clamp((x - a).dot(tangent), 0.0, length);
    if ((a + along * tangent - x).norm() <= d_min + 1e-3 * l0) feet[e].push_back({along, id});
  }
}

// Whether the face of obstacle k at the surface particle x (outward normal n) stands against
// another solid: the lattice point l0 out along n is a tank wall point or held by another obstacle.
bool face_against_solid(const Scene& scene, std::size_t k, const Vec2& x, const Vec2& n) {
  const double l0 = scene.particle_spacing, eps = 1e-6 * l0;
  const Vec2 outside = x + l0 * n;
  if (on_tank_wall(outside, scene, eps)) return true;
  for (std::size_t other = 0; other < scene.walls.obstacles.size(); ++other) {
    if (other != k && obstacle_holds(scene, other, outside, eps)) return true;
  }
  return false;
}

// The shares of edge e of obstacle k's surface polygon: each foot the part of the edge nearer to
// it than to the neighbouring feet, the first and last reaching the edge's ends.
void assign_edge_shares(const Scene& scene, std::size_t k, const Polygon& polygon, std::size_t e,
                        std::vector<EdgeFoot>& feet, const ParticleSet& initial, ObstacleSurface& surface) {
  std::sort(feet.begin(), feet.end(), [](const EdgeFoot& a, const EdgeFoot& b) { return a.along < b.along; });
  const double length = (polygon[(e + 1) % polygon.size()] - polygon[e]).norm();
  const Vec2 normal = outward_normal(polygon, e);
  for (std::size_t m = 0; m < feet.size(); ++m) {
    const double from = m == 0 ? 0.0 : 0.5 * (feet[m - 1].along + feet[m].along);
    const double to = m + 1 == feet.size() ? length : 0.5 * (feet[m].along + feet[m + 1].along);
    if (face_against_solid(scene, k, initial.position[feet[m].id], normal)) continue;
    SurfaceElement& element = surface.element_of_id[feet[m].id];
    if (element.count == 2) continue;  // a third equally near edge: only at degenerate polygons
    element.obstacle = static_cast<std::int32_t>(k);
    element.shares[element.count++] = {normal, to - from};
  }
}

}  // namespace

std::vector<Vec2> obstacle_surface_polygon(const Scene& scene, std::size_t k) {
  if (scene.walls.is_polygon(k)) return counter_clockwise(scene.walls.polygons[k]);
  const double h = 0.5 * scene.particle_spacing;
  const Box& box = scene.walls.obstacles[k];
  return {Vec2(box.min.x() - h, box.min.y() - h), Vec2(box.max.x() + h, box.min.y() - h),
          Vec2(box.max.x() + h, box.max.y() + h), Vec2(box.min.x() - h, box.max.y() + h)};
}

ObstacleSurface obstacle_surface(const Scene& scene, const ParticleSet& initial,
                                 const std::vector<std::int32_t>& obstacle_of_id) {
  const std::size_t obstacles = scene.walls.obstacles.size();
  ObstacleSurface surface;
  surface.element_of_id.assign(initial.size(), SurfaceElement{});
  surface.rest_position_of_id = initial.position;
  surface.rest_mean.assign(obstacles, Vec2::Zero());
  surface.members.assign(obstacles, 0);
  for (std::size_t k = 0; k < obstacles; ++k) {
    const Polygon polygon = obstacle_surface_polygon(scene, k);
    std::vector<std::vector<EdgeFoot>> feet(polygon.size());
    for (std::size_t i = 0; i < initial.size(); ++i) {
      if (obstacle_of_id[i] != static_cast<std::int32_t>(k) || initial.wall_layer[i] != 1) continue;
      add_feet(polygon, initial.position[i], static_cast<std::uint32_t>(i), scene.particle_spacing, feet);
    }
    for (std::size_t e = 0; e < polygon.size(); ++e)
      assign_edge_shares(scene, k, polygon, e, feet[e], initial, surface);
  }
  for (std::size_t i = 0; i < initial.size(); ++i) {
    const SurfaceElement& element = surface.element_of_id[i];
    if (element.count == 0) continue;
    surface.rest_mean[element.obstacle] += initial.position[i];
    ++surface.members[element.obstacle];
  }
  for (std::size_t k = 0; k < obstacles; ++k) {
    if (surface.members[k] > 0) surface.rest_mean[k] /= static_cast<double>(surface.members[k]);
  }
  return surface;
}

std::vector<Vec2> obstacle_rotations(const Scene& scene, const ObstacleSurface& surface, const ParticleSet& particles) {
  const std::size_t obstacles = surface.members.size();
  std::vector<Vec2> rotation(obstacles, Vec2(1.0, 0.0)), mean(obstacles, Vec2::Zero());
  std::vector<double> dot(obstacles, 0.0), cross(obstacles, 0.0);
  const auto moving_element = [&](std::size_t j) -> const SurfaceElement* {
    const SurfaceElement& element = surface.element_of_id[particles.id[j]];
    return element.count > 0 && scene.walls.moving(element.obstacle) ? &element : nullptr;
  };
  for (std::size_t j = 0; j < particles.size(); ++j) {
    if (const SurfaceElement* element = moving_element(j)) mean[element->obstacle] += particles.position[j];
  }
  for (std::size_t k = 0; k < obstacles; ++k) {
    if (surface.members[k] > 0) mean[k] /= static_cast<double>(surface.members[k]);
  }
  for (std::size_t j = 0; j < particles.size(); ++j) {
    const SurfaceElement* element = moving_element(j);
    if (element == nullptr) continue;
    const std::size_t k = element->obstacle;
    const Vec2 r0 = surface.rest_position_of_id[particles.id[j]] - surface.rest_mean[k];
    const Vec2 r = particles.position[j] - mean[k];
    dot[k] += r0.dot(r);
    cross[k] += r0.x() * r.y() - r0.y() * r.x();
  }
  for (std::size_t k = 0; k < obstacles; ++k) {
    const double norm = std::hypot(dot[k], cross[k]);
    if (norm > 0.0) rotation[k] = Vec2(dot[k] / norm, cross[k] / norm);
  }
  return rotation;
}

}  // namespace mps_lab
