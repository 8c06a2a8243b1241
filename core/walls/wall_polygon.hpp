#pragma once
// Polygon walls (walls.obstacles[k].polygon, docs/walls.md "Polygon walls"): the plane
// geometry of a closed polygon and its wall particles.
//
// Where the surface lies. A polygon is the wall SURFACE, what a user draws: fluid lattice
// points inside it or closer than l0/2 to it are not created, and its wall particles lie
// inside it, layer k (k = 0 .. layers-1) on the inward offset of the polygon at depth
// (k + 1/2) l0. A box obstacle [min, max] (corners on the lattice) is the polygon of the box
// grown by l0/2: the same surface, and the same lattice points as wall particles.
#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include "core/base/rigid_pose.hpp"
#include "core/base/types.hpp"

namespace mps_lab {

using Polygon = std::vector<Vec2>;  // vertices, m; closed implicitly (last -> first)

// The signed area, m^2 (> 0 counter-clockwise), shoelace formula.
double signed_area(const Polygon& polygon);
// The same polygon counter-clockwise (reversed if it was clockwise).
Polygon counter_clockwise(Polygon polygon);
// Whether x lies inside the polygon (crossing number; a point on an edge may go either way,
// callers use depth_inside_polygon, which is 0 there).
bool inside_polygon(const Vec2& x, const Polygon& polygon);
// Distance from x to the polygon's edges, m; the nearest edge's index (edge k runs from
// vertex k to vertex k+1) in *edge if given.
double distance_to_polygon(const Vec2& x, const Polygon& polygon, std::size_t* edge = nullptr);
// How far x lies inside the polygon, m: its distance to the surface when inside, else 0.
double depth_inside_polygon(const Vec2& x, const Polygon& polygon);
// The unit normal of edge k of a counter-clockwise polygon, pointing out of it (into the fluid).
Vec2 outward_normal(const Polygon& polygon, std::size_t k);

// The corners of the axis-aligned box [low, high], counter-clockwise from low.
Polygon box_polygon(const Vec2& low, const Vec2& high);
// A polygon where a pose (core/base/rigid_pose.hpp) puts it: each vertex x0 + d when the pose
// does not turn (to the bit at d = 0), else x_c0 + d + R(theta) (x0 - x_c0) about its reference
// point x_c0 (m). The moving obstacles' surfaces (WallGeometry) and clamp polygons share it.
Polygon posed_polygon(const Polygon& rest, const Vec2& rest_centroid, const RigidPose& pose);

// What is wrong with a polygon as a wall, or "" if nothing: fewer than 3 vertices, a repeated
// vertex (closer than `tolerance`, m), two edges that cross or touch (other than neighbours
// at their shared vertex), zero area. The scene loader names the key.
std::string polygon_defect(const Polygon& polygon, double tolerance);

// The wall particles of a counter-clockwise polygon: `layers` layers at depths (k + 1/2) l0
// (layer number k + 1, 1 facing the fluid), each the polygon's inward offset with mitred
// corners (the offsets of two neighbouring edges meet where their lines cross: at a convex
// corner the lines are cut there, at a concave one extended), every offset edge divided evenly
// into round(length / l0) intervals, ends included. A point is dropped where the polygon is
// too thin for its layer (nearer than (k + 1/4) l0 to the surface: it belongs to a shallower
// layer of another face) or where a kept point lies closer than l0/2 (shared corners, the
// overlapping offsets of a concave corner or a thin plate). Layer 0 first, so shallower
// layers win.
std::vector<std::pair<Vec2, int>> polygon_wall_points(const Polygon& polygon, double l0, int layers);

}  // namespace mps_lab
