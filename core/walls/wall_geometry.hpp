#pragma once
// The walls of a scene as geometry: straight wall surfaces (segments) and the solids behind
// them. Boundary models without wall particles build their samples from it (core/walls/),
// the stability monitor and the wall study measure penetration and the fluid-wall distance
// with it.
//
// Where the surface lies. On the lattice of spec §4 the first wall layer sits on the domain
// boundary and the first fluid row one spacing inside, so the wall surface is half a spacing
// from each: x_min + l0/2 for a left wall, and so on. An obstacle box (walls.obstacles,
// corners on the lattice) holds wall particles on and inside its sides; its surface is the
// box grown by l0/2. A polygon obstacle (walls.obstacles[k].polygon) is its own surface, its
// edges segments at any angle (core/walls/wall_polygon.hpp). Every boundary model, with particles or without, thus has
// its wall at the same place and the same fluid lattice fills the tank.
//
// Moving obstacles (a motion law or a body, core/walls/moving_walls.hpp). By default the
// geometry is that of the fixed walls and a moving obstacle is left out (the stability
// monitor's penetration check, the position clamp). A boundary model of wall samples asks for
// them (MovingObstacles::Included) and moves them every step to their poses (move_obstacles):
// a box translated stays a box, a polygon (or a box turned by an angle) is moved vertex by
// vertex, x = x_c0 + d + R(theta) (x0 - x_c0), and the segments are rebuilt as at the start.
// At zero displacement the segments are those of the same obstacle fixed, to the bit; once
// moved, a box is first cut at the tank's wall surfaces (a gate standing on the bed has its foot
// at the bed's surface, as its wall particles: the bed's row stays with the tank).
#include <cstddef>
#include <optional>
#include <vector>

#include "core/base/particles.hpp"
#include "core/base/rigid_pose.hpp"
#include "core/base/types.hpp"
#include "core/io/scene.hpp"
#include "core/walls/wall_polygon.hpp"

namespace mps_lab {

struct WallSegment {
  Vec2 a = Vec2::Zero();  // end points, m
  Vec2 b = Vec2::Zero();
  Vec2 normal = Vec2::Zero();  // unit, pointing into the fluid
  int body = -1;               // -1: the tank; k >= 0: walls.obstacles[k]
};

// Where the segment p + u across (u in [0, 1]) crosses the segment a + t along strictly inside it:
// t in (0, 1), none if they do not cross or are parallel (a wall segment cut where another meets it).
std::optional<double> crossing_parameter(const Vec2& a, const Vec2& along, const Vec2& p, const Vec2& across);

enum class MovingObstacles {
  Excluded,  // the fixed walls only
  Included,  // moving obstacles too, where move_obstacles last put them (at rest until then)
};

class WallGeometry {
 public:
  explicit WallGeometry(const Scene& scene, MovingObstacles moving = MovingObstacles::Excluded);

  const std::vector<WallSegment>& segments() const { return segments_; }
  // Whether the geometry holds an obstacle that moves (MovingObstacles::Included and the scene
  // has one).
  bool has_moving_obstacles() const { return !rest_centroid_.empty(); }
  // Every moving obstacle k to poses[k] (one per obstacle; core/base/rigid_pose.hpp), the
  // segments rebuilt. Fixed obstacles ignore their entry.
  void move_obstacles(const std::vector<RigidPose>& poses);
  // The velocity (m/s) and acceleration (m/s^2) of the wall surface `segment` at the point x
  // (of the solid moving with it): the rigid motion of its obstacle's pose, zero for a fixed wall.
  Vec2 wall_velocity(const WallSegment& segment, const Vec2& x) const;
  Vec2 wall_acceleration(const WallSegment& segment, const Vec2& x) const;
  bool moves(const WallSegment& segment) const { return !moving_pose_.empty() && can_move(segment); }
  // Whether the segment belongs to an obstacle that moves (walls.obstacles[k].motion), wherever
  // it is now: false for the tank and fixed obstacles, whose segments never part.
  bool can_move(const WallSegment& segment) const {
    return segment.body >= 0 && static_cast<std::size_t>(segment.body) < moving_.size() &&
           moving_[static_cast<std::size_t>(segment.body)];
  }
  double surface_offset() const { return half_spacing_; }  // l0 / 2, m

