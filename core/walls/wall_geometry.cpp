#include "core/walls/wall_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/walls/obstacle_membership.hpp"

namespace mps_lab {

namespace {

bool strictly_inside_box(const Vec2& x, const Box& box) {
  return x.x() > box.min.x() && x.x() < box.max.x() && x.y() > box.min.y() && x.y() < box.max.y();
}

}  // namespace

WallGeometry::WallGeometry(const Scene& scene, MovingObstacles moving)
    : walls_(scene.walls), domain_(scene.domain), half_spacing_(0.5 * scene.particle_spacing) {
  const double h = half_spacing_;
  const double far = std::numeric_limits<double>::infinity();
  interior_.min = Vec2(walls_.left ? domain_.min.x() + h : -far, walls_.bottom ? domain_.min.y() + h : -far);
  interior_.max = Vec2(walls_.right ? domain_.max.x() - h : far, walls_.top ? domain_.max.y() - h : far);
  // A moving obstacle (walls.obstacles[k].motion or .body) is part of the geometry only when
  // asked for (at rest until move_obstacles); else an empty box (nothing is inside it) and no faces.
  const bool include_moving = moving == MovingObstacles::Included && walls_.any_moving();
  const Box nothing{Vec2(far, far), Vec2(-far, -far)};
  for (std::size_t k = 0; k < walls_.obstacles.size(); ++k) {
    const Box& box = walls_.obstacles[k];
    const bool left_out = walls_.moving(k) && !include_moving;  // a motion law or a rigid body
    // A polygon is its own surface (core/walls/wall_polygon.hpp): no box.
    const bool polygon = walls_.is_polygon(k);
    polygons_.push_back(polygon && !left_out ? walls_.polygons[k] : Polygon{});
    obstacles_.push_back(left_out || polygon ? nothing : Box{box.min - Vec2(h, h), box.max + Vec2(h, h)});
    if (include_moving) {
      moving_.push_back(walls_.moving(k));
      rest_centroid_.push_back(obstacle_rest_centroid(scene, k));
    }
  }
  rest_obstacles_ = include_moving ? obstacles_ : std::vector<Box>{};
  // A moving box's surface once it has left its scene position: the part of the grown box behind
  // a tank wall's surface is cut off, as the tank keeps the wall particles both hold (a gate on
  // the bed leaves the bed's row: its foot is the bed's surface, and a gap opens as it rises).
  for (const Box& box : rest_obstacles_) {
    rest_clipped_.push_back(
        box.min.x() > box.max.x() ? box : Box{box.min.cwiseMax(interior_.min), box.max.cwiseMin(interior_.max)});
  }
  rest_polygons_ = include_moving ? polygons_ : std::vector<Polygon>{};
  build_segments();
}

// The wall surfaces from the tank and the obstacles where they are now.
void WallGeometry::build_segments() {
  segments_.clear();
  // Tank sides: along the surface, ending at the neighbouring side's surface, or at the domain
  // edge where that side is open.
  const double x0 = walls_.left ? interior_.min.x() : domain_.min.x();
  const double x1 = walls_.right ? interior_.max.x() : domain_.max.x();
  const double y0 = walls_.bottom ? interior_.min.y() : domain_.min.y();
  const double y1 = walls_.top ? interior_.max.y() : domain_.max.y();
  std::vector<WallSegment> candidates;
  if (walls_.bottom) candidates.push_back({Vec2(x0, y0), Vec2(x1, y0), Vec2(0.0, 1.0), -1});
  if (walls_.top) candidates.push_back({Vec2(x0, y1), Vec2(x1, y1), Vec2(0.0, -1.0), -1});
  if (walls_.left) candidates.push_back({Vec2(x0, y0), Vec2(x0, y1), Vec2(1.0, 0.0), -1});
  if (walls_.right) candidates.push_back({Vec2(x1, y0), Vec2(x1, y1), Vec2(-1.0, 0.0), -1});
  // Obstacle faces, outward normals; a face that lies inside another solid (an obstacle on
  // the bed has its bottom face inside the bottom wall) is not a wall surface.
  for (std::size_t k = 0; k < obstacles_.size(); ++k) {
    const Box& s = obstacles_[k];
    if (s.min.x() > s.max.x()) continue;  // left out, or a polygon
    const int body = static_cast<int>(k);
    candidates.push_back({Vec2(s.min.x(), s.max.y()), Vec2(s.max.x(), s.max.y()), Vec2(0.0, 1.0), body});
    candidates.push_back({Vec2(s.min.x(), s.min.y()), Vec2(s.max.x(), s.min.y()), Vec2(0.0, -1.0), body});
    candidates.push_back({Vec2(s.min.x(), s.min.y()), Vec2(s.min.x(), s.max.y()), Vec2(-1.0, 0.0), body});
    candidates.push_back({Vec2(s.max.x(), s.min.y()), Vec2(s.max.x(), s.max.y()), Vec2(1.0, 0.0), body});
  }
  candidates = split_tank_sides_at_polygons(candidates);
  add_polygon_edges(candidates);
  const double h = half_spacing_;
  for (const WallSegment& segment : candidates) {
    // A probe just in front of the face's middle: on the fluid side of every other solid?
    const Vec2 probe = 0.5 * (segment.a + segment.b) + 1e-6 * h * segment.normal;
    bool buried = false;
    if (segment.body >= 0) {
      buried = !strictly_inside_box(probe, interior_) && depth_inside(probe) > 0.0;
    }
    // (Tank sides stay whole: an obstacle on the bed covers part of the bed, not all of it.)
    for (std::size_t k = 0; k < obstacles_.size() && !buried && segment.body >= 0; ++k) {
      if (static_cast<int>(k) == segment.body) continue;
      if (strictly_inside_box(probe, obstacles_[k]) || inside_polygon_solid(probe, k)) buried = true;
    }
    if (!buried) segments_.push_back(segment);
  }
}

// A box that only translates stays a box (min + d, max + d: at d = 0 the same bits as the box
// at rest); a polygon, or a box turned by an angle, is moved vertex by vertex about x_c0.
void WallGeometry::move_obstacles(const std::vector<RigidPose>& poses) {
  if (!has_moving_obstacles()) return;
  moving_pose_ = poses;
  const double far = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < moving_.size(); ++k) {
    if (!moving_[k]) continue;
    const RigidPose& pose = poses[k];
    // At its scene position the box is the fixed obstacle's (to the bit), once moved the cut one.
    const bool at_rest = pose.displacement.isZero(0.0) && pose.angle == 0.0;
    const Box& rest = at_rest ? rest_obstacles_[k] : rest_clipped_[k];
    const bool box = rest.min.x() <= rest.max.x();
    if (box && pose.angle == 0.0) {
      obstacles_[k] = Box{rest.min + pose.displacement, rest.max + pose.displacement};
      continue;
    }
    polygons_[k] = posed_polygon(box ? box_polygon(rest.min, rest.max) : rest_polygons_[k], rest_centroid_[k], pose);
    obstacles_[k] = Box{Vec2(far, far), Vec2(-far, -far)};
  }
  build_segments();
}

