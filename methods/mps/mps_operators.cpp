#include "methods/mps/mps_operators.hpp"

#include <algorithm>
#include <cstddef>

#include <cmath>
#include <limits>

#include "core/search/for_each_neighbour.hpp"
#include "core/walls/wall_reactions.hpp"

namespace mps_lab::mps {

namespace {

// P_min,i of spec §2: the minimum pressure over the neighbours that enter the gradient's sum (within
// re, pressure-carrying, and the wall samples' p_w) and i itself when `min_includes_self`, as in
// K&O 1996; +infinity when there is none. Shared by the gradient and by neighbourhood_minimum (the
// wall side of the reaction, CMPS's Phat), so that both see the same P_min.
double minimum_pressure_of(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                           const OperatorRadius& radius, const std::vector<char>& carries_pressure, double density,
                           const Vec2& gravity, bool min_includes_self, std::size_t i, const DryWallRule& dry) {
  const Vec2 xi = particles.position[i];
  double p_min = min_includes_self ? particles.pressure[i] : std::numeric_limits<double>::infinity();
  for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
    if (!carries_pressure[j] || particles.type[j] == ParticleType::Ghost) return;
    if ((particles.position[j] - xi).norm() >= radius.re || dry.excludes_particle(particles, i, j)) return;
    p_min = std::min(p_min, particles.pressure[j]);
  });
  for_each_neighbour(samples, i, [&](const WallSample& wall) {
    if ((wall.position - xi).norm() >= radius.re) return;
    const double p_w = sample_pressure(wall, particles.pressure, particles.position, density, gravity);
    if (dry.excludes(xi, wall.position, p_w)) return;
    p_min = std::min(p_min, p_w);
  });
  return p_min;
}

}  // namespace

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
  const double coefficient = laplacian_coefficient(radius, kinematic_viscosity);  // 1/s
  for_each_fluid_particle(particles, [&](std::ptrdiff_t i) {
    Vec2 sum = Vec2::Zero();
    for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
      if (particles.type[j] != ParticleType::Ghost) sum += laplacian_pair(particles, i, j, radius);
    });
    for_each_neighbour(samples, i,
                       [&](const WallSample& wall) { sum += laplacian_sample_pair(particles, i, wall, radius); });
    acceleration[i] += coefficient * sum;
  });
}

void pressure_acceleration(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                           const OperatorRadius& radius, const std::vector<char>& carries_pressure, double density,
                           const Vec2& gravity, bool min_includes_self, std::vector<Vec2>& acceleration,
                           const DryWallRule& dry) {
  const double coefficient = kDimension / radius.n0;
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    acceleration[i] = Vec2::Zero();
    if (particles.type[i] != ParticleType::Fluid) continue;
    const double p_min = minimum_pressure_of(particles, neighbours, samples, radius, carries_pressure, density, gravity,
                                             min_includes_self, i, dry);
    Vec2 gradient = Vec2::Zero();  // Pa/m
    for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
      if (!carries_pressure[j] || particles.type[j] == ParticleType::Ghost) return;
      if (dry.excludes_particle(particles, i, j)) return;  // in the air (dry_wall_points excluded)
      gradient += gradient_pair(particles, i, j, p_min, radius);
    });
    for_each_neighbour(samples, i, [&](const WallSample& wall) {
      if (dry.excludes_sample(particles, i, wall)) return;
      gradient += gradient_sample_pair(particles, i, wall, p_min, radius, density, gravity);
    });
    acceleration[i] = -(coefficient / density) * gradient;
  }
}

void neighbourhood_minimum(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                           const OperatorRadius& radius, const std::vector<char>& carries_pressure, double density,
                           const Vec2& gravity, bool min_includes_self, std::vector<double>& out,
                           const DryWallRule& dry) {
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
  out.assign(particles.size(), 0.0);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (!carries_pressure[i] || particles.type[i] == ParticleType::Ghost) continue;
    const double p_min = minimum_pressure_of(particles, neighbours, samples, radius, carries_pressure, density, gravity,
                                             min_includes_self, i, dry);
    out[i] = std::isfinite(p_min) ? p_min : particles.pressure[i];  // no neighbour: no pair term either
  }
}

