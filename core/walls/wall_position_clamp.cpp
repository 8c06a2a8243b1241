// Wall position clamp (MPS spec §6.3): after the explicit position update and after the
// pressure correction, a fluid particle past a wall surface (offset l0 inside the wall's
// first layer; spec: 0.5 l0) is put back on it and its wall-normal velocity is reversed
// and damped, v_n <- -e v_n (e = restitution, spec 0.2). Walls are the tank sides the scene
// lists; an open side (the top in the dam break) is not clamped. An obstacle (walls.obstacles)
// is clamped the same way: a particle inside its box grown by the offset leaves it through
// the nearest face; a polygon obstacle likewise through its nearest edge. A moving obstacle
// (walls.obstacles[k].motion) is kept out of by its wall particles, which move with it, and is
// not clamped; with a boundary model of wall samples (no wall particles) it is clamped where its
// pose (ParticleSet::obstacle_pose) puts it, in the frame moving with it: the particle's normal
// velocity relative to the wall's, (v - u_w) . n, is reversed and damped.
#include <algorithm>
#include <vector>

#include "core/io/scene.hpp"
#include "core/walls/obstacle_membership.hpp"
#include "core/walls/wall_polygon.hpp"
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {
namespace {

class WallPositionClamp final : public WallTreatment {
 public:
  explicit WallPositionClamp(const WallTreatmentSetup& setup)
      : restitution_(setup.parameters.number("restitution")), walls_(setup.scene.walls) {
    const double offset = setup.parameters.number("offset") * setup.scene.particle_spacing;
    polygon_clearance_ = offset - 0.5 * setup.scene.particle_spacing;
    low_ = setup.scene.domain.min + Vec2(offset, offset);
    high_ = setup.scene.domain.max - Vec2(offset, offset);
    for (std::size_t k = 0; k < setup.scene.walls.obstacles.size(); ++k) {
      // A moving obstacle (walls.obstacles[k].motion or .body) is kept out of by its moving
      // wall particles, not clamped at its initial box or polygon; with wall samples, where its pose puts it.
      if (setup.scene.walls.moving(k)) {
        MovingObstacle moving{k, {}, {}, {}, obstacle_rest_centroid(setup.scene, k)};
        const Box& box = setup.scene.walls.obstacles[k];
        if (setup.scene.walls.is_polygon(k)) {
          moving.polygon = setup.scene.walls.polygons[k];
        } else {
          moving.box = {box.min - Vec2(offset, offset), box.max + Vec2(offset, offset)};
          moving.clipped = clipped_at_walled_sides(moving.box);
        }
        moving_.push_back(moving);
        continue;
      }
      if (setup.scene.walls.is_polygon(k)) {
        polygons_.push_back(setup.scene.walls.polygons[k]);
        continue;
      }
      const Box& box = setup.scene.walls.obstacles[k];
      obstacles_.push_back({box.min - Vec2(offset, offset), box.max + Vec2(offset, offset)});
    }
  }

  void after_explicit_position(WallContext& context) override { clamp(context.particles); }
  void after_correction(WallContext& context) override { clamp(context.particles); }

 private:
  // A moving obstacle where the scene puts it: its box grown by the offset, or its polygon.
  struct MovingObstacle {
    std::size_t index;   // walls.obstacles[index]
    Box box;             // m; unused for a polygon
    Box clipped;         // box cut at the clamp lines of the walled sides, m (once moved)
    Polygon polygon;     // m; empty for a box
    Vec2 rest_centroid;  // x_c0, m (core/base/rigid_pose.hpp)
  };

  // A moving box once it has left its scene position: cut at the walled sides' clamp lines, as
  // WallGeometry::move_obstacles cuts its surface (the tank keeps the wall particles both hold:
  // a gate on the bed has its foot at the bed).
  Box clipped_at_walled_sides(Box box) const {
    if (walls_.left) box.min.x() = std::max(box.min.x(), low_.x());
    if (walls_.bottom) box.min.y() = std::max(box.min.y(), low_.y());
    if (walls_.right) box.max.x() = std::min(box.max.x(), high_.x());
    if (walls_.top) box.max.y() = std::min(box.max.y(), high_.y());
    return box;
  }

  void clamp(ParticleSet& particles) const {
    const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      if (particles.type[i] != ParticleType::Fluid) continue;
      Vec2& x = particles.position[i];
      Vec2& v = particles.velocity[i];
      if (walls_.left && x.x() < low_.x()) {
        x.x() = low_.x();
        if (v.x() < 0.0) v.x() *= -restitution_;
      }
      if (walls_.right && x.x() > high_.x()) {
        x.x() = high_.x();
        if (v.x() > 0.0) v.x() *= -restitution_;
      }
      if (walls_.bottom && x.y() < low_.y()) {
        x.y() = low_.y();
        if (v.y() < 0.0) v.y() *= -restitution_;
      }
      if (walls_.top && x.y() > high_.y()) {
        x.y() = high_.y();
        if (v.y() > 0.0) v.y() *= -restitution_;
      }
      for (const Box& box : obstacles_) clamp_out_of(box, x, v);
      for (const Polygon& polygon : polygons_) clamp_out_of(polygon, x, v);
    }
    // Moving obstacles without wall particles (a boundary model of wall samples): at their poses.
    if (!moving_.empty() && !particles.obstacle_pose.empty() && particles.count(ParticleType::Wall) == 0) {
      clamp_moving(particles, placed_moving_obstacles(particles.obstacle_pose));
    }
  }

  // The moving obstacles at their poses: a translated box stays a box (min + d, max + d), a polygon
  // or a turned box is moved vertex by vertex, x = x_c0 + d + R(theta) (x0 - x_c0).
  std::vector<MovingObstacle> placed_moving_obstacles(const std::vector<RigidPose>& poses) const {
    std::vector<MovingObstacle> placed = moving_;
    for (MovingObstacle& obstacle : placed) {
      const RigidPose& pose = poses[obstacle.index];
      const bool box = obstacle.polygon.empty();
      // At its scene position the fixed obstacle's box (to the bit), once moved the cut one.
      if (box && !(pose.displacement.isZero(0.0) && pose.angle == 0.0)) obstacle.box = obstacle.clipped;
      if (box && pose.angle == 0.0) {
        obstacle.box = {obstacle.box.min + pose.displacement, obstacle.box.max + pose.displacement};
        continue;
      }
      obstacle.polygon = posed_polygon(box ? box_polygon(obstacle.box.min, obstacle.box.max) : obstacle.polygon,
                                       obstacle.rest_centroid, pose);
    }
    return placed;
  }

  // Each fluid particle out of the moving obstacles, in the frame of the obstacle's motion.
  void clamp_moving(ParticleSet& particles, const std::vector<MovingObstacle>& placed) const {
    const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      if (particles.type[i] != ParticleType::Fluid) continue;
      Vec2& x = particles.position[i];
      for (const MovingObstacle& obstacle : placed) {
        const RigidPose& pose = particles.obstacle_pose[obstacle.index];
        const Vec2 wall_velocity = rigid_point_velocity(pose, x - (obstacle.rest_centroid + pose.displacement));
        Vec2 relative = particles.velocity[i] - wall_velocity;
        const bool moved = obstacle.polygon.empty() ? clamp_out_of(obstacle.box, x, relative)
                                                    : clamp_out_of(obstacle.polygon, x, relative);
        if (moved) particles.velocity[i] = relative + wall_velocity;
      }
    }
  }

  // A polygon is its wall surface (core/walls/wall_polygon.hpp), l0/2 outside its first layer:
  // a particle inside it, or outside but nearer than `offset - l0/2` to it, is put at that
  // clearance from its nearest edge along the edge's outward normal, v_n <- -e v_n.
  // Whether it moved x.
  bool clamp_out_of(const Polygon& polygon, Vec2& x, Vec2& v) const {
    std::size_t edge = 0;
    const double distance = distance_to_polygon(x, polygon, &edge);
    const double outside = inside_polygon(x, polygon) ? -distance : distance;  // signed, m
    if (outside >= polygon_clearance_) return false;
    const Vec2 normal = outward_normal(polygon, edge);
    x += (polygon_clearance_ - outside) * normal;
    const double normal_speed = v.dot(normal);
    if (normal_speed < 0.0) v -= (1.0 + restitution_) * normal_speed * normal;
    return true;
  }

  // Whether it moved x.
  bool clamp_out_of(const Box& box, Vec2& x, Vec2& v) const {
    if (!(x.x() > box.min.x() && x.x() < box.max.x() && x.y() > box.min.y() && x.y() < box.max.y())) return false;
    // Depth past each face; leave through the shallowest.
    const double left = x.x() - box.min.x(), right = box.max.x() - x.x();
    const double below = x.y() - box.min.y(), above = box.max.y() - x.y();
    const double least = std::min({left, right, below, above});
    if (least == above) {
      x.y() = box.max.y();
      if (v.y() < 0.0) v.y() *= -restitution_;
    } else if (least == left) {
      x.x() = box.min.x();
      if (v.x() > 0.0) v.x() *= -restitution_;
    } else if (least == right) {
      x.x() = box.max.x();
      if (v.x() < 0.0) v.x() *= -restitution_;
    } else {
      x.y() = box.min.y();
      if (v.y() > 0.0) v.y() *= -restitution_;
    }
    return true;
  }

  double restitution_;
  TankWalls walls_;
  std::vector<Box> obstacles_;          // obstacle boxes grown by the offset, m
  std::vector<Polygon> polygons_;       // polygon obstacles (their surfaces), m
  std::vector<MovingObstacle> moving_;  // moving obstacles where the scene puts them
  double polygon_clearance_ = 0.0;      // offset - l0/2, m: where the clamp puts particles off a polygon
  Vec2 low_;                            // m
  Vec2 high_;                           // m
};

}  // namespace
}  // namespace mps_lab

void mps_lab_register_wall_treatment_wall_position_clamp(mps_lab::WallTreatmentRegistry& registry) {
  using namespace mps_lab;
  WallTreatmentInfo info{
      "wall_position_clamp",
      "puts fluid particles past a wall surface back on it, normal velocity reversed and damped "
      "(MPS spec 6.3)",
      {number_parameter("offset", 0.5, "l0", "wall surface distance from the first wall layer")
           .at_least(0.0)
           .at_most(2.0),
       number_parameter("restitution", 0.2, "", "WALL_RESTITUTION: v_n <- -e v_n").at_least(0.0).at_most(1.0)},
      10,
      [](const WallTreatmentSetup& setup) { return std::make_unique<WallPositionClamp>(setup); }};
  info.hooks = {WallHook::AfterExplicitPosition, WallHook::AfterCorrection};
  // A method whose only position update ends the step (advection, then after_correction) has no
  // explicit position update to clamp after.
  info.optional_hooks = {WallHook::AfterExplicitPosition};
  registry.add(std::move(info));
}