Vec2 WallGeometry::wall_velocity(const WallSegment& segment, const Vec2& x) const {
  if (!moves(segment)) return Vec2::Zero();
  const auto k = static_cast<std::size_t>(segment.body);
  const RigidPose& pose = moving_pose_[k];
  return rigid_point_velocity(pose, x - (rest_centroid_[k] + pose.displacement));
}

Vec2 WallGeometry::wall_acceleration(const WallSegment& segment, const Vec2& x) const {
  if (!moves(segment)) return Vec2::Zero();
  const auto k = static_cast<std::size_t>(segment.body);
  const RigidPose& pose = moving_pose_[k];
  return rigid_point_acceleration(pose, x - (rest_centroid_[k] + pose.displacement));
}

// A tank side under a polygon (a wedge on the bed) is no surface there: the side is cut where
// the polygon's edges cross it and the pieces covered by the polygon are dropped. (A wall of
// samples built behind the covered piece would leave a hole inside the polygon next to it:
// core/walls/distance_function.cpp counts each virtual point by its nearest segment.) Box
// obstacles leave the sides whole, as before polygons existed.
std::optional<double> crossing_parameter(const Vec2& a, const Vec2& along, const Vec2& p, const Vec2& across) {
  const double denominator = along.x() * across.y() - along.y() * across.x();
  if (std::fabs(denominator) < 1e-300) return std::nullopt;  // parallel: no crossing point
  const Vec2 w = p - a;
  const double t = (w.x() * across.y() - w.y() * across.x()) / denominator;  // along a + t along
  const double u = (w.x() * along.y() - w.y() * along.x()) / denominator;    // along p + u across
  if (t > 0.0 && t < 1.0 && u >= 0.0 && u <= 1.0) return t;
  return std::nullopt;
}

