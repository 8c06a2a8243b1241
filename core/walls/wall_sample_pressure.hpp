#pragma once
// The pressure a wall sample extends from its source particle, filtered: a method option for the
// boundary models of wall samples (isph and eisph: `wall_sample_pressure` "fitted";
// docs/methods/isph.md, "The wall samples' pressure").
//
// A sample of dummy_layers or distance_function carries the pressure of the fluid particle s it
// serves, extended hydrostatically to the wall point (core/walls/wall_samples.hpp):
//   p_w = p_s + rho0 (g - a_w) . (x_w - x_s).
// That is Adami, Hu & Adams (2012), eq. 27, with the kernel-weighted sum over the fluid near the
// wall point cut down to s alone. The wall then pushes s with s's own pressure twice over in the
// symmetric gradient (p_s + p_w), so every fluctuation of p_s is felt at once, and at full
// strength, as a change of the wall's push on s. "fitted" puts the pressure of s's neighbourhood
// in place of p_s: the linear moving-least-squares fit of the fluid pressure about x_s (Dilts 1999;
// Colagrossi & Landrini 2003 filter the density in the same way),
//   (a, b) = argmin sum_j W(|x_j - x_s|) (p_j - a - b . (x_j - x_s))^2,   p~_s = a,      (FIT)
// over s itself (weight W(0)) and its non-ghost fluid neighbours j. (FIT) reproduces any linear
// field exactly, whatever its gradient (the hydrostatic field at rest, the steep one of an impact),
// so p_w is unchanged wherever p is linear over s's support, while the particle-scale part of p_s
// is averaged over about a dozen neighbours. Where the fit is nearly singular (a splash, a sheet
// one particle thick: the moment matrix's normalised determinant below kMinimumFitDeterminant) s
// keeps its own pressure.
#include <cmath>
#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>

#include "core/base/particles.hpp"
#include "core/search/for_each_neighbour.hpp"
#include "core/search/neighbour_search.hpp"

namespace mps_lab {

// det M / (M00 M11 M22) of (FIT)'s 3 x 3 moment matrix M = sum_j W_j (1, d_j)(1, d_j)^T, d_j =
// x_j - x_s: 1 for a stencil symmetric about x_s, 0.73 beside a wall or under a flat surface and
// 0.53 in the corner where they meet (the still-water lattice, cubic spline of support 2.4 l0:
// tests/test_isph_wall_sample_pressure.cpp), 0 when the neighbours lie on one line.
constexpr double kMinimumFitDeterminant = 0.01;

// (FIT) at fluid particle s, Pa: p~_s from `pressure` (Pa) with weights weight(r) (1/m^2; the
// method's kernel W), or pressure[s] where the fit is nearly singular.
template <typename Weight>
double fitted_pressure(const ParticleSet& particles, const NeighbourList& neighbours, Weight&& weight,
                       const std::vector<double>& pressure, std::size_t s) {
  // s itself: b_s = (1, 0, 0)
  Eigen::Matrix3d moment = Eigen::Matrix3d::Zero();  // sum_j W_j b_j b_j^T, b_j = (1, d_j)
  moment(0, 0) = weight(0.0);
  Eigen::Vector3d projection(weight(0.0) * pressure[s], 0.0, 0.0);  // sum_j W_j p_j b_j
  for_each_neighbour(neighbours, s, [&](std::uint32_t j) {
    if (particles.type[j] != ParticleType::Fluid) return;
    const Vec2 d = particles.position[j] - particles.position[s];  // m
    const double w = weight(d.norm());
    const Eigen::Vector3d b(1.0, d.x(), d.y());
    moment.noalias() += w * b * b.transpose();
    projection.noalias() += w * pressure[j] * b;
  });
  const double diagonal = moment(0, 0) * moment(1, 1) * moment(2, 2);
  if (!(diagonal > 0.0) || moment.determinant() < kMinimumFitDeterminant * diagonal) return pressure[s];
  return moment.partialPivLu().solve(projection)(0);
}

// (FIT) for every fluid particle into `fitted` (non-fluid entries: `pressure` as it is), in
// parallel; each entry depends only on the particle's own neighbours.
template <typename Weight>
void fit_source_pressures(const ParticleSet& particles, const NeighbourList& neighbours, Weight&& weight,
                          const std::vector<double>& pressure, std::vector<double>& fitted) {
  fitted.resize(pressure.size());
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t s = 0; s < n; ++s) {
    fitted[s] = particles.type[s] == ParticleType::Fluid
                    ? fitted_pressure(particles, neighbours, weight, pressure, static_cast<std::size_t>(s))
                    : pressure[s];
  }
}

}  // namespace mps_lab
