#pragma once
// The water surface beyond the free-surface particles: the pressure of a surface particle
// when p = 0 is put at the water surface rather than at the particle's centre (parameter
// free_surface_offset of isph and eisph; docs/methods/isph.md, "Free surface").
//
// Shao & Lo (2003) hold the surface particles at p = 0, but the water they represent reaches
// half a spacing beyond their centres: the pressure everywhere is then rho g l0/2 low
// (measured: docs/methods/isph.md). With an offset delta > 0 the zero-pressure point of
// surface particle i is x_i + delta n_i, n_i its outward unit normal (the colour function's:
// n_i ~ -sum_j m_j grad W_ij over the fluid neighbours and the wall points), and p_i is the
// linear interpolation along n_i between that point and the kernel-weighted mean of its fluid
// neighbours, which lies d_i beneath it (a wall point enters n_i with its wet share: 1 level
// with the particle or below, 0 a spacing or more above it, against gravity; see wet_share in
// isph_surface.cpp):
//   p_i = delta / (delta + d_i) sum_j w_ij p_j,                                        (SURF)
//   w_ij = W_ij / sum_k W_ik,   d_i = sum_j w_ij (x_i - x_j) . n_i,
// over the non-ghost fluid neighbours j != i (Adami, Hu & Adams 2012 take the wall pressure
// the same way, as a kernel-weighted mean plus what lies between). (SURF) is exact when p is
// linear along n_i: under a flat surface at rest p_i = rho g delta. Its weights are positive
// and sum to delta / (delta + d_i) < 1, so the row is strictly diagonally dominant, and a sheet
// whose particles all lie on the surface gets p = 0 (the one solution of p = M p when M's row
// sums are below 1).
//
// A surface particle whose fluid neighbours do not lie beneath it, d_i < kMinimumSurfaceDepth l0
// (a splash, a sheet one particle thick, a particle flagged at a rarefaction inside the fluid,
// whose normal is noise), keeps p = 0 at its centre, as with offset 0.
#include <vector>

#include "core/base/parameters.hpp"
#include "core/base/particles.hpp"
#include "core/kernels/sph_kernels.hpp"
#include "core/search/neighbour_search.hpp"
#include "core/walls/wall_samples.hpp"

namespace mps_lab::isph {

// d_i / l0 below which (SURF) is not used. On a flat surface of the initial lattice d_i is
// 0.57 l0 (cubic spline, h = 1.2 l0; tests/test_isph_surface.cpp); a quarter spacing bounds
// delta / (delta + d_i) by 2/3 at delta = l0/2, so the extrapolation never amplifies.
constexpr double kMinimumSurfaceDepth = 0.25;

// The scene key of isph and eisph: delta / l0, default 0 (p = 0 at the centres, Shao & Lo 2003).
ParameterSpec free_surface_offset_parameter();

// The scene key dry_wall_points of isph and eisph: "clamped" (default: a wall point above the water
// enters the pressure gradient with its pressure clamped at 0) or "excluded" (a wall point above a
// fluid particle whose pressure is not above 0 is left out of that particle's gradient and its
// reaction: SamplePressure::dry_rule, isph_operators.hpp, and DryWallRule, core/walls/wall_samples.hpp;
// docs/methods/isph.md, "The water surface").
ParameterSpec dry_wall_points_parameter();
// Whether the method's parameters ask for "excluded".
bool excludes_dry_wall_points(const ParameterValues& parameters);

// Per particle, the factor of (SURF) written as p_i = factor_i sum_j W_ij p_j:
// factor_i = delta / ((delta + d_i) sum_j W_ij), 1/(1/m^2). 0 for a particle held at p = 0 at its
// centre: not a fluid particle on the free surface (`free_surface[i]` == 0), d_i too small, or
// `offset` (delta, m) 0. Fluid and wall particles weigh m in the normal, a sample m V_w;
// `gravity` (m/s^2) tells which wall points are above the particle.
void water_surface_factors(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                           const SphKernel& kernel, const Vec2& gravity, const std::vector<double>& free_surface,
                           double offset, double spacing, std::vector<double>& factor);

// (SURF) evaluated: factor_i sum_j W_ij pressure_j over the non-ghost fluid neighbours.
double water_surface_pressure(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                              double factor_i, std::size_t i, const std::vector<double>& pressure);

}  // namespace mps_lab::isph
