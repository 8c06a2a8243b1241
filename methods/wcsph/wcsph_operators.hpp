#pragma once
// The operators of weakly compressible SPH with delta-SPH density diffusion, as free functions
// over a ParticleSet and a neighbour list. 2-D; every particle has the mass m = rho0 l0^2 and the
// volume V_j = m / rho_j; r_ij = x_i - x_j, grad W_ij = grad_i W(|r_ij|)
// (core/kernels/sph_kernels.hpp); h = support / 2 is the smoothing length of delta h c0 and
// alpha h c0. Ghost particles are skipped wherever they appear.
//
// Walls: wall particles (adami_wall_particles) carry the pressure and density of Adami, Hu &
// Adams (2012), computed by adami_wall_pressure() before the operators, and velocity 0 (a fixed
// wall). Wall samples (dummy_layers, mirror_particles, distance_function;
// core/walls/wall_samples.hpp) are summed beside the neighbours in the continuity equation and
// in the momentum equation: a sample w of source s has p_w = p_s + rho0 g . (x_w - x_s) (clamped
// at 0 with clamp_negative_wall_pressure, as wall particles), rho_w = the Tait density of p_w,
// mass m V_w and velocity u_w = M_w u_s. The delta-term and the renormalised density gradient sum
// over fluid neighbours only, with either boundary model (docs/methods/wcsph.md, "Walls").
//
// References (full citations in docs/methods/wcsph.md):
//   Monaghan (1992), Annu. Rev. Astron. Astrophys. 30, 543-574: artificial viscosity.
//   Morris, Fox & Zhu (1997), J. Comput. Phys. 136, 214-226: laminar viscosity.
//   Molteni & Colagrossi (2009), Comput. Phys. Commun. 180, 861-872: density diffusion.
//   Antuono, Colagrossi, Marrone & Molteni (2010), Comput. Phys. Commun. 181, 532-549: delta-SPH.
//   Marrone, Antuono, Colagrossi, Colicchio, Le Touze & Graziani (2011), Comput. Methods Appl.
//     Mech. Engrg. 200, 1526-1542: delta-SPH for violent flows, the momentum equation.
//   Adami, Hu & Adams (2012), J. Comput. Phys. 231, 7057-7075: the wall pressure, eq. 27.
#include <vector>

#include "core/base/particles.hpp"
#include "core/kernels/sph_kernels.hpp"
#include "core/search/neighbour_search.hpp"
#include "core/walls/wall_sample_reactions.hpp"
#include "core/walls/wall_samples.hpp"

namespace mps_lab::wcsph {

// The Tait equation of state (Batchelor 1967; Monaghan 1994):
//   p = B ((rho / rho0)^gamma - 1),  B = rho0 c0^2 / gamma,  gamma = 7.
struct TaitEquation {
  double rest_density = 1000.0;  // rho0, kg/m^3
  double sound_speed = 30.0;     // c0, m/s
  double exponent = 7.0;         // gamma

