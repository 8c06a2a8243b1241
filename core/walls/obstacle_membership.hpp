#pragma once
// Which solid obstacle (walls.obstacles[k]) each wall particle belongs to, and the sum of the
// fluid's reaction on wall particles into the load on each obstacle (core/walls/obstacle_loads.hpp).
//
// Membership is read once from the initial particles, where a particle's index is its id
// (ParticleSet::id): a wall particle that is not a tank wall (on or beyond a walled side of the
// domain) belongs to the first obstacle that holds it - a box obstacle: on or inside the box; a
// polygon obstacle: inside its surface polygon (its wall particles lie at depths >= l0/2). It is
// kept by id, so it follows every reordering of the particles (cell order, checkpoints) with no
// bookkeeping. MovingWalls (core/walls/moving_walls.cpp) still has its own copy of the box rule;
// it can take obstacle_of_wall_particles instead (same answer for boxes).
#include <cstdint>
#include <vector>

#include "core/base/particles.hpp"
#include "core/io/scene.hpp"
#include "core/walls/obstacle_loads.hpp"
#include "core/walls/wall_sample_reactions.hpp"

namespace mps_lab {

constexpr std::int32_t kNoObstacle = -1;

// Whether x is a point of the tank's walls: on or beyond (within eps, m) a walled side of the domain.
bool on_tank_wall(const Vec2& x, const Scene& scene, double eps);
// Whether the scene's obstacle k (where the scene puts it) holds the point x: inside or on its
// polygon (within eps, m), or in its closed box.
bool obstacle_holds(const Scene& scene, std::size_t k, const Vec2& x, double eps);

// Per particle of `initial` (index = id): the obstacle k it belongs to, or kNoObstacle (fluid,
// tank walls, ghosts). The first obstacle that holds a wall point (inside or on its polygon, or
// in its closed box) owns it; a point a tank wall also holds stays with the tank.
std::vector<std::int32_t> obstacle_of_wall_particles(const Scene& scene, const ParticleSet& initial);

// The area centroid of obstacle k where the scene puts it, m: the centre of a box (its surface is
// the box grown by l0/2) or of a circle, the centroid of a polygon's surface (the lamina formula).
// The reference point of a moving obstacle's pose (core/walls/moving_walls.hpp) and of its load.
Vec2 obstacle_rest_centroid(const Scene& scene, std::size_t k);

// Zero loads on every obstacle of the scene, each about its reference point at time t (s): its rest
// centroid displaced by its motion law at t (a body's centre is set by the driver afterwards).
void start_obstacle_loads(const Scene& scene, double time, ObstacleLoads& loads);

// The loads at time t (s): force[k] = sum of reaction[j] over the wall particles j of obstacle k
// (reaction: the force the fluid puts on each particle, N/m, in the order of `particles`);
// torque[k] = sum (x_j - c_k) x reaction[j] about c_k = the rest centroid displaced by the
// obstacle's motion law at t (N m/m = N); reference[k] = c_k.
void sum_obstacle_loads(const Scene& scene, const ParticleSet& particles,
                        const std::vector<std::int32_t>& obstacle_of_id, const std::vector<Vec2>& reaction, double time,
                        ObstacleLoads& loads);

// loads += the reaction on each obstacle's wall samples (core/walls/wall_sample_reactions.hpp), its
// moment moved from the origin to the obstacle's reference point (loads.reference, set already).
void add_wall_sample_loads(const WallSampleLoads& sample_loads, ObstacleLoads& loads);

}  // namespace mps_lab
