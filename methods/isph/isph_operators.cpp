#include "methods/isph/isph_operators.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <stdexcept>

#include <Eigen/LU>

#include "core/search/for_each_neighbour.hpp"
#include "core/walls/wall_reactions.hpp"
#include "core/walls/wall_sample_pressure.hpp"

namespace mps_lab::isph {

namespace {
// det of the moment matrix below which the renormalisation is not applied. The matrix is the
// identity for a particle with full support and has det ~0.3 on a flat free surface (half
// support); it degenerates only for a particle with almost no neighbours (a lone splash
// particle), whose corrected gradient would amplify noise: it keeps the difference form.
constexpr double kMinimumMomentDeterminant = 0.1;
}  // namespace

void summation_density(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                       const SphKernel& kernel, double mass, double rest_density, std::vector<double>& density) {
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
  density.resize(particles.size());
  const double self = kernel.value(0.0);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (particles.type[i] != ParticleType::Fluid) {
      density[i] = particles.type[i] == ParticleType::Wall ? rest_density : 0.0;
      continue;
    }
    double sum = self;
    for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
      if (particles.type[j] == ParticleType::Ghost) return;
      sum += kernel.value((particles.position[i] - particles.position[j]).norm());
    });
    for_each_neighbour(samples, i, [&](const WallSample& wall) {
      sum += wall.volume * kernel.value((particles.position[i] - wall.position).norm());  // mass m V_w
    });
    density[i] = mass * sum;  // rho_i = sum_j m_j W_ij (Monaghan 1992, summation density)
  }
}

void ppe_laplacian(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                   const SphKernel& kernel, double mass, const std::vector<double>& density, double rest_density,
                   const Vec2& head, double eta2, const std::vector<double>& values, std::vector<double>& out) {
  out.assign(particles.size(), 0.0);
  for_each_fluid_particle(particles, [&](std::ptrdiff_t i) {
    double sum = 0.0;
    for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
      if (particles.type[j] == ParticleType::Ghost) return;
      const double factor = laplacian_pair_factor(kernel, particles.position[i] - particles.position[j], eta2);
      // Cummins & Rudman (1999) / Shao & Lo (2003): sum_j m 8/(rho_i+rho_j)^2 (p_i - p_j) F_ij
      sum += ppe_pair_coefficient(mass, density[i], density[j], factor) * (values[j] - values[i]);
    });
    for_each_neighbour(samples, i, [&](const WallSample& wall) {
      if (particles.type[wall.source] == ParticleType::Ghost) return;
      const double factor = laplacian_pair_factor(kernel, particles.position[i] - wall.position, eta2);
      const double value = values[wall.source] + head.dot(wall.position - particles.position[wall.source]);
      sum += ppe_pair_coefficient(mass * wall.volume, density[i], rest_density, factor) * (value - values[i]);
    });
    out[i] = sum;
  });
}

void add_viscous_acceleration(const ParticleSet& particles, const NeighbourList& neighbours,
                              const WallSampleList& samples, const SphKernel& kernel, double mass,
                              const std::vector<double>& density, double rest_density, double kinematic_viscosity,
                              double eta2, std::vector<Vec2>& acceleration) {
  for_each_fluid_particle(particles, [&](std::ptrdiff_t i) {
    Vec2 sum = Vec2::Zero();
    for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
      // Morris et al. (1997) viscous term, mu = rho nu: m (mu_i + mu_j)/(rho_i rho_j) F_ij (u_i - u_j)
      if (particles.type[j] != ParticleType::Ghost) sum += viscous_pair(particles, kernel, mass, density, eta2, i, j);
    });
    for_each_neighbour(samples, i, [&](const WallSample& wall) {
      if (particles.type[wall.source] == ParticleType::Ghost) return;
      sum += viscous_sample_pair(particles, kernel, mass, density, rest_density, eta2, i, wall);
    });
    acceleration[i] += kinematic_viscosity * sum;
  });
}

void velocity_divergence(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                         const SphKernel& kernel, double mass, const std::vector<double>& density,
                         const std::vector<Vec2>& velocity, const Vec2& sample_base_velocity,
                         double sample_base_time_step, std::vector<double>& out) {
  out.assign(particles.size(), 0.0);
  for_each_fluid_particle(particles, [&](std::ptrdiff_t i) {
    double sum = 0.0;
    for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
      if (particles.type[j] == ParticleType::Ghost) return;
      // div u_i = (1/rho_i) sum_j m (u_j - u_i) . grad W_ij (Monaghan 1992; Cummins & Rudman 1999)
      sum += mass * (velocity[j] - velocity[i]).dot(kernel.gradient(particles.position[i] - particles.position[j]));
    });
    for_each_neighbour(samples, i, [&](const WallSample& wall) {
      if (particles.type[wall.source] == ParticleType::Ghost) return;
      // b - dt a_w + M (u_s - (b - dt a_w)) + (I - M) u_wall: relative to a moving wall's predicted motion
      const Vec2 base = sample_base_velocity - sample_base_time_step * wall.wall_acceleration;
      const Vec2 u_w = base + wall.velocity_map * (velocity[wall.source] - base) + wall.wall_velocity;
      sum += mass * wall.volume * (u_w - velocity[i]).dot(kernel.gradient(particles.position[i] - wall.position));
    });
    out[i] = sum / density[i];
  });
}

