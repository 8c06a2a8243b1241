#pragma once
// The explicit pressure of EISPH: one relaxation sweep of the ISPH pressure Poisson equation
// per time step, started from the previous step's pressure, instead of a linear solve.
//
// The PPE is the one of the isph method (methods/isph/isph_pressure.hpp), fluid row i:
//   <div(grad p / rho)>_i = sum_j a_ij (p_j - p_i) = S_i,                       (PPE)
//   a_ij = -m 8/(rho_i + rho_j)^2 r_ij.grad W_ij / (r_ij^2 + eta^2) >= 0
// (Cummins & Rudman 1999; Shao & Lo 2003; isph::ppe_pair_coefficient), and the wall pressure
// of Adami, Hu & Adams (2012), eq. 27 with a fixed wall:
//   p_w = (sum_f p_f W_wf + g . sum_f rho_f (x_w - x_f) W_wf) / sum_f W_wf.         (WALL)
// EISPH (Hosseini, Manzari & Hannani 2007, Int. J. Numer. Methods Heat Fluid Flow 17,
// their explicit pressure step; our notes, reference/isph-notes.ja.md, step 7) takes the
// pressure of step n+1 from the pressures of step n in one pass:
//   7.1  p_w from (WALL) with the fluid pressures p^n (surface particles at 0);
//   7.2  p_i^{n+1} = (1 - omega) p_i^n + omega (sum_j a_ij p_j^n - S_i) / sum_j a_ij      (SWEEP)
// for every fluid particle off the free surface (p = 0 on it, or with a surface offset the
// Jacobi update p_i^{n+1} = factor_i sum_j W_ij p_j^n of (SURF), methods/isph/isph_surface.hpp),
// omega the relaxation factor
// (1: one Jacobi sweep). Repeated at fixed particles, (SWEEP) with (WALL) before each pass is a
// block Jacobi iteration of the isph system (the wall rows of which are (WALL)), so its fixed
// point is the implicit solution (tests/test_eisph.cpp measures the contraction).
//
// Wall samples (boundary models without wall particles; core/walls/wall_samples.hpp): fluid row i
// also sums a_iw (p_w - p_i) over its samples w, with mass m V_w, density rho0 and
// p_w = p_s + rho0 g . (x_w - x_s): for s = i only the hydrostatic part is left (a Neumann
// wall, nothing on the diagonal), for s != i the image's pressure p_s^n and the hydrostatic part
// (as the rows of isph_pressure.cpp).
#include <cstddef>
#include <vector>

#include "core/base/particles.hpp"
#include "core/kernels/sph_kernels.hpp"
#include "core/search/neighbour_search.hpp"
#include "core/walls/wall_samples.hpp"

namespace mps_lab::eisph {

struct RelaxationSettings {
  double rest_density = 1000.0;     // rho0, kg/m^3 (density of a wall sample)
  double mass = 0.625;              // m, kg/m (per unit depth)
  double eta2 = 0.0;                // eta^2 of the Laplacian, m^2
  Vec2 gravity = Vec2(0.0, -9.81);  // m/s^2
  double relaxation = 1.0;          // omega of (SWEEP); 1 = Jacobi
};

struct SweepResult {
  std::size_t unknowns = 0;  // fluid particles off the free surface (the swept rows)
  std::size_t surface = 0;   // fluid particles held at p = 0
  // ||p^{n+1} - p^n|| / ||p^{n+1}|| over the swept rows: the Jacobi update omega D^-1 r of the
  // PPE at p^n, relative; 0 when every swept pressure is 0.
  double relative_change = 0.0;
  double largest_change = 0.0;  // max |p^{n+1} - p^n| over the swept rows, Pa
};

// (WALL): writes pressure[w] of every wall particle from the fluid pressures in `pressure`
// (fluid entries are read, never written, so the walls can be updated in place); 0 for a wall
// particle without a fluid neighbour. `density` as in isph_operators.hpp.
void adami_wall_pressure(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                         const std::vector<double>& density, const Vec2& gravity, std::vector<double>& pressure);

// (SWEEP): reads `previous` (p^n of every particle: fluid, and walls from (WALL)), writes
// `pressure` of every fluid particle: on the free surface (`free_surface[i]` != 0) (SURF) from
// `previous` where `surface_factor` (isph::water_surface_factors; null: none) is positive and 0
// elsewhere; 0 for a particle with no neighbour in the support; (SWEEP) elsewhere. `source[i]` is S_i, 1/s^2.
// Walls and ghosts of `pressure` are not written. `previous` and `pressure` must differ.
SweepResult relaxation_sweep(const ParticleSet& particles, const NeighbourList& neighbours,
                             const WallSampleList& samples, const SphKernel& kernel, const std::vector<double>& density,
                             const std::vector<double>& free_surface, const std::vector<double>& source,
                             const RelaxationSettings& settings, const std::vector<double>& previous,
                             std::vector<double>& pressure, const std::vector<double>* surface_factor = nullptr);

}  // namespace mps_lab::eisph
