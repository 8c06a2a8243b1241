#include "methods/mps/mps_operators.hpp"

#include <algorithm>
#include <cstddef>

#include "core/search/for_each_neighbour.hpp"

namespace mps_lab::mps {

OperatorRadius make_operator_radius(double spacing, double re, double r_min) {
  const MpsLatticeConstants lattice = mps_lattice_constants(spacing, re, r_min);
  return {re, r_min, lattice.number_density, lattice.lambda};
}

void number_density(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                    const OperatorRadius& radius, std::vector<double>& out) {
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
  out.resize(particles.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    double sum = 0.0;
    if (particles.type[i] != ParticleType::Ghost) {
      for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
        if (particles.type[j] == ParticleType::Ghost) return;
        sum += mps_weight((particles.position[j] - particles.position[i]).norm(), radius.re, radius.r_min);
      });
      for_each_neighbour(samples, i, [&](const WallSample& wall) {
        sum += wall.volume * mps_weight((wall.position - particles.position[i]).norm(), radius.re, radius.r_min);
      });
    }
    out[i] = sum;
  }
}

void add_viscous_acceleration(const ParticleSet& particles, const NeighbourList& neighbours,
                              const WallSampleList& samples, const OperatorRadius& radius, double kinematic_viscosity,
                              std::vector<Vec2>& acceleration) {
  const double coefficient = kinematic_viscosity * 2.0 * kDimension / (radius.n0 * radius.lambda);  // 1/s
  for_each_fluid_particle(particles, [&](std::ptrdiff_t i) {
    Vec2 sum = Vec2::Zero();
    for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
      if (particles.type[j] == ParticleType::Ghost) return;
      const double w = mps_weight((particles.position[j] - particles.position[i]).norm(), radius.re, radius.r_min);
      sum += (particles.velocity[j] - particles.velocity[i]) * w;
    });
    for_each_neighbour(samples, i, [&](const WallSample& wall) {
      const double w = mps_weight((wall.position - particles.position[i]).norm(), radius.re, radius.r_min);
      sum += wall.volume * (sample_velocity(wall, particles.velocity) - particles.velocity[i]) * w;
    });
    acceleration[i] += coefficient * sum;
  });
}

void pressure_acceleration(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                           const OperatorRadius& radius, const std::vector<char>& carries_pressure, double density,
                           const Vec2& gravity, bool min_includes_self, std::vector<Vec2>& acceleration) {
  const double coefficient = kDimension / radius.n0;
  const double r_min2 = radius.r_min * radius.r_min;
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    acceleration[i] = Vec2::Zero();
    if (particles.type[i] != ParticleType::Fluid) continue;
    const Vec2 xi = particles.position[i];
    // P_min over the neighbours that enter the sum (and i itself, as in K&O 1996).
    double p_min = min_includes_self ? particles.pressure[i] : std::numeric_limits<double>::infinity();
    for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
      if (!carries_pressure[j] || particles.type[j] == ParticleType::Ghost) return;
      if ((particles.position[j] - xi).norm() >= radius.re) return;
      p_min = std::min(p_min, particles.pressure[j]);
    });
    for_each_neighbour(samples, i, [&](const WallSample& wall) {
      if ((wall.position - xi).norm() >= radius.re) return;
      p_min = std::min(p_min, sample_pressure(wall, particles.pressure, particles.position, density, gravity));
    });
    Vec2 gradient = Vec2::Zero();  // Pa/m
    for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
      if (!carries_pressure[j] || particles.type[j] == ParticleType::Ghost) return;
      const Vec2 r_ij = particles.position[j] - xi;
      const double r = r_ij.norm();
      const double w = mps_weight(r, radius.re, radius.r_min);
      if (w == 0.0) return;
      gradient += (particles.pressure[j] - p_min) / std::max(r * r, r_min2) * w * r_ij;
    });
    for_each_neighbour(samples, i, [&](const WallSample& wall) {
      const Vec2 r_iw = wall.position - xi;
      const double r = r_iw.norm();
      const double w = mps_weight(r, radius.re, radius.r_min);
      if (w == 0.0) return;
      const double p_w = sample_pressure(wall, particles.pressure, particles.position, density, gravity);
      gradient += wall.volume * (p_w - p_min) / std::max(r * r, r_min2) * w * r_iw;
    });
    acceleration[i] = -(coefficient / density) * gradient;
  }
}

}  // namespace mps_lab::mps
