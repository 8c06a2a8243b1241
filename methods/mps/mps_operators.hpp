#pragma once
// The MPS particle-interaction models of spec §2 (Koshizuka & Oka 1996), as free functions
// over a ParticleSet and a neighbour list. d = 2 throughout. Each operator has its own
// radius of influence and lattice constants (n0, lambda computed with that radius), so the
// spec's single re = 2.1 l0 and the larger Laplacian radius of K&O 1996 are both expressible.
#include <vector>

#include "core/base/particles.hpp"
#include "core/search/neighbour_search.hpp"
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

// Every operator also sums over the wall samples of i when the boundary model has them
// (core/walls/wall_samples.hpp; an empty list adds nothing): a sample is a neighbour of volume V_w
// (its weight counts V_w times), velocity u_w and pressure p_w.

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
// p_w = p_s + rho g . (x_w - x_s). Writes -(1/rho) <grad P>_i.
void pressure_acceleration(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                           const OperatorRadius& radius, const std::vector<char>& carries_pressure, double density,
                           const Vec2& gravity, bool min_includes_self, std::vector<Vec2>& acceleration);

}  // namespace mps_lab::mps
