#pragma once
// Wall pressure measured like a transducer (scene key diagnostics.pressure_sensors,
// docs/scene-format.md, docs/validation.md "Wall pressure").
//
// A sensor is a face on a wall surface: a segment of length `diameter` centred on its
// position, along the wall segment it lies on (core/walls/wall_geometry.hpp: the surface is
// l0/2 from the first wall layer). Its reading is the same for every method and boundary
// model, computed from the fluid next to the wall: at sample points spread evenly across
// the face, the extrapolation of Adami, Hu & Adams (2012, J. Comput. Phys. 231, eq. 27)
//   p_w = [ sum_f p_f W(r_wf) + (g - a_w) . sum_f rho_f r_wf W(r_wf) ] / sum_f W(r_wf),
//   r_wf = x_w - x_f,
// over the fluid particles f within the kernel's support of the wall point x_w, with a_w the
// wall's acceleration; a point with no fluid in reach reads 0 (dry), and the face reads the
// mean of its points. rho_f is the reference density: every method here is incompressible
// (the common density error stays below 1 %).
//
// The sensors are sampled after every step (Simulation::advance); a series row takes the
// time-weighted mean since the previous row and the peak (pressure_<name>,
// pressure_<name>_max) and starts the next interval. The interval's sums are part of a
// checkpoint, so a resumed run records the same rows bit for bit.
#include <limits>
#include <string>
#include <vector>

#include "core/base/particles.hpp"
#include "core/base/types.hpp"
#include "core/io/scene.hpp"
#include "core/kernels/sph_kernels.hpp"
#include "core/search/point_grid.hpp"
#include "core/walls/wall_pressure_extrapolation.hpp"  // wall_pressure_kernel

namespace mps_lab {

class CheckpointWriter;
class CheckpointReader;

// Adami et al. (2012) eq. 27 at the wall point x_w (see above) with `kernel` (wall_pressure_kernel,
// core/walls/wall_pressure_extrapolation.hpp); `body_force` is g - a_w
// (m/s^2), `density` rho_f (kg/m^3). 0 when no fluid particle lies within the support.
double extrapolated_wall_pressure(const ParticleSet& particles, const Vec2& wall_point, const Vec2& body_force,
                                  double density, const SphKernel& kernel);

// Where a sensor's face is: its sample points on the wall surface and the wall's normal.
struct SensorFace {
  std::string name;
  std::vector<Vec2> points;  // m, evenly across the face (centres of equal parts, at most l0/4 apart)
  Vec2 normal = Vec2::Zero();
};

// The faces of the scene's sensors; the scene guarantees each lies on a wall surface
// (core/io/scene.cpp, check_pressure_sensors).
std::vector<SensorFace> sensor_faces(const Scene& scene);

// Sensor faces with all their points in one grid, so that every face is read in one pass over
// the fluid (core/walls/wall_pressure_extrapolation.hpp): the same bits as
// extrapolated_wall_pressure at each point, without a pass over the particles per point.
class SensorReadout {
 public:
  SensorReadout(const Scene& scene, std::vector<SensorFace> faces);

  const std::vector<SensorFace>& faces() const { return faces_; }
  // Every face's reading now (Pa): the mean of its points', the walls accelerating at
  // `wall_acceleration` (m/s^2; zero for today's fixed walls; a moving wall passes its own).
  std::vector<double> read(const ParticleSet& particles, const Vec2& wall_acceleration = Vec2::Zero()) const;

 private:
  std::vector<SensorFace> faces_;
  PointGrid points_;  // every face's points, face after face
  SphKernel kernel_;
  double density_;  // kg/m^3
  Vec2 gravity_;    // m/s^2
};

// Every sensor's face-averaged reading now (Pa): SensorReadout(scene, faces).read(...).
std::vector<double> read_pressure_sensors(const ParticleSet& particles, const Scene& scene,
                                          const std::vector<SensorFace>& faces,
                                          const Vec2& wall_acceleration = Vec2::Zero());

// The readings of the steps since the last series row.
class PressureSensorRecord {
 public:
  explicit PressureSensorRecord(const Scene& scene);

  std::size_t count() const { return readout_.faces().size(); }
  const std::vector<SensorFace>& faces() const { return readout_.faces(); }
  // Reads every sensor after a step of `dt` seconds and adds it to the interval.
  void sample(const ParticleSet& particles, double dt);
  // The row's values, (mean, peak) per sensor in scene order, and a new interval. An interval
  // without a step (the row at t = 0) gives the instantaneous reading as both.
  std::vector<double> take_row(const ParticleSet& particles);

  void save(CheckpointWriter& out) const;
  void restore(CheckpointReader& in);

 private:
  SensorReadout readout_;
  std::vector<double> weighted_sum_;  // Pa s: sum of reading x dt over the interval
  std::vector<double> peak_;          // Pa
  double duration_ = 0.0;             // s
};

}  // namespace mps_lab
