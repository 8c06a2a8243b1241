#include "methods/mps/mps_schemes.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <stdexcept>

#include <Eigen/LU>

#include "core/search/for_each_neighbour.hpp"

namespace mps_lab::mps {

std::vector<std::string> pressure_gradient_choices() { return {"spec", "cmps"}; }
std::vector<std::string> source_term_choices() { return {"spec", "hs", "ecs", "mixed"}; }
std::vector<std::string> ppe_laplacian_choices() { return {"spec", "hl"}; }

PressureGradientScheme pressure_gradient_scheme(const std::string& value) {
  if (value == "spec") return PressureGradientScheme::Spec;
  if (value == "cmps") return PressureGradientScheme::Cmps;
  throw std::logic_error("mps: pressure_gradient '" + value + "' passed the parameter check");
}

SourceTermScheme source_term_scheme(const std::string& value) {
  if (value == "spec") return SourceTermScheme::Spec;
  if (value == "hs") return SourceTermScheme::Hs;
  if (value == "ecs") return SourceTermScheme::Ecs;
  if (value == "mixed") return SourceTermScheme::Mixed;
  throw std::logic_error("mps: source_term '" + value + "' passed the parameter check");
}

PpeLaplacianScheme ppe_laplacian_scheme(const std::string& value) {
  if (value == "spec") return PpeLaplacianScheme::Spec;
  if (value == "hl") return PpeLaplacianScheme::Hl;
  throw std::logic_error("mps: ppe_laplacian '" + value + "' passed the parameter check");
}

double higher_order_laplacian_coefficient(double r, const OperatorRadius& radius) {
  if (r >= radius.re) return 0.0;
  const double r_clamped = std::max(r, radius.r_min);
  // Khayyer & Gotoh (2010), 2-D: (1/n0) (d2w/dr2 + (1/r) dw/dr) = (1/n0) re / r^3
  return radius.re / (r_clamped * r_clamped * r_clamped) / radius.n0;
}

namespace {

// -(re / r^3) (r_ij . u_ij): one pair's dw_ij/dt (Khayyer & Gotoh 2009), 1/s.
double weight_rate(const Vec2& r_ij, const Vec2& u_ij, const OperatorRadius& radius) {
  const double r = r_ij.norm();
  if (r >= radius.re) return 0.0;
  const double r_clamped = std::max(r, radius.r_min);
  return -radius.re / (r_clamped * r_clamped * r_clamped) * r_ij.dot(u_ij);
}

// (u_ij . r_ij) / |r_ij|^2 w_ij: one pair's term of the MPS divergence, 1/s.
double divergence_term(const Vec2& r_ij, const Vec2& u_ij, const OperatorRadius& radius) {
  const double r = r_ij.norm();
  const double w = mps_weight(r, radius.re, radius.r_min);
  if (w == 0.0) return 0.0;
  return u_ij.dot(r_ij) / std::max(r * r, radius.r_min * radius.r_min) * w;
}

// sum_j pair(r_ij, u_ij) + sum_w V_w pair(r_iw, u_w - u_i) for every non-ghost particle.
template <class Pair>
void pair_sum(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples, Pair pair,
              std::vector<double>& out) {
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
  out.assign(particles.size(), 0.0);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (particles.type[i] == ParticleType::Ghost) continue;
    const Vec2 xi = particles.position[i];
    const Vec2 ui = particles.velocity[i];
    double sum = 0.0;
    for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
      if (particles.type[j] == ParticleType::Ghost) return;
      sum += pair(particles.position[j] - xi, particles.velocity[j] - ui);
    });
    for_each_neighbour(samples, i, [&](const WallSample& wall) {
      sum += wall.volume * pair(wall.position - xi, sample_velocity(wall, particles.velocity) - ui);
    });
    out[i] = sum;
  }
}

}  // namespace

void number_density_rate(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                         const OperatorRadius& radius, std::vector<double>& out) {
  // Khayyer & Gotoh (2009): Dn_i/Dt = sum_j Dw_ij/Dt = -sum_j (re / r_ij^3) (r_ij . u_ij)
  pair_sum(
      particles, neighbours, samples,
      [&](const Vec2& r_ij, const Vec2& u_ij) { return weight_rate(r_ij, u_ij, radius); }, out);
}

void velocity_divergence(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                         const OperatorRadius& radius, std::vector<double>& out) {
  // Koshizuka & Oka (1996): <div u>_i = (d/n0) sum_j (u_ij . r_ij) / |r_ij|^2 w_ij
  pair_sum(
      particles, neighbours, samples,
      [&](const Vec2& r_ij, const Vec2& u_ij) { return divergence_term(r_ij, u_ij, radius); }, out);
  const double coefficient = kDimension / radius.n0;
  for (double& value : out) value *= coefficient;
}