std::vector<WallSegment> WallGeometry::split_tank_sides_at_polygons(const std::vector<WallSegment>& sides) const {
  std::vector<WallSegment> pieces;
  for (const WallSegment& side : sides) {
    if (side.body >= 0) {  // an obstacle's face: buried or not below
      pieces.push_back(side);
      continue;
    }
    const Vec2 along = side.b - side.a;
    std::vector<double> cuts = {0.0, 1.0};
    for (const Polygon& polygon : polygons_) {
      for (std::size_t e = 0; e < polygon.size(); ++e) {
        const Vec2 p = polygon[e];
        if (const auto t = crossing_parameter(side.a, along, p, polygon[(e + 1) % polygon.size()] - p))
          cuts.push_back(*t);
      }
    }
    if (cuts.size() == 2) {  // no polygon crosses it: whole, to the bit, unless one covers it all
      const Vec2 probe = 0.5 * (side.a + side.b) + 1e-6 * half_spacing_ * side.normal;
      bool covered = false;
      for (std::size_t k = 0; k < polygons_.size() && !covered && side.body < 0; ++k) {
        covered = inside_polygon_solid(probe, k);
      }
      if (!covered) pieces.push_back(side);
      continue;
    }
    std::sort(cuts.begin(), cuts.end());
    for (std::size_t c = 0; c + 1 < cuts.size(); ++c) {
      if (cuts[c + 1] - cuts[c] < 1e-12) continue;
      const Vec2 middle = side.a + 0.5 * (cuts[c] + cuts[c + 1]) * along + 1e-6 * half_spacing_ * side.normal;
      bool covered = false;
      for (std::size_t k = 0; k < polygons_.size() && !covered; ++k) covered = inside_polygon_solid(middle, k);
      if (!covered) pieces.push_back({side.a + cuts[c] * along, side.a + cuts[c + 1] * along, side.normal, side.body});
    }
  }
  return pieces;
}

bool WallGeometry::inside_polygon_solid(const Vec2& x, std::size_t k) const {
  return !polygons_[k].empty() && depth_inside_polygon(x, polygons_[k]) > 0.0;
}

// The edges of polygon obstacles with their outward normals, each cut to the tank's interior
// (the part of an edge inside a tank side's wall is no surface: a wedge drawn down into the
// bed has its slope start at the bed's surface). Liang-Barsky clipping against interior_.
void WallGeometry::add_polygon_edges(std::vector<WallSegment>& candidates) const {
  for (std::size_t k = 0; k < polygons_.size(); ++k) {
    const Polygon& polygon = polygons_[k];
    for (std::size_t e = 0; e < polygon.size(); ++e) {
      const Vec2 a = polygon[e], along = polygon[(e + 1) % polygon.size()] - a;
      double t0 = 0.0, t1 = 1.0;
      for (int axis = 0; axis < 2; ++axis) {
        for (const double side : {-1.0, 1.0}) {
          const double bound = side < 0.0 ? interior_.min[axis] : interior_.max[axis];
          const double q = side * (bound - a[axis]), p = side * along[axis];  // inside: p t <= q
          if (p == 0.0) {
            if (q < 0.0) t1 = -1.0;
          } else if (p > 0.0) {
            t1 = std::min(t1, q / p);
          } else {
            t0 = std::max(t0, q / p);
          }
        }
      }
      if (t1 - t0 <= 1e-12) continue;
      candidates.push_back({a + t0 * along, a + t1 * along, outward_normal(polygon, e), static_cast<int>(k)});
    }
  }
}

// Beyond the domain across a side that has no wall (e.g. above the open top).
bool WallGeometry::past_open_side(const Vec2& x) const {
  return (!walls_.left && x.x() < domain_.min.x()) || (!walls_.right && x.x() > domain_.max.x()) ||
         (!walls_.bottom && x.y() < domain_.min.y()) || (!walls_.top && x.y() > domain_.max.y());
}

