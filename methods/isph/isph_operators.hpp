#pragma once
// The SPH operators of the ISPH method, as free functions over a ParticleSet and a
// neighbour list. 2-D; every particle (fluid and wall) has the same mass m; r_ij = x_i - x_j
// and grad W_ij = grad_i W(|r_ij|) (core/sph_kernels.hpp). Ghost particles are skipped
// wherever they appear (a list built before a particle became a ghost may still hold it).
//
// `density` holds, per particle, the density the operators use: the method passes rho0 for
// every particle (default) or the summation density rho* of fluid particles and rho0 for
// walls (parameter operator_density = summation, as Shao & Lo 2003).
//
// References (full citations and equation numbers in docs/methods/isph.md):
//   Monaghan (1992), Annu. Rev. Astron. Astrophys. 30, 543-574: summation density, symmetric
//     pressure gradient, divergence.
//   Morris, Fox & Zhu (1997), J. Comput. Phys. 136, 214-226: viscous term.
//   Cummins & Rudman (1999), J. Comput. Phys. 152, 584-607, and Shao & Lo (2003),
//     Adv. Water Resour. 26, 787-800: the PPE Laplacian.
//   Lee, Moulinec, Xu, Violeau, Laurence & Stansby (2008), J. Comput. Phys. 227, 8417-8436:
//     the position divergence used for free-surface detection.
//   Bonet & Lok (1999), Comput. Methods Appl. Mech. Engrg. 180, 97-115, and Khayyer, Gotoh &
//     Shao (2008), Coastal Eng. 55, 236-250: the renormalised (corrected) gradient.
#include <string>
#include <vector>

#include "core/neighbour_search.hpp"
#include "core/particles.hpp"
#include "core/sph_kernels.hpp"

namespace mps_lab::isph {

// The particle mass is m = rho0 / lattice_kernel_sum (core/sph_kernels.hpp): the summation
// density of a particle with full support on the initial lattice is exactly rho0 (the SPH
// counterpart of MPS's n0).

// rho_i = m (W(0) + sum_j W_ij) over every non-ghost neighbour, fluid and wall (the summation
// density, Monaghan 1992), for fluid particles; wall particles get rho0 (their
// summation density is truncated by the outer layers and is never used as such).
void summation_density(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                       double mass, double rest_density, std::vector<double>& density);

// The pair factor of the Cummins & Rudman / Morris Laplacians:
//   F_ij = r_ij . grad W_ij / (|r_ij|^2 + eta^2)   (1/m^4, <= 0 inside the support)
inline double laplacian_pair_factor(const SphKernel& kernel, const Vec2& r_ij, double eta2) {
  return r_ij.dot(kernel.gradient(r_ij)) / (r_ij.squaredNorm() + eta2);
}

// The PPE Laplacian of Cummins & Rudman (1999) and Shao & Lo (2003):
//   <div(grad p / rho)>_i = sum_j m 8 / (rho_i + rho_j)^2 (p_i - p_j) F_ij,
// written as sum_j a_ij (p_j - p_i) with the pair coefficient a_ij >= 0 returned here (m/kg).
inline double ppe_pair_coefficient(double mass, double density_i, double density_j, double pair_factor) {
  const double sum = density_i + density_j;
  return -mass * 8.0 / (sum * sum) * pair_factor;
}

// <div(grad phi / rho)>_i for every fluid particle (0 elsewhere), over every non-ghost
// neighbour, with `values` the field phi. The operator the PPE matrix is assembled from
// (the unit tests apply it to fields with known Laplacians).
void ppe_laplacian(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel, double mass,
                   const std::vector<double>& density, double eta2, const std::vector<double>& values,
                   std::vector<double>& out);

// Adds nu <lap u>_i to the acceleration of every fluid particle (the laminar viscous term of
// Morris, Fox & Zhu 1997, with mu = rho nu):
//   sum_j m nu (rho_i + rho_j) / (rho_i rho_j) F_ij (u_i - u_j);
// wall particles have u = 0 (no slip).
void add_viscous_acceleration(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                              double mass, const std::vector<double>& density, double kinematic_viscosity, double eta2,
                              std::vector<Vec2>& acceleration);

// <div u>_i = (1/rho_i) sum_j m (u_j - u_i) . grad W_ij (the divergence of Monaghan 1992 that
// Cummins & Rudman 1999 use for the projection source) for fluid particles, 0 elsewhere.
// `velocity` holds the velocity of every particle (walls included: see isph_method.cpp).
void velocity_divergence(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                         double mass, const std::vector<double>& density, const std::vector<Vec2>& velocity,
                         std::vector<double>& out);

// <div r>_i = -sum_j (m / rho_j) r_ij . grad W_ij (Lee et al. 2008, sec. 2.4), for fluid
// particles, 0 elsewhere: ~2 inside the 2-D fluid, ~1 on a flat surface.
void position_divergence(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                         double mass, const std::vector<double>& density, std::vector<double>& out);

enum class PressureGradientForm {
  Symmetric,   // grad p_i / rho_i = sum_j m (p_i/rho_i^2 + p_j/rho_j^2) grad W_ij (Monaghan 1992; Shao & Lo 2003)
  Difference,  // grad p_i / rho_i = (1/rho_i) sum_j (m/rho_j) (p_j - p_i) grad W_ij
  // The difference form with the renormalised kernel gradient (Bonet & Lok 1999; used in ISPH
  // by Khayyer, Gotoh & Shao 2008): L_i sum_j V_j (p_j - p_i) grad W_ij / rho_i,
  // L_i = [sum_j V_j grad W_ij (x_j - x_i)^T]^-1, exact for linear p even where the support is
  // truncated (free surface). Falls back to Difference where L_i is ill-conditioned.
  Corrected,
  // Symmetric for particles inside the fluid, Corrected for free-surface particles: the
  // symmetric form's pairwise repulsion keeps the interior ordered, and at the surface, where
  // p_i = 0 and the support is cut in half, the renormalised form gives the full grad p
  // (the symmetric form gives about half of it: surface particles would sink).
  SymmetricCorrectedSurface,
};
// "symmetric" | "difference" | "corrected" | "symmetric_corrected_surface"
PressureGradientForm pressure_gradient_form_from_name(const std::string& name);

// Writes a_i = -grad p_i / rho_i for fluid particles (0 elsewhere) from particles.pressure,
// over every non-ghost neighbour (wall particles carry their extrapolated pressure).
// `free_surface[i]` != 0 marks surface particles (read by SymmetricCorrectedSurface only).
void pressure_acceleration(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                           double mass, const std::vector<double>& density, const std::vector<double>& free_surface,
                           PressureGradientForm form, std::vector<Vec2>& acceleration);

}  // namespace mps_lab::isph
