#include "core/io/geometry.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <string>
#include <utility>

#include "core/base/error.hpp"
#include "core/walls/wall_polygon.hpp"

namespace mps_lab {

namespace {

std::string describe_point(const Vec2& point) { return describe_json(nlohmann::json::array({point.x(), point.y()})); }

long long whole_spacings(double length, double l0, const Scene& scene, const std::string& what) {
  const double count = length / l0;
  const double rounded = std::round(count);
  if (std::fabs(count - rounded) > 1e-6 * std::max(1.0, count)) {
    throw_input_error(scene.source, "particle_spacing",
                      "got " + describe_json(l0) + ", expected a spacing that divides the domain " + what + " (" +
                          describe_json(length) + " m) a whole number of times; walls must close on the lattice");
  }
  return static_cast<long long>(rounded);
}

// Spec §4 note: fluid particles are the lattice points strictly inside a block.
bool strictly_inside(double coordinate, double low, double high, double eps) {
  return coordinate > low + eps && coordinate < high - eps;
}

// Whether some lattice coordinate origin + k l0 lies strictly inside (low, high).
bool lattice_coordinate_inside(double origin, double low, double high, double l0) {
  const auto first = static_cast<long long>(std::floor((low - origin) / l0)) - 1;
  const auto last = static_cast<long long>(std::ceil((high - origin) / l0)) + 1;
  for (long long k = first; k <= last; ++k) {
    if (strictly_inside(origin + static_cast<double>(k) * l0, low, high, 1e-9 * l0)) return true;
  }
  return false;
}

[[noreturn]] void throw_empty_block(const Scene& scene, std::size_t k) {
  const Box& box = scene.fluid_blocks[k].region;
  throw_input_error(scene.source, "fluid_blocks[" + std::to_string(k) + "]",
                    "got min " + describe_point(box.min) + " and max " + describe_point(box.max) +
                        ", expected a block holding at least one lattice point strictly inside at particle_spacing " +
                        describe_json(scene.particle_spacing) + " m");
}

}  // namespace

void check_lattice(const Scene& scene) {
  const double l0 = scene.particle_spacing;
  const Vec2 origin = scene.domain.min;
  whole_spacings(scene.domain.max.x() - origin.x(), l0, scene, "width");
  whole_spacings(scene.domain.max.y() - origin.y(), l0, scene, "height");
  for (std::size_t k = 0; k < scene.fluid_blocks.size(); ++k) {
    const Box& box = scene.fluid_blocks[k].region;
    if (!lattice_coordinate_inside(origin.x(), box.min.x(), box.max.x(), l0) ||
        !lattice_coordinate_inside(origin.y(), box.min.y(), box.max.y(), l0)) {
      throw_empty_block(scene, k);
    }
  }
}

namespace {

// The lattice of the spec's initial particles (spec §4): origin + (i, j) l0.
struct Lattice {
  Vec2 origin;
  double l0;  // m
  Vec2 operator()(long long i, long long j) const {
    return Vec2(origin.x() + static_cast<double>(i) * l0, origin.y() + static_cast<double>(j) * l0);
  }
};

// A box in lattice indices, corners included.
struct LatticeBox {
  long long i0, j0, i1, j1;
};

using LatticePoints = std::set<std::pair<long long, long long>>;  // (j, i)

// Obstacles in lattice indices (their corners are lattice points: the scene loader checks).
std::vector<LatticeBox> lattice_obstacles(const Scene& scene, const Lattice& lattice) {
  const Vec2 origin = lattice.origin;
  const double l0 = lattice.l0;
  std::vector<LatticeBox> obstacles;
  for (std::size_t k = 0; k < scene.walls.obstacles.size(); ++k) {
    if (scene.walls.is_polygon(k)) continue;  // add_polygon_walls
    const Box& box = scene.walls.obstacles[k];
    obstacles.push_back({std::llround((box.min.x() - origin.x()) / l0), std::llround((box.min.y() - origin.y()) / l0),
                         std::llround((box.max.x() - origin.x()) / l0), std::llround((box.max.y() - origin.y()) / l0)});
  }
  return obstacles;
}

bool in_obstacle(const std::vector<LatticeBox>& obstacles, long long i, long long j) {
  for (const auto& b : obstacles) {
    if (i >= b.i0 && i <= b.i1 && j >= b.j0 && j <= b.j1) return true;
  }
  return false;
}

// Whether a lattice point x is cut by a polygon obstacle: inside its surface or closer than
// l0/2 to it (the rule of a box, whose surface is l0/2 outside its lattice points;
// core/walls/wall_polygon.hpp).
bool cut_by_polygon(const TankWalls& walls, const Vec2& x, double l0) {
  for (const Polygon& polygon : walls.polygons) {
    if (polygon.empty()) continue;
    if (inside_polygon(x, polygon) || distance_to_polygon(x, polygon) < 0.5 * l0 - 1e-9 * l0) return true;
  }
  return false;
}

// Fluid first: lattice points strictly inside any block (blocks may overlap), outside the
// obstacles (an obstacle's lattice points are wall). Returns the fluid's lattice points.
LatticePoints add_fluid(const Scene& scene, const Lattice& lattice, const std::vector<LatticeBox>& obstacles,
                        ParticleSet& particles) {
  const Vec2 origin = lattice.origin;
  const double l0 = lattice.l0;
  LatticePoints fluid_points;
  const double eps = 1e-9 * l0;
  for (std::size_t k = 0; k < scene.fluid_blocks.size(); ++k) {
    const auto& block = scene.fluid_blocks[k];
    const auto i_first = static_cast<long long>(std::floor((block.region.min.x() - origin.x()) / l0)) - 1;
    const auto i_last = static_cast<long long>(std::ceil((block.region.max.x() - origin.x()) / l0)) + 1;
    const auto j_first = static_cast<long long>(std::floor((block.region.min.y() - origin.y()) / l0)) - 1;
    const auto j_last = static_cast<long long>(std::ceil((block.region.max.y() - origin.y()) / l0)) + 1;
    std::size_t inside = 0;
    for (long long j = j_first; j <= j_last; ++j) {
      for (long long i = i_first; i <= i_last; ++i) {
        const Vec2 x = lattice(i, j);
        if (strictly_inside(x.x(), block.region.min.x(), block.region.max.x(), eps) &&
            strictly_inside(x.y(), block.region.min.y(), block.region.max.y(), eps)) {
          ++inside;
          if (in_obstacle(obstacles, i, j) || cut_by_polygon(scene.walls, x, l0)) continue;
          if (fluid_points.insert({j, i}).second) {
            particles.add(x, block.velocity, ParticleType::Fluid);
          }
        }
      }
    }
    if (inside == 0) throw_empty_block(scene, k);
  }
  return fluid_points;
}

// Adds wall particles at lattice points, each once, never where a block keeps its fluid.
class WallBuilder {
 public:
  WallBuilder(const Lattice& lattice, const LatticePoints& fluid_points, ParticleSet& particles)
      : lattice_(lattice), fluid_points_(fluid_points), particles_(particles) {}
  void add(long long i, long long j, std::uint8_t layer) {
    if (fluid_points_.count({j, i}) != 0) return;  // a block reaching the wall keeps its fluid
    if (!wall_points_.insert({j, i}).second) return;
    particles_.add(lattice_(i, j), Vec2::Zero(), ParticleType::Wall, layer);
  }

