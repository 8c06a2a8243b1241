// Mass properties of polygons and circles (core/bodies/mass_properties.hpp).
#include "core/bodies/mass_properties.hpp"

#include <algorithm>
#include <cmath>

namespace mps_lab {

namespace {
constexpr double kPi = 3.141592653589793;
}  // namespace

MassProperties polygon_mass_properties(const Polygon& polygon, double density) {
  const Vec2 origin = polygon.front();  // moments about vertex 0: smaller numbers, less rounding
  double twice_area = 0.0;
  Vec2 first = Vec2::Zero();  // 6 A C (relative to origin)
  double second = 0.0;        // 12 J_O (relative to origin)
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const Vec2 a = polygon[k] - origin, b = polygon[(k + 1) % polygon.size()] - origin;
    const double c = a.x() * b.y() - b.x() * a.y();
    twice_area += c;
    first += (a + b) * c;
    second += (a.x() * a.x() + a.x() * b.x() + b.x() * b.x() + a.y() * a.y() + a.y() * b.y() + b.y() * b.y()) * c;
  }
  const double sign = twice_area < 0.0 ? -1.0 : 1.0;  // a clockwise polygon: every sum changes sign
  MassProperties p;
  p.area = 0.5 * sign * twice_area;
  const Vec2 centroid = first / (3.0 * twice_area);  // (1 / 6A) sum, A = twice_area / 2
  p.centroid = origin + centroid;
  p.mass = density * p.area;
  p.inertia = density * sign * second / 12.0 - p.mass * centroid.squaredNorm();
  return p;
}

MassProperties circle_mass_properties(const Vec2& centre, double radius, double density) {
  MassProperties p;
  p.area = kPi * radius * radius;
  p.mass = density * p.area;
  p.centroid = centre;
  p.inertia = 0.5 * p.mass * radius * radius;
  return p;
}

int circle_sides(double radius, double l0) {
  return std::max(16, static_cast<int>(std::ceil(2.0 * kPi * radius / l0 - 1e-9)));
}

Polygon circle_polygon(const Vec2& centre, double radius, int sides) {
  Polygon polygon;
  for (int k = 0; k < sides; ++k) {
    const double angle = 2.0 * kPi * k / sides;
    polygon.emplace_back(centre.x() + radius * std::cos(angle), centre.y() + radius * std::sin(angle));
  }
  return polygon;
}

}  // namespace mps_lab
