#pragma once
// The pressure on a wall point from the fluid next to it, the same for every method and boundary
// model: the wall-pressure transducers (core/run/pressure_sensors.hpp) and the surface load on
// obstacles without wall particles (core/walls/surface_pressure_loads.hpp) both read it.
//
// Adami, Hu & Adams (2012), J. Comput. Phys. 231, 7057-7075, eq. 27, at a wall point x_w:
//   p_w = [ sum_f p_f W_wf + (g - a_w) . sum_f rho_f r_wf W_wf ] / sum_f W_wf,   r_wf = x_w - x_f,
// over the fluid particles f within the kernel's support of x_w (rho_f the reference density: the
// methods here are incompressible), a_w the wall's acceleration. No fluid in reach: dry, 0.
#include <cstdint>
#include <vector>

#include "core/base/particles.hpp"
#include "core/base/types.hpp"
#include "core/kernels/sph_kernels.hpp"
#include "core/search/point_grid.hpp"

namespace mps_lab {

// The kernel of the extrapolation, for the transducers and the surface loads alike: cubic spline,
// support 2.4 l0 (h = 1.2 l0, as ISPH's and the common density measure's), which reaches the
// first two fluid rows of a wall.
inline SphKernel wall_pressure_kernel(double particle_spacing) {
  constexpr double support = 2.4;  // l0
  return SphKernel(SphKernelKind::CubicSpline, support * particle_spacing);
}

// The sums of eq. 27 over the fluid particles near one wall point.
struct ExtrapolatedPressure {
  double weights = 0.0;                 // sum_f W_wf, 1/m^2
  double weighted_pressure = 0.0;       // sum_f p_f W_wf, Pa/m^2
  Vec2 weighted_offset = Vec2::Zero();  // sum_f r_wf W_wf, m/m^2

  // Fluid particle f with pressure p_f (Pa) at r_wf = x_w - x_f (m) and kernel weight w = W(|r_wf|).
  void add(double pressure, const Vec2& offset, double w) {
    weights += w;
    weighted_pressure += pressure * w;
    weighted_offset += offset * w;
  }
  // p_w (Pa) with rho (kg/m^3) and body_force = g - a_w (m/s^2); 0 when dry.
  double value(double density, const Vec2& body_force) const {
    if (!(weights > 0.0)) return 0.0;
    return (weighted_pressure + density * body_force.dot(weighted_offset)) / weights;
  }
};

// Eq. 27's sums at every point of `points` (a grid whose cells are at least the kernel's support)
// from one pass over the fluid particles. Each point's sums run over the fluid in index order,
// as a loop over the particles for that point alone would: the same bits, for the cost of one
// pass whatever the number of points. `counts(e, r_wf)`: whether the fluid particle at
// r_wf = x_e - x_f is seen by point e (a face's front, for example).
template <class Counts>
void sum_extrapolated_pressures(const ParticleSet& particles, const PointGrid& points, const SphKernel& kernel,
                                Counts&& counts, std::vector<ExtrapolatedPressure>& sums) {
  sums.assign(points.points().size(), ExtrapolatedPressure{});
  const double support = kernel.support();
  for (std::size_t f = 0; f < particles.size(); ++f) {
    if (particles.type[f] != ParticleType::Fluid) continue;
    const Vec2& x_f = particles.position[f];
    if (!points.may_reach(x_f, support)) continue;
    points.for_each_within(x_f, support, [&](std::uint32_t e) {
      const Vec2 r_wf = points.points()[e] - x_f;
      if (!counts(e, r_wf)) return;
      sums[e].add(particles.pressure[f], r_wf, kernel.value(r_wf.norm()));
    });
  }
}

}  // namespace mps_lab
