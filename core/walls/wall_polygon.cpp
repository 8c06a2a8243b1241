#include "core/walls/wall_polygon.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace mps_lab {

namespace {

double cross(const Vec2& u, const Vec2& v) { return u.x() * v.y() - u.y() * v.x(); }

double distance_to_segment(const Vec2& x, const Vec2& a, const Vec2& b) {
  const Vec2 along = b - a;
  const double length2 = along.squaredNorm();
  const double t = length2 > 0.0 ? std::clamp((x - a).dot(along) / length2, 0.0, 1.0) : 0.0;
  return (x - (a + t * along)).norm();
}

// Whether segments ab and cd cross or come closer than `tolerance`, m.
bool segments_meet(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d, double tolerance) {
  const double o1 = cross(b - a, c - a), o2 = cross(b - a, d - a);
  const double o3 = cross(d - c, a - c), o4 = cross(d - c, b - c);
  if (o1 * o2 < 0.0 && o3 * o4 < 0.0) return true;
  return std::min({distance_to_segment(c, a, b), distance_to_segment(d, a, b), distance_to_segment(a, c, d),
                   distance_to_segment(b, c, d)}) < tolerance;
}

Vec2 inward_normal(const Polygon& polygon, std::size_t k) { return -outward_normal(polygon, k); }

// Vertex k of the inward offset at depth d with a mitred corner: where the offset lines of
// edges k-1 and k cross, x_k + d (n1 + n2) / (1 + n1 . n2) (n: inward unit normals).
Vec2 offset_vertex(const Polygon& polygon, std::size_t k, double depth) {
  const std::size_t n = polygon.size();
  const Vec2 n1 = inward_normal(polygon, (k + n - 1) % n);
  const Vec2 n2 = inward_normal(polygon, k);
  return polygon[k] + depth * (n1 + n2) / (1.0 + n1.dot(n2));
}

}  // namespace

double signed_area(const Polygon& polygon) {
  double twice = 0.0;
  for (std::size_t k = 0; k < polygon.size(); ++k) twice += cross(polygon[k], polygon[(k + 1) % polygon.size()]);
  return 0.5 * twice;
}

Polygon counter_clockwise(Polygon polygon) {
  if (signed_area(polygon) < 0.0) std::reverse(polygon.begin(), polygon.end());
  return polygon;
}

bool inside_polygon(const Vec2& x, const Polygon& polygon) {
  bool inside = false;  // crossing number of a ray towards +x
  for (std::size_t k = 0, j = polygon.size() - 1; k < polygon.size(); j = k++) {
    const Vec2& a = polygon[k];
    const Vec2& b = polygon[j];
    if ((a.y() > x.y()) != (b.y() > x.y())) {
      const double crossing = a.x() + (x.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y());
      if (x.x() < crossing) inside = !inside;
    }
  }
  return inside;
}

double distance_to_polygon(const Vec2& x, const Polygon& polygon, std::size_t* edge) {
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const double d = distance_to_segment(x, polygon[k], polygon[(k + 1) % polygon.size()]);
    if (d < best) {
      best = d;
      if (edge != nullptr) *edge = k;
    }
  }
  return best;
}

double depth_inside_polygon(const Vec2& x, const Polygon& polygon) {
  return inside_polygon(x, polygon) ? distance_to_polygon(x, polygon) : 0.0;
}

Vec2 outward_normal(const Polygon& polygon, std::size_t k) {
  const Vec2 along = (polygon[(k + 1) % polygon.size()] - polygon[k]).normalized();
  return Vec2(along.y(), -along.x());  // the right of the direction: outside a counter-clockwise polygon
}