  double stiffness() const { return rest_density * sound_speed * sound_speed / exponent; }  // B, Pa
  double pressure(double density) const;                                                    // Pa
  // The inverse, rho = rho0 (1 + p / B)^(1/gamma), kg/m^3; p <= -B (no density) gives rho0 * 1e-3.
  double density(double pressure) const;
};

// How the delta-term is formed.
enum class DensityDiffusion {
  None,               // delta = 0: the plain continuity equation
  MolteniColagrossi,  // psi_ij = 2 (rho_j - rho_i) (x_j - x_i) / |x_j - x_i|^2
  Antuono,            // psi_ij as above minus (<grad rho>^L_i + <grad rho>^L_j), renormalised gradients
};
// "none" | "molteni_colagrossi" | "antuono"
DensityDiffusion density_diffusion_from_name(const std::string& name);

enum class Viscosity {
  Artificial,  // Monaghan (1992), in the delta-SPH form
  Laminar,     // Morris et al. (1997), with the scene's kinematic viscosity
};

// What every operator reads. `density`, `velocity` and `pressure` hold a value for every
// particle: for fluid the state at which the derivatives are evaluated, for wall particles
// rho_w and p_w of adami_wall_pressure() and velocity 0.
struct FluidState {
  const ParticleSet& particles;
  const NeighbourList& neighbours;
  const WallSampleList& samples;
  const SphKernel& kernel;
  double mass = 0.0;  // m, kg/m (per unit depth)
  const std::vector<double>& density;
  const std::vector<Vec2>& velocity;
  const std::vector<double>& pressure;
  const TaitEquation& eos;
  Vec2 gravity = Vec2(0.0, -9.81);  // m/s^2
  bool clamp_negative_wall_pressure = true;
};

// Adami et al. (2012) eq. 27 with a fixed wall (a_w = 0), for every wall particle w:
//   p_w = [sum_f p_f W_wf + g . sum_f rho_f (x_w - x_f) W_wf] / sum_f W_wf
// over its non-ghost fluid neighbours f, then max(p_w, 0) when `clamp_negative`; rho_w is the
// Tait density of p_w. A wall particle without fluid neighbours gets p_w = 0, rho_w = rho0.
// Reads the fluid entries of `pressure` and `density`, writes the wall entries.
void adami_wall_pressure(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                         const TaitEquation& eos, const Vec2& gravity, bool clamp_negative,
                         std::vector<double>& pressure, std::vector<double>& density);

// The renormalised density gradient of Antuono et al. (2010) (Randles & Libersky 1996):
//   <grad rho>^L_i = L_i sum_j (rho_j - rho_i) grad W_ij V_j,
//   L_i = [sum_j grad W_ij (x_j - x_i)^T V_j]^-1,
// over fluid neighbours, exact for a linear density whatever the support's truncation. Where
// |det L_i^-1| < 0.1 (a particle with almost no neighbours; 1 with full support) the sum is
// used without L_i. 0 for non-fluid particles.
void renormalised_density_gradient(const FluidState& state, std::vector<Vec2>& gradient);

// The delta-term alone, kg/(m^3 s), for fluid particles (0 elsewhere):
//   D_i = delta h c0 sum_j psi_ij . grad W_ij V_j   (Antuono et al. 2010; Marrone et al. 2011)
// over fluid neighbours, psi_ij by `form` (the gradient is read for Antuono only).
void density_diffusion(const FluidState& state, DensityDiffusion form, double delta_h_c0,
                       const std::vector<Vec2>& gradient, std::vector<double>& out);

// The continuity equation, kg/(m^3 s), for fluid particles (0 elsewhere):
//   D rho_i / Dt = rho_i sum_j (u_i - u_j) . grad W_ij V_j   (Monaghan 1992; Marrone et al. 2011)
// over every non-ghost neighbour (walls with u = 0) and wall sample (V_w = m V_w / rho_w).
void continuity(const FluidState& state, std::vector<double>& out);

// What the momentum equation adds besides the pressure gradient and gravity.
struct ViscositySettings {
  Viscosity model = Viscosity::Artificial;
  double alpha_h_c0 = 0.0;           // alpha h c0, m^2/s (artificial)
  double kinematic_viscosity = 0.0;  // nu, m^2/s (laminar)
  double eta2 = 0.0;                 // eta^2 = (0.1 h)^2 of both denominators, m^2
};

// One pair's contribution to a_i (without gravity): the pressure gradient and the viscous term of
// momentum() below, for a neighbour at r_ij = x_i - x_j with pressure p_j, density rho_j, velocity
// u_j, mass m_j. Shared by momentum() and the reaction on wall particles (add_momentum_wall_reactions).
struct MomentumPair {
  const FluidState& state;
  const ViscositySettings& viscosity;
  double p_i, rho_i;
  Vec2 u_i;