 private:
  const Lattice& lattice_;
  const LatticePoints& fluid_points_;
  ParticleSet& particles_;
  LatticePoints wall_points_;
};

// The tank's walls. Layer = 1 + how many spacings the point lies outside the fluid region
// along the walled directions (Chebyshev distance), so corner blocks belong to outer layers.
void add_tank_walls(const TankWalls& walls, long long nx, long long ny, WallBuilder& builder) {
  const long long layers = walls.layers;
  const auto layer_of = [&](long long i, long long j) {
    long long outside = 0;
    if (walls.left) outside = std::max(outside, -i);
    if (walls.right) outside = std::max(outside, i - nx);
    if (walls.bottom) outside = std::max(outside, -j);
    if (walls.top) outside = std::max(outside, j - ny);
    return static_cast<std::uint8_t>(1 + outside);
  };
  const long long i_min = walls.left ? -(layers - 1) : 0;
  const long long i_max = walls.right ? nx + layers - 1 : nx;
  const auto add_wall = [&](long long i, long long j) { builder.add(i, j, layer_of(i, j)); };
  if (walls.bottom) {
    for (long long k = 0; k < layers; ++k) {
      for (long long i = i_min; i <= i_max; ++i) add_wall(i, -k);
    }
  }
  const long long j_first = walls.bottom ? 1 : 0;
  const long long j_last = ny - 1;
  for (long long j = j_first; j <= j_last; ++j) {
    for (long long k = 0; k < layers; ++k) {
      if (walls.left) add_wall(-k, j);
      if (walls.right) add_wall(nx + k, j);
    }
  }
  if (walls.top) {
    for (long long k = 0; k < layers; ++k) {
      for (long long i = i_min; i <= i_max; ++i) add_wall(i, ny + k);
    }
  }
}

// Obstacles: `layers` layers from the box sides inwards (layer 1 on the sides), the core of
// a thick box left empty as the outer tank layers end; points the tank walls hold are theirs.
void add_obstacle_walls(const std::vector<LatticeBox>& obstacles, long long layers, WallBuilder& builder) {
  for (const auto& b : obstacles) {
    for (long long j = b.j0; j <= b.j1; ++j) {
      for (long long i = b.i0; i <= b.i1; ++i) {
        const long long inward = std::min({i - b.i0, b.i1 - i, j - b.j0, b.j1 - j});
        if (inward < layers) builder.add(i, j, static_cast<std::uint8_t>(1 + inward));
      }
    }
  }
}

// Polygon obstacles: their wall points (core/walls/wall_polygon.hpp), each dropped where a
// wall particle already lies closer than l0/2 (a polygon on the bed or against another solid).
void add_polygon_walls(const TankWalls& walls, double l0, ParticleSet& particles) {
  for (const Polygon& polygon : walls.polygons) {
    if (polygon.empty()) continue;
    std::vector<Vec2> nearby;  // wall particles within reach of the polygon, m
    Vec2 low = polygon.front(), high = low;
    for (const Vec2& x : polygon) low = low.cwiseMin(x), high = high.cwiseMax(x);
    for (std::size_t i = 0; i < particles.size(); ++i) {
      const Vec2& x = particles.position[i];
      const bool reach = (x.array() > low.array() - l0).all() && (x.array() < high.array() + l0).all();
      if (particles.type[i] == ParticleType::Wall && reach) nearby.push_back(x);
    }
    for (const auto& [x, layer] : polygon_wall_points(polygon, l0, walls.layers)) {
      const bool taken =
          std::any_of(nearby.begin(), nearby.end(), [&](const Vec2& y) { return (x - y).norm() < 0.5 * l0; });
      if (!taken) particles.add(x, Vec2::Zero(), ParticleType::Wall, static_cast<std::uint8_t>(layer));
    }
  }
}

}  // namespace

ParticleSet build_particles(const Scene& scene, bool wall_particles) {
  const double l0 = scene.particle_spacing;
  const Vec2 origin = scene.domain.min;
  const long long nx = whole_spacings(scene.domain.max.x() - origin.x(), l0, scene, "width");
  const long long ny = whole_spacings(scene.domain.max.y() - origin.y(), l0, scene, "height");
  const Lattice lattice{origin, l0};
  ParticleSet particles;
  const std::vector<LatticeBox> obstacles = lattice_obstacles(scene, lattice);
  const LatticePoints fluid_points = add_fluid(scene, lattice, obstacles, particles);
  if (!wall_particles) return particles;  // the boundary model builds its own wall (wall samples)
  WallBuilder builder(lattice, fluid_points, particles);
  add_tank_walls(scene.walls, nx, ny, builder);
  add_obstacle_walls(obstacles, scene.walls.layers, builder);
  add_polygon_walls(scene.walls, l0, particles);
  return particles;
}

double escape_margin(const Scene& scene) { return scene.particle_spacing * (scene.walls.layers + 1); }

std::size_t mark_escaped_as_ghosts(ParticleSet& particles, const Scene& scene) {
  const double margin = escape_margin(scene);
  const Vec2 low = scene.domain.min - Vec2(margin, margin);
  const Vec2 high = scene.domain.max + Vec2(margin, margin);
  std::size_t escaped = 0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] != ParticleType::Fluid) continue;
    const Vec2& x = particles.position[i];
    const bool finite = std::isfinite(x.x()) && std::isfinite(x.y());
    if (!finite || x.x() < low.x() || x.y() < low.y() || x.x() > high.x() || x.y() > high.y()) {
      particles.type[i] = ParticleType::Ghost;
      particles.velocity[i] = Vec2::Zero();
      particles.pressure[i] = 0.0;
      ++escaped;
    }
  }
  return escaped;
}

