#pragma once
// The pressure-stabilising schemes of MPS, options of the `mps` method beside the spec's scheme
// (docs/methods/mps.md, "Pressure schemes"). d = 2 throughout; r_ij = r_j - r_i, u_ij = u_j - u_i.
// The spec's operators stay in mps_operators.* and mps_pressure.*; this file adds
//   pressure_gradient = cmps   Khayyer & Gotoh (2008): antisymmetric pressure gradient
//   source_term = hs           Khayyer & Gotoh (2009): the time derivative of n written out
//   source_term = ecs          Khayyer & Gotoh (2011): hs plus the error-compensating terms
//   source_term = mixed        Tanaka & Masunaga (2010): velocity divergence plus gamma times
//                              the number-density deviation
//   ppe_laplacian = hl         Khayyer & Gotoh (2010): the higher-order Laplacian of the PPE
//   gradient_correction        Khayyer & Gotoh (2011): the corrective matrix of the gradient (GC)
// Every source term is written as b_i of the system A p = b that mps_pressure.cpp assembles
// (A = -<lap>, so b > 0 where the fluid is compressed), in Pa/m^2.
#include <string>
#include <vector>

#include <Eigen/Core>

#include "core/base/particles.hpp"
#include "core/search/neighbour_search.hpp"
#include "core/walls/wall_samples.hpp"
#include "methods/mps/mps_operators.hpp"