  Vec2 operator()(const Vec2& r_ij, double p_j, double rho_j, const Vec2& u_j, double m_j) const {
    const Vec2 grad = state.kernel.gradient(r_ij);
    const double volume = m_j / rho_j;
    // Marrone et al. (2011): -(1/rho_i) sum_j (p_i + p_j) grad W_ij V_j
    Vec2 a = -(p_i + p_j) * volume / rho_i * grad;
    const double r2 = r_ij.squaredNorm() + viscosity.eta2;
    if (viscosity.model == Viscosity::Artificial) {
      // Monaghan (1992), Antuono et al. (2010): alpha h c0 (rho0/rho_i) pi_ij grad W_ij V_j,
      // pi_ij = (u_j - u_i) . (x_j - x_i) / |x_j - x_i|^2
      const double pi_ij = (u_j - u_i).dot(-r_ij) / r2;
      a += viscosity.alpha_h_c0 * state.eos.rest_density / rho_i * pi_ij * volume * grad;
    } else {
      // Morris et al. (1997): nu m_j (rho_i + rho_j) / (rho_i rho_j) F_ij (u_i - u_j)
      const double factor = r_ij.dot(grad) / r2;
      a += viscosity.kinematic_viscosity * m_j * (rho_i + rho_j) / (rho_i * rho_j) * factor * (u_i - u_j);
    }
    return a;
  }
};

// The momentum equation, m/s^2, for fluid particles (0 elsewhere):
//   a_i = g - (1/rho_i) sum_j (p_i + p_j) grad W_ij V_j              (Marrone et al. 2011)
//       + artificial:  alpha h c0 (rho0 / rho_i) sum_j pi_ij grad W_ij V_j,
//                      pi_ij = (u_j - u_i) . (x_j - x_i) / (|x_j - x_i|^2 + eta^2)
//                      (Monaghan 1992, as written by Antuono et al. 2010)
//       | laminar:     nu sum_j m (rho_i + rho_j) / (rho_i rho_j) F_ij (u_i - u_j),
//                      F_ij = r_ij . grad W_ij / (|r_ij|^2 + eta^2)   (Morris et al. 1997)
// over every non-ghost neighbour and wall sample.
void momentum(const FluidState& state, const ViscositySettings& viscosity, std::vector<Vec2>& acceleration);

// The fluid's reaction on wall particles at the state of momentum() (docs/walls.md, "Loads on
// obstacles"): for every wall particle j, minus the sum over its fluid neighbours i of m times
// j's MomentumPair term for i (pressure and viscosity); adds to `reaction`, N/m.
void add_momentum_wall_reactions(const FluidState& state, const ViscositySettings& viscosity,
                                 std::vector<Vec2>& reaction);
// The same on wall samples (core/walls/wall_sample_reactions.hpp): adds to `loads` minus m times each
// sample's MomentumPair term in momentum() (its pressure clamped and its Tait density as there), per
// obstacle; `scratch` is reused storage.
void add_momentum_sample_reactions(const FluidState& state, const ViscositySettings& viscosity,
                                   std::vector<Vec2>& scratch, WallSampleLoads& loads);

// The time-step limits, s (docs/methods/wcsph.md, "Time step"):
//   acoustic (CFL):  C l0 / (c0 + v_max)                              (Monaghan 1992)
//   viscous:         0.125 h^2 / nu, nu = alpha h c0 / 8 (artificial, 2-D; Monaghan 2005) or
//                    the kinematic viscosity (laminar; Morris et al. 1997)
//   force:           0.25 sqrt(h / a_max)                             (Monaghan 1992)
// A limit whose denominator is 0 is infinite.
double acoustic_time_step(double courant, double spacing, double sound_speed, double max_speed);
double viscous_time_step(double smoothing_length, double kinematic_viscosity);
double force_time_step(double smoothing_length, double max_acceleration);

}  // namespace mps_lab::wcsph