void position_divergence(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                         const SphKernel& kernel, double mass, const std::vector<double>& density, double rest_density,
                         std::vector<double>& out) {
  out.assign(particles.size(), 0.0);
  for_each_fluid_particle(particles, [&](std::ptrdiff_t i) {
    double sum = 0.0;
    for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
      if (particles.type[j] == ParticleType::Ghost) return;
      const Vec2 r_ij = particles.position[i] - particles.position[j];
      // div r_i = -sum_j (m/rho_j) r_ij . grad W_ij (Lee et al. 2008)
      sum -= mass / density[j] * r_ij.dot(kernel.gradient(r_ij));
    });
    for_each_neighbour(samples, i, [&](const WallSample& wall) {
      const Vec2 r_iw = particles.position[i] - wall.position;
      sum -= mass * wall.volume / rest_density * r_iw.dot(kernel.gradient(r_iw));
    });
    out[i] = sum;
  });
}

PressureGradientForm pressure_gradient_form_from_name(const std::string& name) {
  if (name == "symmetric") return PressureGradientForm::Symmetric;
  if (name == "difference") return PressureGradientForm::Difference;
  if (name == "corrected") return PressureGradientForm::Corrected;
  if (name == "symmetric_corrected_surface") return PressureGradientForm::SymmetricCorrectedSurface;
  throw std::invalid_argument("unknown pressure gradient form '" + name +
                              "' (expected symmetric, difference, corrected or symmetric_corrected_surface)");
}

ParameterSpec wall_sample_pressure_parameter() {
  return string_parameter("wall_sample_pressure", "own",
                          "what a wall sample extends to the wall point: own (its source particle's pressure) or "
                          "fitted (the linear MLS fit of the fluid pressure about the source: for loads; boundary "
                          "models of wall samples, docs/methods/isph.md)")
      .one_of({"own", "fitted"});
}

bool fits_wall_sample_pressure(const ParameterValues& parameters) {
  return parameters.string("wall_sample_pressure") == "fitted";
}

SamplePressure with_source_pressure(SamplePressure rule, const ParticleSet& particles, const NeighbourList& neighbours,
                                    const WallSampleList& samples, const SphKernel& kernel, bool fit,
                                    std::vector<double>& fitted) {
  if (!fit || !samples.has_samples()) return rule;
  fit_source_pressures(
      particles, neighbours, [&](double r) { return kernel.value(r); }, particles.pressure, fitted);
  rule.source_pressure = &fitted;
  return rule;
}

void pressure_acceleration(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                           const SamplePressure& sample_rule, const SphKernel& kernel, double mass,
                           const std::vector<double>& density, const std::vector<double>& free_surface,
                           PressureGradientForm form, std::vector<Vec2>& acceleration,
                           std::vector<Eigen::Matrix2d>* renormalisation) {
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
  acceleration.resize(particles.size());
  if (renormalisation != nullptr) renormalisation->assign(particles.size(), Eigen::Matrix2d::Identity());
  const double rho_w = sample_rule.rest_density;
  const DryWallRule dry = sample_rule.dry_rule();
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    acceleration[i] = Vec2::Zero();
    if (particles.type[i] != ParticleType::Fluid) continue;
    const bool corrected = corrected_gradient(form, free_surface[i]);
    const bool symmetric = symmetric_gradient(form, free_surface[i]);
    Vec2 sum = Vec2::Zero();                           // grad p_i / rho_i, m/s^2
    Eigen::Matrix2d moment = Eigen::Matrix2d::Zero();  // sum_j V_j grad W_ij (x_j - x_i)^T
    for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
      if (particles.type[j] == ParticleType::Ghost) return;
      if (dry.excludes_particle(particles, static_cast<std::size_t>(i), j)) return;  // in the air (dry_wall_points)
      sum += pressure_pair(particles, kernel, mass, density, symmetric, i, j);       // symmetric or difference form
      if (!symmetric) {
        const Vec2 r_ij = particles.position[i] - particles.position[j];
        moment -= mass / density[j] * kernel.gradient(r_ij) * r_ij.transpose();
      }
    });
    // Wall samples: particles of mass m V_w, density rho0, pressure p_s + rho0 g . (x_w - x_s).
    for_each_neighbour(samples, i, [&](const WallSample& wall) {
      if (particles.type[wall.source] == ParticleType::Ghost) return;
      if (sample_rule.excludes_sample(particles, static_cast<std::size_t>(i), wall)) return;
      sum += pressure_sample_pair(particles, sample_rule, kernel, mass, density, symmetric, i, wall);
      if (!symmetric) {
        const Vec2 r_iw = particles.position[i] - wall.position;
        moment -= mass * wall.volume / rho_w * kernel.gradient(r_iw) * r_iw.transpose();
      }
    });
    if (corrected && std::fabs(moment.determinant()) > kMinimumMomentDeterminant) {
      // Bonet & Lok (1999) renormalisation: grad p_i = L_i sum_j V_j (p_j - p_i) grad W_ij, L_i = moment^-1
      const Eigen::Matrix2d inverse = moment.inverse();
      sum = inverse * sum;
      if (renormalisation != nullptr) (*renormalisation)[i] = inverse;
    }
    acceleration[i] = -sum;
  }
}