double WallGeometry::tank_depth(const Vec2& x) const {
  double depth = 0.0;
  // Tank: behind a walled side's surface, unless past an open side (above an open top).
  if (past_open_side(x)) return depth;
  // A tank side is a slab `layers` spacings thick (its wall particles): a particle beyond its
  // outer face went over the crest and lies outside the tank, not in the wall.
  const double thickness = walls_.layers * 2.0 * half_spacing_;
  for (const double d :
       {interior_.min.x() - x.x(), x.x() - interior_.max.x(), interior_.min.y() - x.y(), x.y() - interior_.max.y()}) {
    if (d < thickness) depth = std::max(depth, d);
  }
  return depth;
}

std::optional<int> WallGeometry::solid_holding(const Vec2& x) const {
  if (tank_depth(x) > 0.0) return -1;
  for (std::size_t k = 0; k < obstacles_.size(); ++k) {
    if (strictly_inside_box(x, obstacles_[k])) return static_cast<int>(k);
  }
  for (std::size_t k = 0; k < polygons_.size(); ++k) {
    if (inside_polygon_solid(x, k)) return static_cast<int>(k);
  }
  return std::nullopt;
}

double WallGeometry::depth_inside(const Vec2& x) const {
  double depth = tank_depth(x);
  for (const Box& s : obstacles_) {
    if (strictly_inside_box(x, s)) {
      depth = std::max(depth, std::min({x.x() - s.min.x(), s.max.x() - x.x(), x.y() - s.min.y(), s.max.y() - x.y()}));
    }
  }
  for (const Polygon& polygon : polygons_) {
    if (!polygon.empty()) depth = std::max(depth, depth_inside_polygon(x, polygon));
  }
  return depth;
}

bool WallGeometry::behind_walled_side(const Vec2& x) const {
  const bool past_open = past_open_side(x);
  return !past_open && !strictly_inside_box(x, interior_);
}

bool WallGeometry::inside_solid(const Vec2& x) const { return depth_inside(x) > 0.0; }

double WallGeometry::distance_to(const Vec2& x, std::size_t k) const {
  const WallSegment& s = segments_[k];
  const Vec2 along = s.b - s.a;
  const double length2 = along.squaredNorm();
  const double t = length2 > 0.0 ? std::clamp((x - s.a).dot(along) / length2, 0.0, 1.0) : 0.0;
  return (x - (s.a + t * along)).norm();
}

std::size_t WallGeometry::nearest_behind(const Vec2& x) const {
  double best = std::numeric_limits<double>::infinity();
  std::size_t nearest = segments_.size();
  for (std::size_t k = 0; k < segments_.size(); ++k) {
    if ((segments_[k].a - x).dot(segments_[k].normal) <= 0.0) continue;  // in front of its line
    const double d = distance_to(x, k);
    if (d < best) {
      best = d;
      nearest = k;
    }
  }
  return nearest;
}

double WallGeometry::distance(const Vec2& x, std::size_t* nearest) const {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < segments_.size(); ++k) {
    const double d = distance_to(x, k);
    if (d < best) {
      best = d;
      if (nearest != nullptr) *nearest = k;
    }
  }
  return best;
}

std::size_t reflect_crossed_particles(ParticleSet& particles, const WallGeometry& geometry) {
  std::size_t moved = 0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] != ParticleType::Fluid) continue;
    Vec2& x = particles.position[i];
    if (!(geometry.depth_inside(x) > 0.0)) continue;
    std::size_t nearest = 0;
    geometry.distance(x, &nearest);
    const WallSegment& wall = geometry.segments()[nearest];
    const double behind = (wall.a - x).dot(wall.normal);  // > 0: behind this surface
    if (behind > 0.0) x += 2.0 * behind * wall.normal;
    Vec2& u = particles.velocity[i];
    const double normal_speed = (u - geometry.wall_velocity(wall, x)).dot(wall.normal);  // relative to the wall
    if (normal_speed < 0.0) u -= normal_speed * wall.normal;
    ++moved;
  }
  return moved;
}

}  // namespace mps_lab
