#pragma once
// The SPH operators of the ISPH method, as free functions over a ParticleSet and a
// neighbour list. 2-D; every particle (fluid and wall) has the same mass m; r_ij = x_i - x_j
// and grad W_ij = grad_i W(|r_ij|) (core/kernels/sph_kernels.hpp). Ghost particles are skipped
// wherever they appear (a list built before a particle became a ghost may still hold it).
//
// `density` holds, per particle, the density the operators use: the method passes rho0 for
// every particle (default) or the summation density rho* of fluid particles and rho0 for
// walls (parameter operator_density = summation, as Shao & Lo 2003).
//
// Wall samples (core/walls/wall_samples.hpp): with a boundary model that has no wall particles
// (dummy_layers, mirror_particles, distance_function) every operator adds, beside its sum over
// the neighbours j of i, the same sum over the samples w of i: a sample is a particle of mass
// m V_w and density rho0 at x_w, with velocity u_w = M_w u_s and pressure
// p_w = p_s + rho0 g . (x_w - x_s) (s its source particle). An empty list (the default
// boundary model, adami_wall_particles, whose wall particles are in the ParticleSet) adds
// nothing; the overloads without a list are the operators of that model.
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
#include <algorithm>
#include <string>
#include <vector>

#include "core/base/parameters.hpp"
#include "core/base/particles.hpp"
#include "core/kernels/sph_kernels.hpp"
#include "core/search/neighbour_search.hpp"
#include "core/walls/wall_sample_reactions.hpp"
#include "core/walls/wall_samples.hpp"

