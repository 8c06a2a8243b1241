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
// its wall at the same place and the same fluid lattice fills the tank. The geometry is that of the fixed walls: an
// obstacle with a motion law (core/walls/moving_walls.hpp) is left out.
#include <cstddef>
#include <vector>

#include "core/base/particles.hpp"
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

class WallGeometry {
 public:
  explicit WallGeometry(const Scene& scene);

  const std::vector<WallSegment>& segments() const { return segments_; }
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
  // Distance from x to the nearest wall segment, m; its index in *nearest if given.
  double distance(const Vec2& x, std::size_t* nearest = nullptr) const;
  // Distance from x to segment k, m.
  double distance_to(const Vec2& x, std::size_t k) const;

 private:
  bool past_open_side(const Vec2& x) const;
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
};

// The kinematic no-penetration condition of the boundary models of wall samples
// (docs/walls.md): a fluid particle found behind a wall surface is reflected back across the
// surface nearest to it, x <- x + 2 d n, and its velocity into the wall is removed,
// u_n <- max(u_n, 0). Returns how many particles it moved. Mirror-particle codes treat
// particles that cross the mirror line this way (e.g. Randles & Libersky 1996).
std::size_t reflect_crossed_particles(ParticleSet& particles, const WallGeometry& geometry);

}  // namespace mps_lab
