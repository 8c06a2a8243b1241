#pragma once
// The load on obstacles as the fluid's pressure over their wetted surface, the same for every method
// and boundary model (wall particles or wall samples). A method whose load is of kind FluidPressure
// (Method::obstacle_load_kind(): mps's default obstacle_load fluid_pressure, and its wall_pressure
// with wall samples, which have no pressure of their own; docs/walls.md "Loads on obstacles") gets
// it from the driver:
//   F_k = - sum over the surface points x_e of obstacle k of  p_e n_e s_e        (N/m)
//   T_k =   sum (x_e - c_k) x (-p_e n_e s_e)                                     (N)
// n_e the outward normal (into the fluid), s_e the length a point stands for (points at most l0/4
// apart along each surface segment, as a transducer's face: core/run/pressure_sensors.hpp), and
// p_e = max(0, p_w(x_e)) the pressure of the fluid in front of the face carried to it by Adami,
// Hu & Adams (2012) eq. 27 with the wall's acceleration (core/walls/wall_pressure_extrapolation.hpp;
// cubic spline, support 2.4 l0, the transducers' kernel). Only the fluid in front of the face,
// (x_f - x_e) . n_e > 0, enters its sums: a thin solid's other side is not this face's water. A
// point with no fluid in reach reads 0 (dry); a negative reading is 0 (a wall does not pull on the
// water, as mps's wall-particle load, methods/mps/mps_loads.hpp); a point whose face stands
// against another solid (the point one spacing out along n_e lies inside a solid: a box's foot on
// the bed) carries nothing.
//
// The fluid does not receive -F_k exactly: it receives the method's wall terms.
// The check is physical (still water: Archimedes and rho g h^2 / 2; a floating body's mean load
// equals its weight), not the bits of a pair reaction.
#include <vector>

#include "core/base/particles.hpp"
#include "core/io/scene.hpp"
#include "core/kernels/sph_kernels.hpp"
#include "core/search/point_grid.hpp"
#include "core/walls/obstacle_loads.hpp"
#include "core/walls/wall_geometry.hpp"

namespace mps_lab {

class SurfacePressureLoads {
 public:
  explicit SurfacePressureLoads(const Scene& scene);

  // Adds the pressure load of the fluid on every obstacle to `loads` (references already set,
  // core/walls/obstacle_membership.hpp), at the obstacles' poses in particles.obstacle_pose (moving
  // obstacles; fixed ones where the scene puts them). Reads particles.pressure of the fluid.
  void add(const ParticleSet& particles, ObstacleLoads& loads);

  // The surface points of the last add(), for tests: position, outward normal, length (m) and the
  // pressure read there (Pa), per point; obstacle index per point.
  struct Point {
    Vec2 position = Vec2::Zero();
    Vec2 normal = Vec2::Zero();
    double length = 0.0;
    double pressure = 0.0;
    std::size_t obstacle = 0;
    std::size_t segment = 0;  // in the geometry's segments
  };
  const std::vector<Point>& points() const { return points_; }

 private:
  void place_points();
  void read_pressures(const ParticleSet& particles);

  WallGeometry geometry_;
  SphKernel kernel_;
  double spacing_;  // l0, m
  double density_;  // rho, kg/m^3
  Vec2 gravity_;    // m/s^2
  std::vector<Point> points_;
  PointGrid grid_;
};

}  // namespace mps_lab
