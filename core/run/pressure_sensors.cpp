#include "core/run/pressure_sensors.hpp"

#include <algorithm>
#include <cmath>

#include "core/io/checkpoint.hpp"
#include "core/walls/wall_geometry.hpp"
#include "core/walls/wall_pressure_extrapolation.hpp"

namespace mps_lab {

namespace {

constexpr double kSampleSpacing = 0.25;  // l0: the largest distance between a face's sample points

// The wall segment a sensor lies on: the nearest one (the scene checked that the position is
// on it or behind it up to the first wall particle line, core/io/scene.cpp).
const WallSegment& sensor_segment(const WallGeometry& geometry, const Vec2& position) {
  std::size_t nearest = 0;
  geometry.distance(position, &nearest);
  return geometry.segments()[nearest];
}

}  // namespace

// Adami, Hu & Adams (2012), eq. 27 (core/walls/wall_pressure_extrapolation.hpp).
double extrapolated_wall_pressure(const ParticleSet& particles, const Vec2& wall_point, const Vec2& body_force,
                                  double density, const SphKernel& kernel) {
  const double support2 = kernel.support() * kernel.support();
  ExtrapolatedPressure sums;
  for (std::size_t f = 0; f < particles.size(); ++f) {
    if (particles.type[f] != ParticleType::Fluid) continue;
    const Vec2 r_wf = wall_point - particles.position[f];
    const double r2 = r_wf.squaredNorm();
    if (r2 >= support2) continue;
    sums.add(particles.pressure[f], r_wf, kernel.value(std::sqrt(r2)));
  }
  return sums.value(density, body_force);
}

std::vector<SensorFace> sensor_faces(const Scene& scene) {
  const WallGeometry geometry(scene);
  const double l0 = scene.particle_spacing;
  std::vector<SensorFace> faces;
  for (const auto& sensor : scene.diagnostics.pressure_sensors) {
    const WallSegment& segment = sensor_segment(geometry, sensor.position);
    const Vec2 tangent = (segment.b - segment.a).normalized();
    // The face along the surface, cut where the surface ends (a corner, an open side); then
    // parts of equal length, a sample point at the centre of each.
    const double along = tangent.dot(sensor.position - segment.a);
    const double from = std::max(0.0, along - 0.5 * sensor.diameter);
    const double to = std::min((segment.b - segment.a).norm(), along + 0.5 * sensor.diameter);
    const double length = std::max(0.0, to - from);
    const int parts = std::max(1, static_cast<int>(std::ceil(length / (kSampleSpacing * l0) - 1e-9)));
    SensorFace face{sensor.name, {}, segment.normal};
    for (int k = 0; k < parts; ++k) face.points.push_back(segment.a + (from + length * (k + 0.5) / parts) * tangent);
    faces.push_back(std::move(face));
  }
  return faces;
}

SensorReadout::SensorReadout(const Scene& scene, std::vector<SensorFace> faces)
    : faces_(std::move(faces)),
      kernel_(wall_pressure_kernel(scene.particle_spacing)),
      density_(scene.physics.density),
      gravity_(scene.physics.gravity) {
  std::vector<Vec2> points;
  for (const SensorFace& face : faces_) points.insert(points.end(), face.points.begin(), face.points.end());
  points_.build(std::move(points), kernel_.support());
}

// The face's reading: the mean of its points' extrapolated pressures (dry points count 0).
std::vector<double> SensorReadout::read(const ParticleSet& particles, const Vec2& wall_acceleration) const {
  std::vector<ExtrapolatedPressure> sums;
  sum_extrapolated_pressures(
      particles, points_, kernel_, [](std::uint32_t, const Vec2&) { return true; }, sums);
  const Vec2 body_force = gravity_ - wall_acceleration;  // g - a_w, m/s^2
  std::vector<double> readings;
  readings.reserve(faces_.size());
  std::size_t point = 0;
  for (const SensorFace& face : faces_) {
    double sum = 0.0;
    for (std::size_t k = 0; k < face.points.size(); ++k) sum += sums[point++].value(density_, body_force);
    readings.push_back(sum / static_cast<double>(face.points.size()));
  }
  return readings;
}

std::vector<double> read_pressure_sensors(const ParticleSet& particles, const Scene& scene,
                                          const std::vector<SensorFace>& faces, const Vec2& wall_acceleration) {
  return SensorReadout(scene, faces).read(particles, wall_acceleration);
}

PressureSensorRecord::PressureSensorRecord(const Scene& scene)
    : readout_(scene, sensor_faces(scene)),
      weighted_sum_(count(), 0.0),
      peak_(count(), -std::numeric_limits<double>::infinity()) {}

void PressureSensorRecord::sample(const ParticleSet& particles, double dt) {
  if (count() == 0) return;
  // Today's walls are fixed (a_w = 0).
  const std::vector<double> readings = readout_.read(particles);
  for (std::size_t k = 0; k < count(); ++k) {
    weighted_sum_[k] += readings[k] * dt;
    peak_[k] = std::max(peak_[k], readings[k]);
  }
  duration_ += dt;
}

std::vector<double> PressureSensorRecord::take_row(const ParticleSet& particles) {
  std::vector<double> row;
  row.reserve(2 * count());
  const std::vector<double> now = duration_ > 0.0 ? std::vector<double>() : readout_.read(particles);
  for (std::size_t k = 0; k < count(); ++k) {
    row.push_back(duration_ > 0.0 ? weighted_sum_[k] / duration_ : now[k]);
    row.push_back(duration_ > 0.0 ? peak_[k] : now[k]);
  }
  std::fill(weighted_sum_.begin(), weighted_sum_.end(), 0.0);
  std::fill(peak_.begin(), peak_.end(), -std::numeric_limits<double>::infinity());
  duration_ = 0.0;
  return row;
}

void PressureSensorRecord::save(CheckpointWriter& out) const {
  out.write_doubles(weighted_sum_);
  out.write_doubles(peak_);
  out.write_double(duration_);
}

void PressureSensorRecord::restore(CheckpointReader& in) {
  weighted_sum_ = in.read_doubles();
  peak_ = in.read_doubles();
  duration_ = in.read_double();
  if (weighted_sum_.size() != count() || peak_.size() != count()) {
    in.fail("pressure sensors: " + std::to_string(weighted_sum_.size()) + " in the checkpoint, the scene has " +
            std::to_string(count()));
  }
}

}  // namespace mps_lab