void add_viscous_wall_reactions(const ParticleSet& particles, const NeighbourList& neighbours,
                                const OperatorRadius& radius, double kinematic_viscosity, double particle_mass,
                                std::vector<Vec2>& reaction) {
  // The force on i from j: m nu (2d / (n0 lambda)) (u_j - u_i) w_ij (add_viscous_acceleration).
  const double coefficient = laplacian_coefficient(radius, kinematic_viscosity);  // 1/s
  add_wall_reactions(
      particles, neighbours,
      [&](std::size_t i, std::size_t j) -> Vec2 {
        return (particle_mass * coefficient) * laplacian_pair(particles, i, j, radius);
      },
      reaction);
}

void add_pressure_wall_reactions(const ParticleSet& particles, const NeighbourList& neighbours,
                                 const OperatorRadius& radius, const std::vector<char>& carries_pressure,
                                 const std::vector<double>& minimum_pressure, bool cmps, double density,
                                 double particle_mass, std::vector<Vec2>& reaction,
                                 const std::vector<Eigen::Matrix2d>* correction, const DryWallRule& dry) {
  // The force on i from j: -m (d / (n0 rho)) times the pair term of <grad P>_i (pressure_acceleration),
  // times C_i with the gradient correction.
  const double coefficient = -particle_mass * kDimension / (radius.n0 * density);  // kg m/(m Pa), per metre
  add_wall_reactions(
      particles, neighbours,
      [&](std::size_t i, std::size_t j) -> Vec2 {
        if (!carries_pressure[j] || dry.excludes_particle(particles, i, j)) return Vec2::Zero();
        const Vec2 pair = coefficient * (cmps ? cmps_gradient_pair(particles, i, j, minimum_pressure, radius)
                                              : gradient_pair(particles, i, j, minimum_pressure[i], radius));
        return correction != nullptr ? Vec2((*correction)[i] * pair) : pair;
      },
      reaction);
}

void add_viscous_sample_reactions(const ParticleSet& particles, const WallSampleList& samples,
                                  const OperatorRadius& radius, double kinematic_viscosity, double particle_mass,
                                  std::vector<Vec2>& scratch, WallSampleLoads& loads) {
  // The force on i from sample w: m nu (2d / (n0 lambda)) V_w (u_w - u_i) w_iw (add_viscous_acceleration).
  const double coefficient = laplacian_coefficient(radius, kinematic_viscosity);  // 1/s
  add_wall_sample_reactions(
      particles, samples,
      [&](std::size_t i, std::uint32_t, const WallSample& wall) -> Vec2 {
        return (particle_mass * coefficient) * laplacian_sample_pair(particles, i, wall, radius);
      },
      scratch, loads);
}

void add_pressure_sample_reactions(const ParticleSet& particles, const WallSampleList& samples,
                                   const OperatorRadius& radius, const std::vector<double>& minimum_pressure, bool cmps,
                                   double density, const Vec2& gravity, double particle_mass,
                                   std::vector<Vec2>& scratch, WallSampleLoads& loads,
                                   const std::vector<Eigen::Matrix2d>* correction, const DryWallRule& dry) {
  // The force on i from sample w: -m (d / (n0 rho)) times the sample's pair term of <grad P>_i
  // (times C_i with the gradient correction).
  const double coefficient = -particle_mass * kDimension / (radius.n0 * density);  // per metre of depth
  add_wall_sample_reactions(
      particles, samples,
      [&](std::size_t i, std::uint32_t, const WallSample& wall) -> Vec2 {
        if (dry.excludes_sample(particles, i, wall)) return Vec2::Zero();
        const Vec2 pair =
            coefficient *
            (cmps ? cmps_gradient_sample_pair(particles, i, wall, minimum_pressure[i], radius, density, gravity)
                  : gradient_sample_pair(particles, i, wall, minimum_pressure[i], radius, density, gravity));
        return correction != nullptr ? Vec2((*correction)[i] * pair) : pair;
      },
      scratch, loads);
}

}  // namespace mps_lab::mps
