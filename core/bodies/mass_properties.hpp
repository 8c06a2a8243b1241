#pragma once
// Mass properties of a rigid body (docs/bodies.md) of uniform density: mass, centre of mass and
// moment of inertia about it, per metre of width (2-D: density kg/m^3 times area m^2 times 1 m).
//
// Polygon: the area, first and second moments as sums over the edges (Green's theorem; e.g.
// Bourke 1988, "Calculating the area and centroid of a polygon", and Steger 1996, "On the
// calculation of arbitrary moments of polygons"), with c_k = x_k y_{k+1} - x_{k+1} y_k:
//   A   = 1/2 sum c_k
//   C   = 1/(6 A) sum (x_k + x_{k+1}, y_k + y_{k+1}) c_k
//   J_O = 1/12 sum (x_k^2 + x_k x_{k+1} + x_{k+1}^2 + y_k^2 + y_k y_{k+1} + y_{k+1}^2) c_k
//   m = rho A,  I_C = rho J_O - m |C|^2  (parallel axes)
// computed in coordinates relative to vertex 0 to keep the rounding small.
// Circle: m = rho pi r^2, I_C = m r^2 / 2 (exact).
#include "core/base/types.hpp"
#include "core/walls/wall_polygon.hpp"

namespace mps_lab {

struct MassProperties {
  double area = 0.0;             // m^2
  double mass = 0.0;             // kg per m of width
  Vec2 centroid = Vec2::Zero();  // centre of mass, m
  double inertia = 0.0;          // about the centroid, kg m^2 per m of width
};

// A polygon of either orientation (the area is taken positive).
MassProperties polygon_mass_properties(const Polygon& polygon, double density);
MassProperties circle_mass_properties(const Vec2& centre, double radius, double density);

// How many sides the wall polygon of a circle of radius r has at spacing l0: max(16,
// ceil(2 pi r / l0)), so that its vertices lie about l0 apart on the surface like the lattice's
// particles and the polygon departs from the circle by at most the sagitta r (1 - cos(pi/n))
// ~ l0^2 / (8 r) (l0/40 for r = 5 l0).
int circle_sides(double radius, double l0);
// The regular polygon with `sides` vertices on the circle, counter-clockwise, vertex 0 at angle 0.
Polygon circle_polygon(const Vec2& centre, double radius, int sides);

}  // namespace mps_lab