double source_term(SourceTermScheme scheme, const SourceTermInputs& in, std::size_t i) {
  const double deviation = (in.number_density[i] - in.n0) / in.n0;  // (n*_i - n0)/n0
  const double rate = in.rate[i];                                   // Dn/Dt or <div u*>, 1/s
  switch (scheme) {
    case SourceTermScheme::Hs:  // Khayyer & Gotoh (2009): (rho / (n0 dt)) Dn/Dt
      return in.density / (in.n0 * in.dt) * rate;
    case SourceTermScheme::Ecs: {  // Khayyer & Gotoh (2011): HS + alpha HS + beta (rho/dt^2)(n* - n0)/n0
      const double alpha = std::fabs(deviation);
      const double beta = std::fabs(in.dt * rate / in.n0);
      return in.density / (in.n0 * in.dt) * (1.0 + alpha) * rate + beta * in.density / (in.dt * in.dt) * deviation;
    }
    case SourceTermScheme::Mixed:  // Tanaka & Masunaga (2010): -(rho/dt) div u* + gamma (rho/dt^2)(n* - n0)/n0
      return -in.density / in.dt * rate + in.mixed_relaxation * in.density / (in.dt * in.dt) * deviation;
    case SourceTermScheme::Spec:
      break;
  }
  return 0.0;
}

void source_terms(SourceTermScheme scheme, const ParticleSet& particles, const NeighbourList& neighbours,
                  const WallSampleList& samples, const OperatorRadius& radius, const SourceTermInputs& in,
                  std::vector<double>& rate, std::vector<double>& out) {
  out.assign(particles.size(), 0.0);
  if (scheme == SourceTermScheme::Spec) return;
  if (scheme == SourceTermScheme::Mixed) {
    velocity_divergence(particles, neighbours, samples, radius, rate);
  } else {
    number_density_rate(particles, neighbours, samples, radius, rate);
  }
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] != ParticleType::Ghost) out[i] = source_term(scheme, in, i);
  }
}

void cmps_pressure_acceleration(const ParticleSet& particles, const NeighbourList& neighbours,
                                const WallSampleList& samples, const OperatorRadius& radius,
                                const std::vector<char>& carries_pressure, double density, const Vec2& gravity,
                                bool min_includes_self, std::vector<double>& minimum_pressure,
                                std::vector<Vec2>& acceleration, const DryWallRule& dry) {
  neighbourhood_minimum(particles, neighbours, samples, radius, carries_pressure, density, gravity, min_includes_self,
                        minimum_pressure, dry);
  const double coefficient = kDimension / radius.n0;
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    acceleration[i] = Vec2::Zero();
    if (particles.type[i] != ParticleType::Fluid) continue;
    const double p_hat_i = minimum_pressure[i];
    Vec2 gradient = Vec2::Zero();  // Pa/m
    for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
      if (!carries_pressure[j] || particles.type[j] == ParticleType::Ghost) return;
      if (dry.excludes_particle(particles, static_cast<std::size_t>(i), j)) return;
      gradient += cmps_gradient_pair(particles, i, j, minimum_pressure, radius);  // Khayyer & Gotoh (2008)
    });
    for_each_neighbour(samples, i, [&](const WallSample& wall) {
      if (dry.excludes_sample(particles, static_cast<std::size_t>(i), wall)) return;
      gradient += cmps_gradient_sample_pair(particles, i, wall, p_hat_i, radius, density, gravity);
    });
    acceleration[i] = -(coefficient / density) * gradient;
  }
}

// M_i of GC (Khayyer & Gotoh 2011): (d/n0) sum_j w_ij r_ij r_ij^T / |r_ij|^2, the neighbours and
// samples of the gradient (pressure_acceleration).
namespace {
Eigen::Matrix2d gradient_moment(const ParticleSet& particles, const NeighbourList& neighbours,
                                const WallSampleList& samples, const OperatorRadius& radius,
                                const std::vector<char>& carries_pressure, const DryWallRule& dry, std::size_t i) {
  Eigen::Matrix2d moment = Eigen::Matrix2d::Zero();
  const auto add = [&](const Vec2& r_ij, double volume) {
    const double r = r_ij.norm();
    const double w = mps_weight(r, radius.re, radius.r_min);
    if (w == 0.0) return;
    moment += (volume * w / std::max(r * r, radius.r_min * radius.r_min)) * (r_ij * r_ij.transpose());
  };
  for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
    if (!carries_pressure[j] || particles.type[j] == ParticleType::Ghost || dry.excludes_particle(particles, i, j))
      return;
    add(particles.position[j] - particles.position[i], 1.0);
  });
  for_each_neighbour(samples, i, [&](const WallSample& wall) {
    if (!dry.excludes_sample(particles, i, wall)) add(wall.position - particles.position[i], wall.volume);
  });
  return (kDimension / radius.n0) * moment;
}
}  // namespace

void gradient_correction_matrices(const ParticleSet& particles, const NeighbourList& neighbours,
                                  const WallSampleList& samples, const OperatorRadius& radius,
                                  const std::vector<char>& carries_pressure, std::vector<Eigen::Matrix2d>& correction,
                                  const DryWallRule& dry) {
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
  correction.resize(particles.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    correction[i] = Eigen::Matrix2d::Identity();
    if (particles.type[i] != ParticleType::Fluid) continue;
    const Eigen::Matrix2d moment =
        gradient_moment(particles, neighbours, samples, radius, carries_pressure, dry, static_cast<std::size_t>(i));
    if (moment.determinant() > kMinimumCorrectionDeterminant) correction[i] = moment.inverse();
  }
}

void apply_gradient_correction(const ParticleSet& particles, const std::vector<Eigen::Matrix2d>& correction,
                               std::vector<Vec2>& acceleration) {
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (particles.type[i] == ParticleType::Fluid) acceleration[i] = correction[i] * acceleration[i];
  }
}

}  // namespace mps_lab::mps
