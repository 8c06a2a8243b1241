#include "methods/wcsph/wcsph_operators.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/LU>

#include "core/search/for_each_neighbour.hpp"
#include "core/walls/wall_reactions.hpp"

namespace mps_lab::wcsph {

namespace {
// |det| of the moment matrix below which the density gradient is not renormalised: the matrix
// is the identity with full support, has det ~0.5 on a flat free surface, and degenerates only
// for a particle with almost no neighbours, whose renormalised gradient would amplify noise.
constexpr double kMinimumMomentDeterminant = 0.1;

// A wall sample's pressure (clamped as wall particles are) and density.
struct SampleState {
  double pressure = 0.0;  // Pa
  double density = 0.0;   // kg/m^3
};

SampleState sample_state(const FluidState& state, const WallSample& wall) {
  double p = sample_pressure(wall, state.pressure, state.particles.position, state.eos.rest_density, state.gravity);
  if (state.clamp_negative_wall_pressure) p = std::max(p, 0.0);
  return {p, state.eos.density(p)};
}

// A wall sample's MomentumPair term for fluid i (mass m V_w, its pressure and density), m/s^2. Shared by
// momentum() and add_momentum_sample_reactions.
Vec2 sample_pair(const MomentumPair& pair, const FluidState& state, std::size_t i, const WallSample& wall) {
  const SampleState sample = sample_state(state, wall);
  return pair(state.particles.position[i] - wall.position, sample.pressure, sample.density,
              sample_velocity(wall, state.velocity), state.mass * wall.volume);
}
}  // namespace

double TaitEquation::pressure(double density) const {
  return stiffness() * (std::pow(density / rest_density, exponent) - 1.0);  // Tait: B ((rho/rho0)^gamma - 1)
}

double TaitEquation::density(double pressure) const {
  const double base = 1.0 + pressure / stiffness();
  if (base <= 1e-21) return 1e-3 * rest_density;  // (1e-21)^(1/7) = 1e-3
  return rest_density * std::pow(base, 1.0 / exponent);
}

DensityDiffusion density_diffusion_from_name(const std::string& name) {
  if (name == "none") return DensityDiffusion::None;
  if (name == "molteni_colagrossi") return DensityDiffusion::MolteniColagrossi;
  if (name == "antuono") return DensityDiffusion::Antuono;
  throw std::invalid_argument("unknown density diffusion '" + name +
                              "' (expected none, molteni_colagrossi or antuono)");
}

void adami_wall_pressure(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                         const TaitEquation& eos, const Vec2& gravity, bool clamp_negative,
                         std::vector<double>& pressure, std::vector<double>& density) {
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t w = 0; w < n; ++w) {
    if (particles.type[w] != ParticleType::Wall) continue;
    double weight = 0.0, weighted_pressure = 0.0;
    Vec2 head = Vec2::Zero();  // sum_f rho_f (x_w - x_f) W_wf, kg/m^4
    for_each_neighbour(neighbours, w, [&](std::uint32_t f) {
      if (particles.type[f] != ParticleType::Fluid) return;
      const Vec2 r_wf = particles.position[w] - particles.position[f];
      const double W = kernel.value(r_wf.norm());
      weight += W;
      weighted_pressure += pressure[f] * W;
      head += density[f] * r_wf * W;
    });
    double p = 0.0;
    if (weight > 0.0) p = (weighted_pressure + gravity.dot(head)) / weight;  // Adami et al. (2012) eq. 27, a_w = 0
    if (clamp_negative) p = std::max(p, 0.0);
    pressure[w] = p;
    density[w] = weight > 0.0 ? eos.density(p) : eos.rest_density;
  }
}

void renormalised_density_gradient(const FluidState& state, std::vector<Vec2>& gradient) {
  const ParticleSet& particles = state.particles;
  gradient.assign(particles.size(), Vec2::Zero());
  for_each_fluid_particle(particles, [&](std::ptrdiff_t i) {
    Vec2 sum = Vec2::Zero();                           // sum_j (rho_j - rho_i) grad W_ij V_j, kg/m^4
    Eigen::Matrix2d moment = Eigen::Matrix2d::Zero();  // sum_j grad W_ij (x_j - x_i)^T V_j
    for_each_neighbour(state.neighbours, i, [&](std::uint32_t j) {
      if (particles.type[j] != ParticleType::Fluid) return;
      const Vec2 r_ij = particles.position[i] - particles.position[j];
      const Vec2 grad = state.kernel.gradient(r_ij);
      const double volume = state.mass / state.density[j];
      sum += (state.density[j] - state.density[i]) * volume * grad;
      moment -= volume * grad * r_ij.transpose();
    });
    // Antuono et al. (2010): <grad rho>^L_i = L_i sum_j (rho_j - rho_i) grad W_ij V_j
    gradient[i] = std::fabs(moment.determinant()) > kMinimumMomentDeterminant ? Vec2(moment.inverse() * sum) : sum;
  });
}