namespace mps_lab::isph {

// The empty sample list: the operators of a boundary model made of wall particles.
inline const WallSampleList& no_wall_samples() {
  static const WallSampleList empty;
  return empty;
}

// The particle mass is m = rho0 / lattice_kernel_sum (core/kernels/sph_kernels.hpp): the summation
// density of a particle with full support on the initial lattice is exactly rho0 (the SPH
// counterpart of MPS's n0).

// rho_i = m (W(0) + sum_j W_ij + sum_w V_w W_iw) over every non-ghost neighbour, fluid and wall,
// and the wall samples (the summation density, Monaghan 1992), for fluid particles; wall
// particles get rho0 (their summation density is truncated by the outer layers and is never
// used as such).
void summation_density(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                       const SphKernel& kernel, double mass, double rest_density, std::vector<double>& density);
inline void summation_density(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                              double mass, double rest_density, std::vector<double>& density) {
  summation_density(particles, neighbours, no_wall_samples(), kernel, mass, rest_density, density);
}

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
// (the unit tests apply it to fields with known Laplacians). A wall sample w carries
// phi_w = phi_s + head . (x_w - x_s): head = rho0 g for the pressure (the PPE), 0 for a field
// without hydrostatic extrapolation; its pair coefficient has mass m V_w and density rho0.
void ppe_laplacian(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                   const SphKernel& kernel, double mass, const std::vector<double>& density, double rest_density,
                   const Vec2& head, double eta2, const std::vector<double>& values, std::vector<double>& out);
inline void ppe_laplacian(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                          double mass, const std::vector<double>& density, double eta2,
                          const std::vector<double>& values, std::vector<double>& out) {
  ppe_laplacian(particles, neighbours, no_wall_samples(), kernel, mass, density, 0.0, Vec2::Zero(), eta2, values, out);
}

// What neighbour j (fluid or wall particle) adds to the viscous sum of i (Morris, Fox & Zhu 1997):
//   m (rho_i + rho_j) / (rho_i rho_j) F_ij (u_i - u_j), 1/s per m^2/s of nu; a wall particle moves
// with its prescribed velocity (no slip). Shared by add_viscous_acceleration and the reaction on
// wall particles (add_viscous_wall_reactions), so that both are the same.
inline Vec2 viscous_pair(const ParticleSet& particles, const SphKernel& kernel, double mass,
                         const std::vector<double>& density, double eta2, std::size_t i, std::size_t j) {
  const double factor = laplacian_pair_factor(kernel, particles.position[i] - particles.position[j], eta2);
  const Vec2 u_j =
      particles.type[j] == ParticleType::Wall ? particles.prescribed_wall_velocity(j) : particles.velocity[j];
  return mass * (density[i] + density[j]) / (density[i] * density[j]) * factor * (particles.velocity[i] - u_j);
}

// What wall sample w adds to the viscous sum of i: viscous_pair with mass m V_w, density rho0 and
// the sample's velocity u_w. Shared by add_viscous_acceleration and add_viscous_sample_reactions.
inline Vec2 viscous_sample_pair(const ParticleSet& particles, const SphKernel& kernel, double mass,
                                const std::vector<double>& density, double rest_density, double eta2, std::size_t i,
                                const WallSample& wall) {
  const double factor = laplacian_pair_factor(kernel, particles.position[i] - wall.position, eta2);
  const Vec2 u_w = sample_velocity(wall, particles.velocity);
  return mass * wall.volume * (density[i] + rest_density) / (density[i] * rest_density) * factor *
         (particles.velocity[i] - u_w);
}

// Adds nu <lap u>_i to the acceleration of every fluid particle (the laminar viscous term of
// Morris, Fox & Zhu 1997, with mu = rho nu):
//   sum_j m nu (rho_i + rho_j) / (rho_i rho_j) F_ij (u_i - u_j);
// wall particles have u = 0 (no slip); a wall sample has u_w = M_w u_s (mass m V_w, rho0).
void add_viscous_acceleration(const ParticleSet& particles, const NeighbourList& neighbours,
                              const WallSampleList& samples, const SphKernel& kernel, double mass,
                              const std::vector<double>& density, double rest_density, double kinematic_viscosity,
                              double eta2, std::vector<Vec2>& acceleration);
inline void add_viscous_acceleration(const ParticleSet& particles, const NeighbourList& neighbours,
                                     const SphKernel& kernel, double mass, const std::vector<double>& density,
                                     double kinematic_viscosity, double eta2, std::vector<Vec2>& acceleration) {
  add_viscous_acceleration(particles, neighbours, no_wall_samples(), kernel, mass, density, 0.0, kinematic_viscosity,
                           eta2, acceleration);
}

// <div u>_i = (1/rho_i) sum_j m (u_j - u_i) . grad W_ij (the divergence of Monaghan 1992 that
// Cummins & Rudman 1999 use for the projection source) for fluid particles, 0 elsewhere.
// `velocity` holds the velocity of every particle (walls included: see isph_method.cpp).
// A wall sample (mass m V_w) moves with u_w = b + M_w (u_s - b), b = `sample_base_velocity`:
// the velocity map acts on the motion relative to b. b = 0 is u_w = M_w u_s; the method passes
// b = dt g for the predicted velocity u*, the velocity a wall point at rest has in u* (as its
// wall particles: isph_method.cpp, docs/methods/isph.md). A sample of a moving wall has
// b = u_wall + dt (g - a_w) (dt = `sample_base_time_step`, s; its wall particles' u*): the
// sample's wall_velocity (I - M_w) u_wall is added and b lowered by dt a_w.
void velocity_divergence(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                         const SphKernel& kernel, double mass, const std::vector<double>& density,
                         const std::vector<Vec2>& velocity, const Vec2& sample_base_velocity,
                         double sample_base_time_step, std::vector<double>& out);
inline void velocity_divergence(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                                double mass, const std::vector<double>& density, const std::vector<Vec2>& velocity,
                                std::vector<double>& out) {
  velocity_divergence(particles, neighbours, no_wall_samples(), kernel, mass, density, velocity, Vec2::Zero(), 0.0,
                      out);
}

// <div r>_i = -sum_j (m / rho_j) r_ij . grad W_ij (Lee et al. 2008, sec. 2.4), for fluid
// particles, 0 elsewhere: ~2 inside the 2-D fluid, ~1 on a flat surface. Wall samples count
// with m V_w / rho0.
void position_divergence(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                         const SphKernel& kernel, double mass, const std::vector<double>& density, double rest_density,
                         std::vector<double>& out);
inline void position_divergence(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                                double mass, const std::vector<double>& density, std::vector<double>& out) {
  position_divergence(particles, neighbours, no_wall_samples(), kernel, mass, density, 0.0, out);
}

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

// Whether the gradient of fluid particle i is renormalised (Corrected, or SymmetricCorrectedSurface on
// a free-surface particle), and whether its pairs take the symmetric form.
inline bool corrected_gradient(PressureGradientForm form, double free_surface_i) {
  return form == PressureGradientForm::Corrected ||
         (form == PressureGradientForm::SymmetricCorrectedSurface && free_surface_i != 0.0);
}
inline bool symmetric_gradient(PressureGradientForm form, double free_surface_i) {
  return !corrected_gradient(form, free_surface_i) && form != PressureGradientForm::Difference;
}
// What neighbour j adds to grad p_i / rho_i before the renormalisation, m/s^2: Monaghan's symmetric
// m (p_i/rho_i^2 + p_j/rho_j^2) grad W_ij, or the difference form m/(rho_i rho_j) (p_j - p_i) grad W_ij.
// Shared by pressure_acceleration and the reaction on wall particles (add_pressure_wall_reactions).
inline Vec2 pressure_pair(const ParticleSet& particles, const SphKernel& kernel, double mass,
                          const std::vector<double>& density, bool symmetric, std::size_t i, std::size_t j) {
  const Vec2 gradient = kernel.gradient(particles.position[i] - particles.position[j]);
  const double p_i = particles.pressure[i], p_j = particles.pressure[j];
  const double rho_i = density[i], rho_j = density[j];
  if (symmetric) return mass * (p_i / (rho_i * rho_i) + p_j / (rho_j * rho_j)) * gradient;  // Monaghan (1992)
  return mass / (rho_i * rho_j) * (p_j - p_i) * gradient;                                   // zero for constant p
}

// How a wall point's pressure enters the gradient. A wall sample's is p_w = p_s + rho0 g . (x_w - x_s),
// and max(p_w, 0) when negative pressures are clamped (as the method clamps wall particles'
// pressures after the solve: a wall above the water whose extrapolated pressure is negative
// would pull the fluid towards it). With exclude_dry (parameter dry_wall_points "excluded",
// isph_surface.hpp) a dry wall point - above fluid particle i, against gravity, with a pressure
// (a sample's before the clamp) not above 0 - is left out of i's gradient and its reaction: it
// stands in the air above the water, where the clamped point would still push i away with i's
// own pressure (the symmetric form's p_i term).
//
// What a sample extends is its source's pressure: particles.pressure, or with `source_pressure` that
// field instead (parameter wall_sample_pressure "fitted": the linear MLS fit of the fluid pressure
// about each source, core/walls/wall_sample_pressure.hpp). Its p_w is then the one value that enters
// the gradient, the dry-wall test and the reactions alike; the pair's p_i stays i's own pressure.
struct SamplePressure {
  double rest_density = 1000.0;     // rho0, kg/m^3: the density of a sample
  Vec2 gravity = Vec2(0.0, -9.81);  // m/s^2
  bool clamp_negative = true;
  bool exclude_dry = false;
  const std::vector<double>* source_pressure = nullptr;  // Pa per particle; null: particles.pressure
  // The wall points left out of fluid particles' gradients (core/walls/wall_samples.hpp).
  DryWallRule dry_rule() const { return {exclude_dry, gravity, rest_density}; }
  // p_w of sample `wall` before any clamp, Pa; `symmetric`: for a pair in the symmetric form.
  double wall_pressure(const ParticleSet& particles, const WallSample& wall, bool symmetric = true) const {
    const std::vector<double>& source = source_pressure != nullptr && symmetric ? *source_pressure : particles.pressure;
    return sample_pressure(wall, source, particles.position, rest_density, gravity);
  }
  // Whether sample `wall` is dry for fluid particle i (DryWallRule with this p_w).
  bool excludes_sample(const ParticleSet& particles, std::size_t i, const WallSample& wall) const {
    return exclude_dry && dry_wall_point(particles.position[i], wall.position, wall_pressure(particles, wall), gravity);
  }
};

// The scene key wall_sample_pressure of isph and eisph: "own" (default: a wall sample extends its
// source particle's pressure, core/walls/wall_samples.hpp) or "fitted" (the linear MLS fit of the
// fluid pressure about the source, core/walls/wall_sample_pressure.hpp; for loads). Boundary models
// of wall particles have no samples: their wall pressure is Adami's mean over the fluid already.
ParameterSpec wall_sample_pressure_parameter();
// Whether the method's parameters ask for "fitted".
bool fits_wall_sample_pressure(const ParameterValues& parameters);

// `rule` for this step's gradient: when `fit` is set and the boundary model has wall samples,
// `fitted` gets (FIT) of particles.pressure at every fluid particle (with the method's kernel) and
// the rule's samples extend it; otherwise `rule` as it is (the sources' own pressures).
SamplePressure with_source_pressure(SamplePressure rule, const ParticleSet& particles, const NeighbourList& neighbours,
                                    const WallSampleList& samples, const SphKernel& kernel, bool fit,
                                    std::vector<double>& fitted);

// What wall sample w adds to grad p_i / rho_i before the renormalisation, m/s^2: pressure_pair with
// mass m V_w, density rho0 and the pressure p_w of `rule`. Shared by pressure_acceleration and the
// reaction on wall samples (add_pressure_sample_reactions).
inline Vec2 pressure_sample_pair(const ParticleSet& particles, const SamplePressure& rule, const SphKernel& kernel,
                                 double mass, const std::vector<double>& density, bool symmetric, std::size_t i,
                                 const WallSample& wall) {
  const double rho_w = rule.rest_density;
  const Vec2 gradient = kernel.gradient(particles.position[i] - wall.position);
  double p_w = rule.wall_pressure(particles, wall, symmetric);
  if (rule.clamp_negative) p_w = std::max(p_w, 0.0);
  const double m_w = mass * wall.volume;
  const double p_i = particles.pressure[i], rho_i = density[i];
  if (symmetric) return m_w * (p_i / (rho_i * rho_i) + p_w / (rho_w * rho_w)) * gradient;
  return m_w / (rho_i * rho_w) * (p_w - p_i) * gradient;
}

// Writes a_i = -grad p_i / rho_i for fluid particles (0 elsewhere) from particles.pressure,
// over every non-ghost neighbour (wall particles carry their extrapolated pressure) and the
// wall samples (mass m V_w, density rho0, pressure by `sample_rule`; in the
// renormalisation matrix too). `free_surface[i]` != 0 marks surface particles (read by
// SymmetricCorrectedSurface only). `renormalisation`, when given, gets each fluid particle's L_i
// (the identity where the gradient is not renormalised) for add_pressure_wall_reactions.
void pressure_acceleration(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                           const SamplePressure& sample_rule, const SphKernel& kernel, double mass,
                           const std::vector<double>& density, const std::vector<double>& free_surface,
                           PressureGradientForm form, std::vector<Vec2>& acceleration,
                           std::vector<Eigen::Matrix2d>* renormalisation = nullptr);
inline void pressure_acceleration(const ParticleSet& particles, const NeighbourList& neighbours,
                                  const SphKernel& kernel, double mass, const std::vector<double>& density,
                                  const std::vector<double>& free_surface, PressureGradientForm form,
                                  std::vector<Vec2>& acceleration) {
  pressure_acceleration(particles, neighbours, no_wall_samples(), SamplePressure{}, kernel, mass, density, free_surface,
                        form, acceleration);
}

// The fluid's reaction on wall particles (docs/walls.md, "Loads on obstacles"): for every wall
// particle j, minus the sum over its fluid neighbours i of m times the acceleration j's pair term
// gives i - pressure: -L_i pressure_pair (L_i from pressure_acceleration; none for a dry wall
// particle `rule` excludes); viscosity: nu viscous_pair. Adds to `reaction`, N/m; with the inputs
// the fluid's operators had.
void add_pressure_wall_reactions(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                                 double mass, const std::vector<double>& density,
                                 const std::vector<double>& free_surface, PressureGradientForm form,
                                 const std::vector<Eigen::Matrix2d>& renormalisation, std::vector<Vec2>& reaction,
                                 const SamplePressure& rule = SamplePressure{});
void add_viscous_wall_reactions(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                                double mass, const std::vector<double>& density, double kinematic_viscosity,
                                double eta2, std::vector<Vec2>& reaction);

// The same on wall samples (core/walls/wall_sample_reactions.hpp): adds to `loads` the reaction of each
// obstacle's samples, -m L_i pressure_sample_pair and m nu viscous_sample_pair, with the inputs the
// fluid's operators had (the samples of that operator; `scratch` is reused storage).
void add_pressure_sample_reactions(const ParticleSet& particles, const WallSampleList& samples,
                                   const SamplePressure& rule, const SphKernel& kernel, double mass,
                                   const std::vector<double>& density, const std::vector<double>& free_surface,
                                   PressureGradientForm form, const std::vector<Eigen::Matrix2d>& renormalisation,
                                   std::vector<Vec2>& scratch, WallSampleLoads& loads);
void add_viscous_sample_reactions(const ParticleSet& particles, const WallSampleList& samples, const SphKernel& kernel,
                                  double mass, const std::vector<double>& density, double rest_density,
                                  double kinematic_viscosity, double eta2, std::vector<Vec2>& scratch,
                                  WallSampleLoads& loads);

}  // namespace mps_lab::isph
