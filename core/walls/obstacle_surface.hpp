#pragma once
// The wetted surface of obstacles as their surface wall particles represent it: for each wall
// particle of the layer facing the fluid (wall_layer 1), the outward unit normal of the surface
// edge it lies against and the length of that edge it stands for. What a load computed as the
// integral of the wall's pressure over the surface needs (F = - sum_j P_j n_j s_j; docs/walls.md,
// "Loads on obstacles"). Shared geometry: no method's operators.
//
// The surface is the obstacle's polygon (a box: the box grown by l0/2; a circle: its inscribed
// polygon), and its layer-1 wall particles lie at depth l0/2 under it (core/walls/wall_polygon.hpp).
//   - A particle belongs to the edge nearest to it; at a corner whose offset lines meet at the
//     particle (equally near both edges, within 1e-3 l0) to both: it carries a share of each.
//   - Along an edge, each of its particles stands for the part of the edge nearer to it than to its
//     neighbours on the edge (the cut half-way between their feet); the first and the last reach
//     the edge's ends. An edge's shares add up to its length, so a closed surface's n s add up to
//     zero (no net force from a uniform pressure). A box's particle on a face: l0; at a corner: l0
//     on each of its two faces.
//   - A share is dropped where the face stands against another solid (the lattice point l0 out
//     along its normal is a tank wall point or inside another obstacle, e.g. a plate's foot on
//     the bed): no fluid wets it. Judged where the scene puts the obstacle.
// Normals are in the obstacle's rest frame (where the scene puts it); obstacle_rotations gives
// the rotation of a moving one from its wall particles.
#include <array>
#include <cstdint>
#include <vector>

#include "core/base/particles.hpp"
#include "core/io/scene.hpp"

namespace mps_lab {

// A part of an obstacle's surface that one wall particle stands for.
struct SurfaceShare {
  Vec2 normal = Vec2::Zero();  // outward unit normal of the edge (into the fluid), rest frame
  double length = 0.0;         // m
};

// The shares of one wall particle: none (fluid, tank walls, inner layers), one on a face, two at a corner.
struct SurfaceElement {
  std::int32_t obstacle = -1;  // walls.obstacles[k], or kNoObstacle
  int count = 0;
  std::array<SurfaceShare, 2> shares{};
};

struct ObstacleSurface {
  std::vector<SurfaceElement> element_of_id;  // per particle id
  std::vector<Vec2> rest_position_of_id;      // m, the initial position (for obstacle_rotations)
  std::vector<Vec2> rest_mean;                // per obstacle: mean rest position of its surface particles, m
  std::vector<std::uint32_t> members;         // per obstacle: how many surface particles it has
};

// The counter-clockwise surface polygon of obstacle k where the scene puts it, m.
std::vector<Vec2> obstacle_surface_polygon(const Scene& scene, std::size_t k);

// The surface elements of every wall particle of `initial` (index = id) that belongs to an
// obstacle (obstacle_of_id from obstacle_of_wall_particles) and faces the fluid (wall_layer 1).
ObstacleSurface obstacle_surface(const Scene& scene, const ParticleSet& initial,
                                 const std::vector<std::int32_t>& obstacle_of_id);

// Per obstacle, (cos theta, sin theta) of its rotation from where the scene put it, from its
// surface particles now (`particles`, any order): the angle that maps the rest arms r0 = x0 - c0
// onto the arms r = x - c (c0, c the means), theta = atan2(sum r0 x r, sum r0 . r), exact for a
// rigid motion. (1, 0) for an obstacle that does not move (Scene walls.moving(k)).
std::vector<Vec2> obstacle_rotations(const Scene& scene, const ObstacleSurface& surface, const ParticleSet& particles);

// A rest-frame vector v turned by the rotation (cos, sin) = r.
inline Vec2 rotated(const Vec2& v, const Vec2& r) {
  return Vec2(r.x() * v.x() - r.y() * v.y(), r.y() * v.x() + r.x() * v.y());
}

}  // namespace mps_lab
