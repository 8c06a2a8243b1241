#pragma once
// The still-water obstacle case shared by the load tests (test_obstacle_loads, test_mps_loads,
// test_mps_surface_loads): scenes/hydrostatic.json (l0 = 0.025 m, water to y = 0.2875 m) with a
// submerged box and a plate standing on the bed against the right wall.
//   box surface [0.1875, 0.3125] x [0.0875, 0.1625] m: buoyancy rho g A, A = 0.125 x 0.075 m^2;
//   plate surface [0.4375, 0.4875] x [0.0125, 0.5125] m, its right face against the tank's wall
//   (x = 0.5) and its foot on the bed (y = 0): thrust rho g h^2 / 2 with h = 0.275 m.
#include "core/base/types.hpp"
#include "core/run/driver.hpp"

namespace mps_lab::testing {

inline constexpr const char* kStillWaterObstacles =
    "walls.obstacles=[{\"min\": [0.2, 0.1], \"max\": [0.3, 0.15]}, {\"min\": [0.45, 0.025], \"max\": [0.475, 0.5]}]";

// The loads on the box (obstacle 0) and the plate (obstacle 1).
struct MeanLoads {
  Vec2 box_force = Vec2::Zero(), plate_force = Vec2::Zero();  // N/m
  double box_torque = 0.0, plate_torque = 0.0;                // N, about each obstacle's area centroid
};

// The loads averaged over every step in [from, to] s of `run`.
inline MeanLoads mean_loads(Simulation& run, double from, double to) {
  MeanLoads mean;
  long long steps = 0;
  run.run_to(from);
  while (run.time() < to) {
    run.advance();
    const ObstacleLoads& loads = run.obstacle_loads();
    mean.box_force += loads.force[0];
    mean.plate_force += loads.force[1];
    mean.box_torque += loads.torque[0];
    mean.plate_torque += loads.torque[1];
    ++steps;
  }
  const double n = static_cast<double>(steps);
  mean.box_force /= n;
  mean.plate_force /= n;
  mean.box_torque /= n;
  mean.plate_torque /= n;
  return mean;
}

}  // namespace mps_lab::testing
