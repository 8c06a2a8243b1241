// Wall position clamp (MPS spec §6.3): after the explicit position update and after the
// pressure correction, a fluid particle past a wall surface (offset l0 inside the wall's
// first layer; spec: 0.5 l0) is put back on it and its wall-normal velocity is reversed
// and damped, v_n <- -e v_n (e = restitution, spec 0.2). Walls are the tank sides the scene
// lists; an open side (the top in the dam break) is not clamped. An obstacle (walls.obstacles)
// is clamped the same way: a particle inside its box grown by the offset leaves it through
// the nearest face; a polygon obstacle likewise through its nearest edge. A moving obstacle is not clamped (its wall
// particles move with it).
#include <algorithm>
#include <vector>

#include "core/io/scene.hpp"
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
      // wall particles, not clamped at its initial box or polygon.
      if (setup.scene.walls.moving(k)) continue;
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
  }

  // A polygon is its wall surface (core/walls/wall_polygon.hpp), l0/2 outside its first layer:
  // a particle inside it, or outside but nearer than `offset - l0/2` to it, is put at that
  // clearance from its nearest edge along the edge's outward normal, v_n <- -e v_n.
  void clamp_out_of(const Polygon& polygon, Vec2& x, Vec2& v) const {
    std::size_t edge = 0;
    const double distance = distance_to_polygon(x, polygon, &edge);
    const double outside = inside_polygon(x, polygon) ? -distance : distance;  // signed, m
    if (outside >= polygon_clearance_) return;
    const Vec2 normal = outward_normal(polygon, edge);
    x += (polygon_clearance_ - outside) * normal;
    const double normal_speed = v.dot(normal);
    if (normal_speed < 0.0) v -= (1.0 + restitution_) * normal_speed * normal;
  }

  void clamp_out_of(const Box& box, Vec2& x, Vec2& v) const {
    if (!(x.x() > box.min.x() && x.x() < box.max.x() && x.y() > box.min.y() && x.y() < box.max.y())) return;
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
  }

  double restitution_;
  TankWalls walls_;
  std::vector<Box> obstacles_;      // obstacle boxes grown by the offset, m
  std::vector<Polygon> polygons_;   // polygon obstacles (their surfaces), m
  double polygon_clearance_ = 0.0;  // offset - l0/2, m: where the clamp puts particles off a polygon
  Vec2 low_;                        // m
  Vec2 high_;                       // m
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