namespace mps_lab::mps {

enum class PressureGradientScheme { Spec, Cmps };
enum class SourceTermScheme { Spec, Hs, Ecs, Mixed };
enum class PpeLaplacianScheme { Spec, Hl };

// The parameter values (the vocabulary of methods.mps.pressure_gradient, source_term and
// ppe_laplacian); the parameter machinery has already refused any other value.
std::vector<std::string> pressure_gradient_choices();
std::vector<std::string> source_term_choices();
std::vector<std::string> ppe_laplacian_choices();
PressureGradientScheme pressure_gradient_scheme(const std::string& value);
SourceTermScheme source_term_scheme(const std::string& value);
PpeLaplacianScheme ppe_laplacian_scheme(const std::string& value);

// The HL coefficient of one pair (Khayyer & Gotoh 2010, 2-D): the Laplacian of the weight,
// d2w/dr2 + (1/r) dw/dr = re / r^3 for w = re/r - 1, divided by n0 (r clamped to r_min as in the
// weight). 1/m^2.
double higher_order_laplacian_coefficient(double r, const OperatorRadius& radius);

// Dn/Dt_i = sum_j dw/dr (r_ij . u_ij) / r = -sum_j (re / r^3) (r_ij . u_ij) over every non-ghost
// neighbour within re (walls with their velocity, 0) and wall sample (V_w times, u_w)
// (Khayyer & Gotoh 2009, the HS source). 1/s.
void number_density_rate(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                         const OperatorRadius& radius, std::vector<double>& out);

// <div u>_i = (d/n0) sum_j (u_ij . r_ij) / |r_ij|^2 w_ij over the same neighbours and samples
// (the MPS divergence model, Koshizuka & Oka 1996; the velocity part of Tanaka & Masunaga 2010).
// 1/s.
void velocity_divergence(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                         const OperatorRadius& radius, std::vector<double>& out);

// What a source term reads besides the particles.
struct SourceTermInputs {
  const std::vector<double>& number_density;  // n*_i at the provisional positions
  const std::vector<double>& rate;            // Dn/Dt_i (hs, ecs) or <div u*>_i (mixed), 1/s
  double n0 = 0.0;                            // of the number-density radius
  double dt = 0.0;                            // s
  double density = 1000.0;                    // kg/m^3
  double mixed_relaxation = 0.0;              // gamma of Tanaka & Masunaga (mixed only)
};

// b_i of one particle for a source-term scheme other than spec:
//   hs:    b_i = (rho / (n0 dt)) Dn/Dt_i                                         (KG 2009)
//   ecs:   b_i = (rho / (n0 dt)) (1 + alpha_i) Dn/Dt_i + beta_i (rho/dt^2)(n*_i - n0)/n0,
//          alpha_i = |n*_i - n0| / n0,  beta_i = |dt Dn/Dt_i / n0|              (KG 2011)
//   mixed: b_i = -(rho / dt) <div u*>_i + gamma (rho/dt^2)(n*_i - n0)/n0        (T&M 2010)
// (the ECS terms of time level k are taken at the provisional state, docs/methods/mps.md).
double source_term(SourceTermScheme scheme, const SourceTermInputs& in, std::size_t i);

// The rate the scheme needs (Dn/Dt or <div u*>), then b_i for every particle (0 for spec: the
// spec's source stays in mps_pressure.cpp). Pa/m^2.
void source_terms(SourceTermScheme scheme, const ParticleSet& particles, const NeighbourList& neighbours,
                  const WallSampleList& samples, const OperatorRadius& radius, const SourceTermInputs& in,
                  std::vector<double>& rate, std::vector<double>& out);

// CMPS (Khayyer & Gotoh 2008):
//   <grad P>_i = (d/n0) sum_j [(P_i + P_j) - (Phat_i + Phat_j)] / |r_ij|^2 r_ij w_ij,
// Phat the minimum pressure of a particle's neighbourhood (the spec's P_min, with the same
// min_includes_self rule), over the neighbours with carries_pressure[j]. The pair term is
// symmetric in i and j, so the force of j on i is minus that of i on j: linear momentum is
// conserved. A wall sample w enters with p_w = p_s + rho g . (x_w - x_s) and Phat_w = Phat_i.
// Writes -(1/rho) <grad P>_i for fluid particles, 0 for the others.
void cmps_pressure_acceleration(const ParticleSet& particles, const NeighbourList& neighbours,
                                const WallSampleList& samples, const OperatorRadius& radius,
                                const std::vector<char>& carries_pressure, double density, const Vec2& gravity,
                                bool min_includes_self, std::vector<double>& minimum_pressure,
                                std::vector<Vec2>& acceleration, const DryWallRule& dry);

// GC, the corrective matrix of the pressure gradient (Khayyer & Gotoh 2011, J. Comput. Phys. 230,
// "Enhancement of stability and accuracy of the moving particle semi-implicit method"):
//   C_i = M_i^-1,   M_i = (d/n0) sum_j w_ij r_ij r_ij^T / |r_ij|^2
// over the gradient's neighbours (pressure-carrying, non-ghost, not left out by `dry`; a wall
// sample V_w times), r
// clamped to r_min as in the weight. The spec's gradient of a pressure P = P_i + a . r_ij is
// M_i a (plus the P_min term, 0 where i is its neighbourhood's minimum), so C_i makes it a at any
// arrangement; on the full lattice M = I (C changes nothing), on a flat free surface
// M = diag(0.85, 0.50): the uncorrected gradient there reads half the vertical one. Where
// det M_i <= kMinimumCorrectionDeterminant (neighbours on a line, or almost none: a sheet, a
// splash) C_i = I, since the inverse would amplify noise. Writes C_i for fluid particles and I
// for the others.
constexpr double kMinimumCorrectionDeterminant = 0.1;  // a flat surface: 0.43; a fluid corner: 0.18
void gradient_correction_matrices(const ParticleSet& particles, const NeighbourList& neighbours,
                                  const WallSampleList& samples, const OperatorRadius& radius,
                                  const std::vector<char>& carries_pressure, std::vector<Eigen::Matrix2d>& correction,
                                  const DryWallRule& dry);

// a_i <- C_i a_i for every fluid particle: the pressure acceleration -(1/rho) <grad P>_i (spec or
// CMPS) is linear in the gradient, so this is -(1/rho) C_i <grad P>_i.
void apply_gradient_correction(const ParticleSet& particles, const std::vector<Eigen::Matrix2d>& correction,
                               std::vector<Vec2>& acceleration);

}  // namespace mps_lab::mps