std::string polygon_defect(const Polygon& polygon, double tolerance) {
  const std::size_t n = polygon.size();
  if (n < 3) return "fewer than 3 vertices";
  for (std::size_t a = 0; a < n; ++a) {
    for (std::size_t b = a + 1; b < n; ++b) {
      if ((polygon[a] - polygon[b]).norm() < tolerance) {
        return "vertex " + std::to_string(b) + " repeats vertex " + std::to_string(a);
      }
    }
  }
  // All vertices on one line (within the tolerance): the line through vertex 0 and the vertex farthest from it.
  std::size_t far = 0;
  for (std::size_t a = 1; a < n; ++a) {
    if ((polygon[a] - polygon[0]).norm() > (polygon[far] - polygon[0]).norm()) far = a;
  }
  const Vec2 line = (polygon[far] - polygon[0]).normalized();
  const bool collinear = std::all_of(polygon.begin(), polygon.end(),
                                     [&](const Vec2& x) { return std::fabs(cross(line, x - polygon[0])) < tolerance; });
  if (collinear) return "zero area: the vertices lie on one line";
  for (std::size_t a = 0; a < n; ++a) {
    const Vec2 &p = polygon[a], &q = polygon[(a + 1) % n];
    for (std::size_t b = a + 1; b < n; ++b) {
      const Vec2 &r = polygon[b], &s = polygon[(b + 1) % n];
      const bool next = b == a + 1, wraps = (b + 1) % n == a;
      // Neighbours share a vertex: they overlap only if one folds back onto the other.
      const bool meet = next    ? distance_to_segment(s, p, q) < tolerance || distance_to_segment(p, r, s) < tolerance
                        : wraps ? distance_to_segment(r, p, q) < tolerance || distance_to_segment(q, r, s) < tolerance
                                : segments_meet(p, q, r, s, tolerance);
      if (meet) return "edges " + std::to_string(a) + " and " + std::to_string(b) + " intersect";
    }
  }
  if (std::fabs(signed_area(polygon)) < tolerance * tolerance) return "zero area";
  return "";
}

std::vector<std::pair<Vec2, int>> polygon_wall_points(const Polygon& polygon, double l0, int layers) {
  std::vector<std::pair<Vec2, int>> points;
  const auto near_kept = [&](const Vec2& x) {
    return std::any_of(points.begin(), points.end(), [&](const auto& p) { return (p.first - x).norm() < 0.5 * l0; });
  };
  const std::size_t n = polygon.size();
  for (int layer = 0; layer < layers; ++layer) {
    const double depth = (layer + 0.5) * l0;  // m, behind the surface
    for (std::size_t k = 0; k < n; ++k) {
      const Vec2 start = offset_vertex(polygon, k, depth);
      const Vec2 end = offset_vertex(polygon, (k + 1) % n, depth);
      const Vec2 edge = polygon[(k + 1) % n] - polygon[k];
      // The offset edge turned back: the polygon is too thin here for this layer. (One of length
      // 0, a square's centre, gives its point.)
      if ((end - start).dot(edge) < -1e-9 * l0 * edge.norm()) continue;
      const auto intervals = std::max(1L, std::lround((end - start).norm() / l0));
      for (long m = 0; m <= intervals; ++m) {
        const Vec2 x = start + (static_cast<double>(m) / static_cast<double>(intervals)) * (end - start);
        if (depth_inside_polygon(x, polygon) < depth - 0.25 * l0 || near_kept(x)) continue;
        points.emplace_back(x, layer + 1);
      }
    }
  }
  return points;
}

Polygon box_polygon(const Vec2& low, const Vec2& high) {
  return {low, Vec2(high.x(), low.y()), high, Vec2(low.x(), high.y())};
}

Polygon posed_polygon(const Polygon& rest, const Vec2& rest_centroid, const RigidPose& pose) {
  Polygon placed;
  placed.reserve(rest.size());
  const Vec2 centre = rest_centroid + pose.displacement;
  for (const Vec2& vertex : rest) {
    placed.push_back(pose.angle == 0.0 ? Vec2(vertex + pose.displacement)
                                       : Vec2(centre + rotated_arm(pose, vertex - rest_centroid)));
  }
  return placed;
}

}  // namespace mps_lab
