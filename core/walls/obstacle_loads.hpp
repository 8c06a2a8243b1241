#pragma once
// The load the fluid puts on each solid obstacle (walls.obstacles[k]), per unit width (2-D).
//
// This is the contract between what produces the load (a method's wall terms, through the
// boundary model in use) and what uses it (series columns, rigid bodies that move under it):
//   force[k]      N/m   the force the fluid exerts on obstacle k: minus the sum, over every
//                       fluid particle, of its mass times the acceleration the obstacle's
//                       wall terms give it (pressure and viscosity), so that the fluid and
//                       the obstacle exchange equal and opposite forces
//                       (or, where the method's Method::obstacle_load_kind() is SurfacePressure
//                       or FluidPressure, the integral of its wall particles' or the fluid's
//                       pressure over the obstacle's wetted surface, which the fluid's wall terms
//                       do not return exactly: docs/walls.md)
//   torque[k]     N     (N m per m width) the moment of those forces about reference[k],
//                       counter-clockwise positive: sum of (x - reference[k]) x f
//   reference[k]  m     the obstacle's area centroid where it is at this time (for a rigid
//                       body of uniform density, its centre of mass)
// Gravity on the obstacle and contact forces are not part of it. Sizes are the number of
// obstacles of the scene; a fixed obstacle has its load too.
#include <cstddef>
#include <vector>

#include "core/base/types.hpp"

namespace mps_lab {

struct ObstacleLoads {
  std::vector<Vec2> force;      // N/m
  std::vector<double> torque;   // N
  std::vector<Vec2> reference;  // m

  std::size_t size() const { return force.size(); }
  // Zero loads for `obstacles` obstacles (references kept if the size does not change).
  void reset(std::size_t obstacles) {
    force.assign(obstacles, Vec2::Zero());
    torque.assign(obstacles, 0.0);
    reference.resize(obstacles, Vec2::Zero());
  }
};

}  // namespace mps_lab