  // Whether x lies beyond a wall surface: behind a tank side (within the side's `layers`
  // spacings of thickness, and not past an open side) or inside an obstacle's surface box.
  bool inside_solid(const Vec2& x) const;
  // How far x lies beyond the wall surface, m (0 on the fluid side). The first wall particle
  // line is at depth l0/2: a fluid particle deeper than that has penetrated the wall.
  double depth_inside(const Vec2& x) const;
  // Whether x lies outside the tank across a walled side, at any distance behind it, and not
  // past an open side (not above an open top). A ghost there left through the wall: ghosts are
  // made more than l0 (layers + 1) outside the domain, beyond any side's slab, so depth_inside
  // alone cannot see them (core/run/stability.cpp, check_ghosts).
  bool behind_walled_side(const Vec2& x) const;
  // The solid that holds x: -1 for the tank's walls (which win where an obstacle overlaps them),
  // k for walls.obstacles[k] where the geometry puts it, none outside every solid.
  std::optional<int> solid_holding(const Vec2& x) const;
  // The index of the nearest wall segment among those whose line x lies behind (on the solid's
  // side of it), segments().size() if there is none: the segment whose virtual wall can hold
  // the point x (core/walls/distance_function.cpp).
  std::size_t nearest_behind(const Vec2& x) const;
  // Distance from x to the nearest wall segment, m; its index in *nearest if given.
  double distance(const Vec2& x, std::size_t* nearest = nullptr) const;
  // Distance from x to segment k, m.
  double distance_to(const Vec2& x, std::size_t k) const;

 private:
  void build_segments();
  bool past_open_side(const Vec2& x) const;
  double tank_depth(const Vec2& x) const;  // m behind a walled side's surface, 0 elsewhere
  bool inside_polygon_solid(const Vec2& x, std::size_t k) const;
  void add_polygon_edges(std::vector<WallSegment>& candidates) const;
  std::vector<WallSegment> split_tank_sides_at_polygons(const std::vector<WallSegment>& sides) const;
  std::vector<WallSegment> segments_;
  TankWalls walls_;
  Box domain_;
  Box interior_;                   // the tank's surfaces; open sides extend to infinity
  std::vector<Box> obstacles_;     // surface boxes (the obstacle grown by l0/2); empty for a polygon
  std::vector<Polygon> polygons_;  // per obstacle: its surface polygon, counter-clockwise; empty for a box
  double half_spacing_ = 0.0;
  // Moving obstacles (MovingObstacles::Included): per obstacle, whether it moves, its surface
  // box and polygon where the scene puts them, and its reference point x_c0 (m); empty otherwise.
  std::vector<bool> moving_;
  std::vector<Box> rest_obstacles_;
  std::vector<Box> rest_clipped_;  // rest_obstacles_ cut at the tank's wall surfaces (move_obstacles)
  std::vector<Polygon> rest_polygons_;
  std::vector<Vec2> rest_centroid_;
  std::vector<RigidPose> moving_pose_;  // per obstacle, the last move_obstacles (empty until then)
};

// The kinematic no-penetration condition of the boundary models of wall samples
// (docs/walls.md): a fluid particle found behind a wall surface is reflected back across the
// surface nearest to it, x <- x + 2 d n, and its velocity into the wall relative to the wall's
// is removed, (u - u_w) . n <- max((u - u_w) . n, 0) (u_w = 0 for a wall at rest). Returns how many particles it moved.
// Mirror-particle codes treat particles that cross the mirror line this way (e.g. Randles & Libersky 1996).
std::size_t reflect_crossed_particles(ParticleSet& particles, const WallGeometry& geometry);

}  // namespace mps_lab
