// The wall's pressure over the obstacles' wetted surface (core/walls/surface_pressure_loads.hpp).
#include "core/walls/surface_pressure_loads.hpp"

#include <algorithm>
#include <cmath>

#include "core/walls/wall_pressure_extrapolation.hpp"

namespace mps_lab {

namespace {

constexpr double kPointSpacing = 0.25;  // l0: the largest distance between two surface points

}  // namespace

SurfacePressureLoads::SurfacePressureLoads(const Scene& scene)
    : geometry_(scene, MovingObstacles::Included),
      kernel_(wall_pressure_kernel(scene.particle_spacing)),
      spacing_(scene.particle_spacing),
      density_(scene.physics.density),
      gravity_(scene.physics.gravity) {}

// Points at the centres of equal parts of every obstacle segment, none where the face stands
// against another solid.
void SurfacePressureLoads::place_points() {
  points_.clear();
  const auto& segments = geometry_.segments();
  for (std::size_t s = 0; s < segments.size(); ++s) {
    const WallSegment& segment = segments[s];
    if (segment.body < 0) continue;
    const Vec2 along = segment.b - segment.a;
    const double length = along.norm();
    const int parts = std::max(1, static_cast<int>(std::ceil(length / (kPointSpacing * spacing_) - 1e-9)));
    for (int k = 0; k < parts; ++k) {
      const Vec2 x = segment.a + along * ((k + 0.5) / parts);
      if (geometry_.inside_solid(x + spacing_ * segment.normal)) continue;  // against another solid
      points_.push_back({x, segment.normal, length / parts, 0.0, static_cast<std::size_t>(segment.body), s});
    }
  }
  std::vector<Vec2> positions;
  positions.reserve(points_.size());
  for (const Point& point : points_) positions.push_back(point.position);
  grid_.build(std::move(positions), kernel_.support());
}

// Adami et al. (2012) eq. 27 at every point from the fluid in front of its face.
void SurfacePressureLoads::read_pressures(const ParticleSet& particles) {
  if (points_.empty()) return;
  std::vector<ExtrapolatedPressure> sums;
  sum_extrapolated_pressures(
      particles, grid_, kernel_,
      [&](std::uint32_t e, const Vec2& r_wf) { return r_wf.dot(points_[e].normal) < 0.0; },  // not behind the face
      sums);
  const auto& segments = geometry_.segments();
  for (std::size_t e = 0; e < points_.size(); ++e) {
    const Vec2 body_force = gravity_ - geometry_.wall_acceleration(segments[points_[e].segment], points_[e].position);
    points_[e].pressure = std::max(0.0, sums[e].value(density_, body_force));
  }
}

void SurfacePressureLoads::add(const ParticleSet& particles, ObstacleLoads& loads) {
  if (geometry_.has_moving_obstacles() && !particles.obstacle_pose.empty()) {
    geometry_.move_obstacles(particles.obstacle_pose);
    points_.clear();
  }
  if (points_.empty()) place_points();
  read_pressures(particles);
  for (const Point& point : points_) {
    const Vec2 force = -point.pressure * point.length * point.normal;  // N/m
    const Vec2 arm = point.position - loads.reference[point.obstacle];
    loads.force[point.obstacle] += force;
    loads.torque[point.obstacle] += arm.x() * force.y() - arm.y() * force.x();
  }
}

}  // namespace mps_lab