void add_pressure_wall_reactions(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                                 double mass, const std::vector<double>& density,
                                 const std::vector<double>& free_surface, PressureGradientForm form,
                                 const std::vector<Eigen::Matrix2d>& renormalisation, std::vector<Vec2>& reaction,
                                 const SamplePressure& rule) {
  // The force on i from j: m a_ij = -m L_i pressure_pair(i, j) (pressure_acceleration).
  const DryWallRule dry = rule.dry_rule();
  add_wall_reactions(
      particles, neighbours,
      [&](std::size_t i, std::size_t j) -> Vec2 {
        if (dry.excludes_particle(particles, i, j)) return Vec2::Zero();
        const bool symmetric = symmetric_gradient(form, free_surface[i]);
        return -mass * (renormalisation[i] * pressure_pair(particles, kernel, mass, density, symmetric, i, j));
      },
      reaction);
}

void add_viscous_wall_reactions(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                                double mass, const std::vector<double>& density, double kinematic_viscosity,
                                double eta2, std::vector<Vec2>& reaction) {
  // The force on i from j: m nu viscous_pair(i, j) (add_viscous_acceleration).
  add_wall_reactions(
      particles, neighbours,
      [&](std::size_t i, std::size_t j) -> Vec2 {
        return (mass * kinematic_viscosity) * viscous_pair(particles, kernel, mass, density, eta2, i, j);
      },
      reaction);
}

void add_pressure_sample_reactions(const ParticleSet& particles, const WallSampleList& samples,
                                   const SamplePressure& rule, const SphKernel& kernel, double mass,
                                   const std::vector<double>& density, const std::vector<double>& free_surface,
                                   PressureGradientForm form, const std::vector<Eigen::Matrix2d>& renormalisation,
                                   std::vector<Vec2>& scratch, WallSampleLoads& loads) {
  // The force on i from sample w: m a_iw = -m L_i pressure_sample_pair(i, w) (pressure_acceleration).
  add_wall_sample_reactions(
      particles, samples,
      [&](std::size_t i, std::uint32_t, const WallSample& wall) -> Vec2 {
        if (particles.type[wall.source] == ParticleType::Ghost || rule.excludes_sample(particles, i, wall))
          return Vec2::Zero();
        const bool symmetric = symmetric_gradient(form, free_surface[i]);
        return -mass *
               (renormalisation[i] * pressure_sample_pair(particles, rule, kernel, mass, density, symmetric, i, wall));
      },
      scratch, loads);
}

void add_viscous_sample_reactions(const ParticleSet& particles, const WallSampleList& samples, const SphKernel& kernel,
                                  double mass, const std::vector<double>& density, double rest_density,
                                  double kinematic_viscosity, double eta2, std::vector<Vec2>& scratch,
                                  WallSampleLoads& loads) {
  // The force on i from sample w: m nu viscous_sample_pair(i, w) (add_viscous_acceleration).
  add_wall_sample_reactions(
      particles, samples,
      [&](std::size_t i, std::uint32_t, const WallSample& wall) -> Vec2 {
        if (particles.type[wall.source] == ParticleType::Ghost) return Vec2::Zero();
        return (mass * kinematic_viscosity) *
               viscous_sample_pair(particles, kernel, mass, density, rest_density, eta2, i, wall);
      },
      scratch, loads);
}

}  // namespace mps_lab::isph
