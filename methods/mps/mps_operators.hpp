#pragma once
// The MPS particle-interaction models of spec §2 (Koshizuka & Oka 1996), as free functions
// over a ParticleSet and a neighbour list. d = 2 throughout. Each operator has its own
// radius of influence and lattice constants (n0, lambda computed with that radius), so the
// spec's single re = 2.1 l0 and the larger Laplacian radius of K&O 1996 are both expressible.
#include <algorithm>
#include <cstddef>
#include <vector>

#include "core/base/particles.hpp"
#include "core/search/neighbour_search.hpp"
#include "core/walls/wall_sample_reactions.hpp"
#include "core/walls/wall_samples.hpp"
#include "methods/mps/mps_kernels.hpp"

namespace mps_lab::mps {

constexpr double kDimension = 2.0;

// An operator's radius of influence and the lattice constants measured with it.
struct OperatorRadius {
  double re = 0.0;      // m
  double r_min = 0.0;   // m, spec R_MIN
  double n0 = 0.0;      // lattice number density with this re
  double lambda = 0.0;  // m^2, lattice lambda with this re
};
OperatorRadius make_operator_radius(double spacing, double re, double r_min);

// The pair terms of spec §2, shared by the operators (sum over j of i) and by the fluid's reaction
// on wall particles (sum over i of j, docs/walls.md "Loads on obstacles"), so both are the same.
// Laplacian: nu times its coefficient 2d / (n0 lambda), 1/s; what neighbour j adds to
// sum_j (u_j - u_i) w_ij, m/s.
inline double laplacian_coefficient(const OperatorRadius& radius, double kinematic_viscosity) {
  return kinematic_viscosity * 2.0 * kDimension / (radius.n0 * radius.lambda);
}
inline Vec2 laplacian_pair(const ParticleSet& particles, std::size_t i, std::size_t j, const OperatorRadius& radius) {
  const double w = mps_weight((particles.position[j] - particles.position[i]).norm(), radius.re, radius.r_min);
  return (particles.velocity[j] - particles.velocity[i]) * w;
}
// Gradient: what neighbour j adds to sum_j (P_j - P_min,i) / |r_ij|^2 r_ij w_ij, Pa/m.
inline Vec2 gradient_pair(const ParticleSet& particles, std::size_t i, std::size_t j, double p_min,
                          const OperatorRadius& radius) {
  const Vec2 r_ij = particles.position[j] - particles.position[i];
  const double r = r_ij.norm();
  const double w = mps_weight(r, radius.re, radius.r_min);
  if (w == 0.0) return Vec2::Zero();
  return (particles.pressure[j] - p_min) / std::max(r * r, radius.r_min * radius.r_min) * w * r_ij;
}
// CMPS gradient (Khayyer & Gotoh 2008): what j adds to sum_j [(P_i + P_j) - (Phat_i + Phat_j)] /
// |r_ij|^2 r_ij w_ij, Pa/m (Phat: minimum_pressure, neighbourhood_minimum).
inline Vec2 cmps_gradient_pair(const ParticleSet& particles, std::size_t i, std::size_t j,
                               const std::vector<double>& minimum_pressure, const OperatorRadius& radius) {
  const Vec2 r_ij = particles.position[j] - particles.position[i];
  const double r = r_ij.norm();
  const double w = mps_weight(r, radius.re, radius.r_min);
  if (w == 0.0) return Vec2::Zero();
  const double pair = (particles.pressure[i] + particles.pressure[j]) - (minimum_pressure[i] + minimum_pressure[j]);
  return pair / std::max(r * r, radius.r_min * radius.r_min) * w * r_ij;
}

// Every operator also sums over the wall samples of i when the boundary model has them
// (core/walls/wall_samples.hpp; an empty list adds nothing): a sample is a neighbour of volume V_w
// (its weight counts V_w times), velocity u_w and pressure p_w. Its pair terms, shared by the
// operators and by the fluid's reaction on the samples (add_*_sample_reactions):
// Laplacian: what sample w adds to sum (u_j - u_i) w_ij, V_w (u_w - u_i) w_iw, m/s.
inline Vec2 laplacian_sample_pair(const ParticleSet& particles, std::size_t i, const WallSample& wall,
                                  const OperatorRadius& radius) {
  const double w = mps_weight((wall.position - particles.position[i]).norm(), radius.re, radius.r_min);
  return wall.volume * (sample_velocity(wall, particles.velocity) - particles.velocity[i]) * w;
}
// Gradient: V_w (p_w - P_min,i) / |r_iw|^2 r_iw w_iw, Pa/m, p_w = p_s + rho (g - a_w) . (x_w - x_s).
inline Vec2 gradient_sample_pair(const ParticleSet& particles, std::size_t i, const WallSample& wall, double p_min,
                                 const OperatorRadius& radius, double density, const Vec2& gravity) {
  const Vec2 r_iw = wall.position - particles.position[i];
  const double r = r_iw.norm();
  const double w = mps_weight(r, radius.re, radius.r_min);
  if (w == 0.0) return Vec2::Zero();
  const double p_w = sample_pressure(wall, particles.pressure, particles.position, density, gravity);
  return wall.volume * (p_w - p_min) / std::max(r * r, radius.r_min * radius.r_min) * w * r_iw;
}
// CMPS: V_w [(P_i + p_w) - 2 Phat_i] / |r_iw|^2 r_iw w_iw, Pa/m (a sample's Phat is i's).
inline Vec2 cmps_gradient_sample_pair(const ParticleSet& particles, std::size_t i, const WallSample& wall,
                                      double p_hat_i, const OperatorRadius& radius, double density,
                                      const Vec2& gravity) {
  const Vec2 r_iw = wall.position - particles.position[i];
  const double r = r_iw.norm();
  const double w = mps_weight(r, radius.re, radius.r_min);
  if (w == 0.0) return Vec2::Zero();
  const double p_w = sample_pressure(wall, particles.pressure, particles.position, density, gravity);
  return wall.volume * ((particles.pressure[i] + p_w) - 2.0 * p_hat_i) / std::max(r * r, radius.r_min * radius.r_min) *
         w * r_iw;
}

// n_i = sum_j w(|r_j - r_i|, re) + sum_w V_w w(|r_w - r_i|, re) over every non-ghost
// neighbour and wall sample (spec §2, PND; the sample sum is Harada et al. 2008's wall weight
// for the distance-function wall).
void number_density(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                    const OperatorRadius& radius, std::vector<double>& out);

// <lap u>_i = (2d / (n0 lambda)) sum_j (u_j - u_i) w_ij (spec §2), for fluid particles,
// over every non-ghost neighbour (walls have u = 0) and wall sample (u_w). Adds nu <lap u>_i
// to acceleration.
void add_viscous_acceleration(const ParticleSet& particles, const NeighbourList& neighbours,
                              const WallSampleList& samples, const OperatorRadius& radius, double kinematic_viscosity,
                              std::vector<Vec2>& acceleration);

// <grad P>_i = (d/n0) sum_j (P_j - P_min,i) / |r_ij|^2 r_ij w_ij (spec §2), for fluid
// particles, over neighbours with carries_pressure[j]; P_min,i is the minimum pressure over
// those neighbours, and over i itself when `min_includes_self`; wall samples enter both with
// p_w = p_s + rho g . (x_w - x_s); `dry` may leave dry wall points out. Writes -(1/rho) <grad P>_i.
void pressure_acceleration(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                           const OperatorRadius& radius, const std::vector<char>& carries_pressure, double density,
                           const Vec2& gravity, bool min_includes_self, std::vector<Vec2>& acceleration,
                           const DryWallRule& dry);

// P_min,i (the spec's, §2) or Phat_i (CMPS): the minimum pressure over i's pressure-carrying
// neighbours and wall samples within re, and over i itself when `min_includes_self`, for every
// pressure-carrying particle (i's own pressure where it has none), Pa.
void neighbourhood_minimum(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                           const OperatorRadius& radius, const std::vector<char>& carries_pressure, double density,
                           const Vec2& gravity, bool min_includes_self, std::vector<double>& out,
                           const DryWallRule& dry);

// The fluid's reaction on wall particles (docs/walls.md, "Loads on obstacles"): for every wall
// particle j, minus the sum over its fluid neighbours i of m nu <lap u> pair term (spec §2,
// laplacian_pair), with m = rho l0^2 the mass of a particle per metre of depth (kg/m); adds to
// `reaction` (N/m). With the same neighbours and velocities as add_viscous_acceleration.
void add_viscous_wall_reactions(const ParticleSet& particles, const NeighbourList& neighbours,
                                const OperatorRadius& radius, double kinematic_viscosity, double particle_mass,
                                std::vector<Vec2>& reaction);
// The same for the pressure term, -(1/rho) <grad P>_i (spec §2, gradient_pair; cmps_gradient_pair
// when `cmps`), over the pressure-carrying wall particles; `minimum_pressure` from
// neighbourhood_minimum with the operator's settings.
// `correction`, when not null, holds C_i of the gradient correction (GC, mps_schemes.hpp): the pair
// term of i is then C_i times it, as in the corrected acceleration.
void add_pressure_wall_reactions(const ParticleSet& particles, const NeighbourList& neighbours,
                                 const OperatorRadius& radius, const std::vector<char>& carries_pressure,
                                 const std::vector<double>& minimum_pressure, bool cmps, double density,
                                 double particle_mass, std::vector<Vec2>& reaction,
                                 const std::vector<Eigen::Matrix2d>* correction, const DryWallRule& dry);

// The same on wall samples (obstacle_load pair_reaction with a boundary model of wall samples; core/walls/
// wall_sample_reactions.hpp): adds to `loads` the reaction of each obstacle's samples of the viscous and
// the pressure term, with the samples and inputs the operator had (`scratch` is reused storage).
void add_viscous_sample_reactions(const ParticleSet& particles, const WallSampleList& samples,
                                  const OperatorRadius& radius, double kinematic_viscosity, double particle_mass,
                                  std::vector<Vec2>& scratch, WallSampleLoads& loads);
void add_pressure_sample_reactions(const ParticleSet& particles, const WallSampleList& samples,
                                   const OperatorRadius& radius, const std::vector<double>& minimum_pressure, bool cmps,
                                   double density, const Vec2& gravity, double particle_mass,
                                   std::vector<Vec2>& scratch, WallSampleLoads& loads,
                                   const std::vector<Eigen::Matrix2d>* correction, const DryWallRule& dry);

}  // namespace mps_lab::mps