namespace {

// The index of the first fluid block holding x (bounds included), or -1.
int block_holding(const Scene& scene, const Vec2& x) {
  for (std::size_t b = 0; b < scene.fluid_blocks.size(); ++b) {
    const Box& box = scene.fluid_blocks[b].region;
    if (x.x() >= box.min.x() && x.x() <= box.max.x() && x.y() >= box.min.y() && x.y() <= box.max.y()) {
      return static_cast<int>(b);
    }
  }
  return -1;
}

}  // namespace

std::vector<double> hydrostatic_block_pressure(const Scene& scene, const ParticleSet& particles,
                                               double surface_offset) {
  std::vector<double> pressure(particles.size(), 0.0);
  const double g = scene.physics.gravity.norm();  // m/s^2
  if (!(g > 0.0)) return pressure;                // no weight, no head
  const Vec2 up = -scene.physics.gravity / g;     // for gravity along -y, exactly (0, 1): the height is y
  std::vector<double> block_top(scene.fluid_blocks.size(), -1e300);
  std::vector<int> block_of(particles.size(), -1);
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] != ParticleType::Fluid) continue;
    block_of[i] = block_holding(scene, particles.position[i]);
    if (block_of[i] >= 0) block_top[block_of[i]] = std::max(block_top[block_of[i]], up.dot(particles.position[i]));
  }
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (block_of[i] < 0) continue;
    const double surface = block_top[block_of[i]] + surface_offset;  // its height, m
    pressure[i] = std::max(0.0, scene.physics.density * g * (surface - up.dot(particles.position[i])));
  }
  return pressure;
}

}  // namespace mps_lab
