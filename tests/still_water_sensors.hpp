#pragma once
// The still-water tank's wall sensors for one method with every boundary model it supports
// (tests/test_dfsph_wall_pressure.cpp, tests/test_isph_surface.cpp): scenes/hydrostatic.json
// with `overrides`, the sensors of tests/test_pressure_sensors.cpp (left wall surface
// x = 0.0125 m, depths h = 0.225 / 0.15 / 0.075 m below the lattice's top edge y = 0.2875 m),
// their record's mean over [0.5 s, end_time] against rho g h: calls check(model, h, ratio) for
// each of the 3 x (number of models) sensors. `gravity` (m/s^2) is the tank frame's g.
#include <string>
#include <vector>

#include "core/run/driver.hpp"
#include "core/walls/wall_treatment.hpp"
#include "support.hpp"

namespace mps_lab::testing {

template <class Check>
void still_water_wall_sensors(const std::string& method_name, const std::vector<std::string>& overrides,
                              double end_time, Check check, double gravity = 9.81) {
  const MethodInfo& method = *registries().methods.find(method_name);
  const std::vector<double> heights = {0.0625, 0.1375, 0.2125};  // m, sensor centres
  std::string sensors = "diagnostics.pressure_sensors=[";
  for (std::size_t k = 0; k < heights.size(); ++k) {
    sensors += std::string(k > 0 ? "," : "") + "{\"name\": \"s" + std::to_string(k) + "\", \"position\": [0.0125, " +
               std::to_string(heights[k]) + "]}";
  }
  sensors += "]";
  for (const auto* wall : registries().walls.all()) {
    if (wall->role != WallTreatmentRole::Boundary || !wall_treatment_supports(*wall, method)) continue;
    std::vector<std::string> all = overrides;
    all.push_back("methods." + method_name + ".wall_treatments={\"" + wall->name + "\":{}}");
    all.push_back(sensors);
    all.push_back("time.end_time=" + std::to_string(end_time));
    all.push_back("physics.gravity=[0, " + std::to_string(-gravity) + "]");
    const Scene scene = load("hydrostatic.json", all);  // the Simulation keeps a reference to it
    Simulation simulation(scene, method);
    simulation.run_to(0.5);
    simulation.pressure_sensors().take_row(simulation.particles());
    simulation.run_to(end_time);
    const std::vector<double> row = simulation.pressure_sensors().take_row(simulation.particles());
    REQUIRE(row.size() == 2 * heights.size());  // mean and peak per sensor
    for (std::size_t k = 0; k < heights.size(); ++k) {
      const double depth = 0.2875 - heights[k];
      check(wall->name, depth, row[2 * k] / (1000.0 * gravity * depth));
    }
  }
}

}  // namespace mps_lab::testing