void density_diffusion(const FluidState& state, DensityDiffusion form, double delta_h_c0,
                       const std::vector<Vec2>& gradient, std::vector<double>& out) {
  const ParticleSet& particles = state.particles;
  out.assign(particles.size(), 0.0);
  if (form == DensityDiffusion::None || delta_h_c0 == 0.0) return;
  const bool renormalised = form == DensityDiffusion::Antuono;
  for_each_fluid_particle(particles, [&](std::ptrdiff_t i) {
    double sum = 0.0;
    for_each_neighbour(state.neighbours, i, [&](std::uint32_t j) {
      if (particles.type[j] != ParticleType::Fluid) return;
      const Vec2 r_ji = particles.position[j] - particles.position[i];
      const double r2 = r_ji.squaredNorm();
      if (r2 <= 0.0) return;
      // psi_ij = 2 (rho_j - rho_i) (x_j - x_i) / |x_j - x_i|^2 [- (<grad rho>^L_i + <grad rho>^L_j)]
      Vec2 psi = 2.0 * (state.density[j] - state.density[i]) / r2 * r_ji;
      if (renormalised) psi -= gradient[i] + gradient[j];
      sum += psi.dot(state.kernel.gradient(-r_ji)) * state.mass / state.density[j];
    });
    out[i] = delta_h_c0 * sum;  // Antuono et al. (2010): delta h c0 sum_j psi_ij . grad W_ij V_j
  });
}

void continuity(const FluidState& state, std::vector<double>& out) {
  const ParticleSet& particles = state.particles;
  out.assign(particles.size(), 0.0);
  for_each_fluid_particle(particles, [&](std::ptrdiff_t i) {
    const Vec2 u_i = state.velocity[i];
    double sum = 0.0;
    for_each_neighbour(state.neighbours, i, [&](std::uint32_t j) {
      if (particles.type[j] == ParticleType::Ghost) return;
      const Vec2 grad = state.kernel.gradient(particles.position[i] - particles.position[j]);
      sum += (u_i - state.velocity[j]).dot(grad) * state.mass / state.density[j];
    });
    for_each_neighbour(state.samples, i, [&](const WallSample& wall) {
      if (particles.type[wall.source] == ParticleType::Ghost) return;
      const SampleState sample = sample_state(state, wall);
      const Vec2 grad = state.kernel.gradient(particles.position[i] - wall.position);
      sum += (u_i - sample_velocity(wall, state.velocity)).dot(grad) * state.mass * wall.volume / sample.density;
    });
    out[i] = state.density[i] * sum;  // D rho_i / Dt = rho_i sum_j (u_i - u_j) . grad W_ij V_j
  });
}

void momentum(const FluidState& state, const ViscositySettings& viscosity, std::vector<Vec2>& acceleration) {
  const ParticleSet& particles = state.particles;
  acceleration.assign(particles.size(), Vec2::Zero());
  for_each_fluid_particle(particles, [&](std::ptrdiff_t i) {
    const MomentumPair pair{state, viscosity, state.pressure[i], state.density[i], state.velocity[i]};
    Vec2 sum = state.gravity;
    for_each_neighbour(state.neighbours, i, [&](std::uint32_t j) {
      if (particles.type[j] == ParticleType::Ghost) return;
      sum += pair(particles.position[i] - particles.position[j], state.pressure[j], state.density[j], state.velocity[j],
                  state.mass);
    });
    for_each_neighbour(state.samples, i, [&](const WallSample& wall) {
      if (particles.type[wall.source] == ParticleType::Ghost) return;
      sum += sample_pair(pair, state, static_cast<std::size_t>(i), wall);
    });
    acceleration[i] = sum;
  });
}

void add_momentum_wall_reactions(const FluidState& state, const ViscositySettings& viscosity,
                                 std::vector<Vec2>& reaction) {
  const ParticleSet& particles = state.particles;
  // The force on fluid i from wall particle j: m times j's MomentumPair term in momentum().
  mps_lab::add_wall_reactions(
      particles, state.neighbours,
      [&](std::size_t i, std::size_t j) -> Vec2 {
        const MomentumPair pair{state, viscosity, state.pressure[i], state.density[i], state.velocity[i]};
        return state.mass * pair(particles.position[i] - particles.position[j], state.pressure[j], state.density[j],
                                 state.velocity[j], state.mass);
      },
      reaction);
}

double acoustic_time_step(double courant, double spacing, double sound_speed, double max_speed) {
  return courant * spacing / (sound_speed + max_speed);  // Monaghan (1992): C l0 / (c0 + v_max)
}

double viscous_time_step(double smoothing_length, double kinematic_viscosity) {
  if (kinematic_viscosity <= 0.0) return std::numeric_limits<double>::infinity();
  return 0.125 * smoothing_length * smoothing_length / kinematic_viscosity;  // Morris et al. (1997)
}

double force_time_step(double smoothing_length, double max_acceleration) {
  if (max_acceleration <= 0.0) return std::numeric_limits<double>::infinity();
  return 0.25 * std::sqrt(smoothing_length / max_acceleration);  // Monaghan (1992)
}

void add_momentum_sample_reactions(const FluidState& state, const ViscositySettings& viscosity,
                                   std::vector<Vec2>& scratch, WallSampleLoads& loads) {
  const ParticleSet& particles = state.particles;
  // The force on fluid i from sample w: m times w's MomentumPair term in momentum().
  add_wall_sample_reactions(
      particles, state.samples,
      [&](std::size_t i, std::uint32_t, const WallSample& wall) -> Vec2 {
        if (particles.type[wall.source] == ParticleType::Ghost) return Vec2::Zero();
        const MomentumPair pair{state, viscosity, state.pressure[i], state.density[i], state.velocity[i]};
        return state.mass * sample_pair(pair, state, i, wall);
      },
      scratch, loads);
}

}  // namespace mps_lab::wcsph
