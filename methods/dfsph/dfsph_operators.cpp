#include "methods/dfsph/dfsph_operators.hpp"

#include <cmath>
#include <stdexcept>

namespace mps_lab::dfsph {

void compute_kernel_cache(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                          KernelCache& cache) {
  cache.value.resize(neighbours.indices.size());
  cache.gradient.resize(neighbours.indices.size());
  cache.self_value = kernel.value(0.0);
  const auto n = static_cast<std::ptrdiff_t>(neighbours.particle_count());
#pragma omp parallel for schedule(static) if (n >= kThreadedLoopMinimum)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    for (std::uint32_t k = neighbours.begin(i); k < neighbours.end(i); ++k) {
      const Vec2 r_ij = particles.position[i] - particles.position[neighbours.indices[k]];
      cache.value[k] = kernel.value(r_ij.norm());
      cache.gradient[k] = kernel.gradient(r_ij);
    }
  }
}

BoundaryVolume boundary_volume_from_name(const std::string& name) {
  if (name == "akinci") return BoundaryVolume::Akinci;
  if (name == "lattice") return BoundaryVolume::Lattice;
  throw std::invalid_argument("unknown boundary volume rule '" + name + "' (expected akinci or lattice)");
}

void compute_boundary_masses(const ParticleSet& particles, const NeighbourList& neighbours,
                             const KernelCache& kernel, int wall_layers, double rest_density,
                             BoundaryVolume rule, double lattice_volume, std::vector<double>& boundary_mass) {
  const auto uses = [&](std::size_t j) {
    return particles.type[j] == ParticleType::Wall && particles.wall_layer[j] <= wall_layers;
  };
  boundary_mass.assign(particles.size(), 0.0);
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static) if (n >= kThreadedLoopMinimum)
  for (std::ptrdiff_t b = 0; b < n; ++b) {
    if (!uses(b)) continue;
    if (rule == BoundaryVolume::Lattice) {
      boundary_mass[b] = rest_density * lattice_volume;
      continue;
    }
    double number_density = kernel.self_value;  // delta_b = sum_k W_bk, k = b included
    for (std::uint32_t k = neighbours.begin(b); k < neighbours.end(b); ++k) {
      if (uses(neighbours.indices[k])) number_density += kernel.value[k];
    }
    boundary_mass[b] = rest_density / number_density;  // Psi_b = rho0 V_b, V_b = 1 / delta_b
  }
}

void compute_densities(const ParticleSet& particles, const SphSystem& system, std::vector<double>& density) {
  const auto& list = system.neighbours;
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
  density.resize(particles.size());
#pragma omp parallel for schedule(static) if (n >= kThreadedLoopMinimum)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (particles.type[i] != ParticleType::Fluid) {
      density[i] = 0.0;
      continue;
    }
    double fluid_sum = system.kernel.self_value;  // sum_j W_ij over fluid j, i included
    double boundary_sum = 0.0;                    // sum_b Psi_b W_ib, kg/m^3
    for (std::uint32_t k = list.begin(i); k < list.end(i); ++k) {
      const std::uint32_t j = list.indices[k];
      if (particles.type[j] == ParticleType::Fluid) {
        fluid_sum += system.kernel.value[k];
      } else if (is_boundary(particles, system, j)) {
        boundary_sum += system.boundary_mass[j] * system.kernel.value[k];
      }
    }
    density[i] = system.particle_mass * fluid_sum + boundary_sum;  // SPH density sum, [AIA12] boundary term
  }
}

void compute_dfsph_factors(const ParticleSet& particles, const SphSystem& system, const std::vector<double>& density,
                           std::vector<double>& alpha) {
  const auto& list = system.neighbours;
  const double m = system.particle_mass;
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
  alpha.resize(particles.size());
#pragma omp parallel for schedule(static) if (n >= kThreadedLoopMinimum)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    alpha[i] = 0.0;
    if (particles.type[i] != ParticleType::Fluid) continue;
    Vec2 gradient_sum = Vec2::Zero();  // sum_j m grad W_ij + sum_b Psi_b grad W_ib
    double squared_sum = 0.0;          // sum_j |m grad W_ij|^2 over fluid j
    for (std::uint32_t k = list.begin(i); k < list.end(i); ++k) {
      const std::uint32_t j = list.indices[k];
      if (particles.type[j] == ParticleType::Fluid) {
        const Vec2 term = m * system.kernel.gradient[k];
        gradient_sum += term;
        squared_sum += term.squaredNorm();
      } else if (is_boundary(particles, system, j)) {
        gradient_sum += system.boundary_mass[j] * system.kernel.gradient[k];
      }
    }
    const double denominator = gradient_sum.squaredNorm() + squared_sum;
    // A particle alone (no neighbour, or only partners exactly at the support) has no
    // pressure coupling: alpha = 0 leaves it to gravity, as the authors' code does.
    alpha[i] = denominator > 0.0 ? density[i] / denominator : 0.0;  // [BK17] eq. (11)
  }
}

void compute_density_change_rate(const ParticleSet& particles, const SphSystem& system, std::vector<double>& rate) {
  const auto& list = system.neighbours;
  const double m = system.particle_mass;
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
  rate.resize(particles.size());
#pragma omp parallel for schedule(static) if (n >= kThreadedLoopMinimum)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    rate[i] = 0.0;
    if (particles.type[i] != ParticleType::Fluid) continue;
    const Vec2 vi = particles.velocity[i];
    double sum = 0.0;
    for (std::uint32_t k = list.begin(i); k < list.end(i); ++k) {
      const std::uint32_t j = list.indices[k];
      if (particles.type[j] == ParticleType::Fluid) {
        sum += m * (vi - particles.velocity[j]).dot(system.kernel.gradient[k]);
      } else if (is_boundary(particles, system, j)) {
        sum += system.boundary_mass[j] * vi.dot(system.kernel.gradient[k]);  // v_b = 0
      }
    }
    rate[i] = sum;  // [BK17] eq. (9)
  }
}

void apply_pressure_velocity_change(ParticleSet& particles, const SphSystem& system,
                                    const std::vector<double>& stiffness_over_density, double dt) {
  const auto& list = system.neighbours;
  const double m = system.particle_mass;
  const auto& s = stiffness_over_density;
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static) if (n >= kThreadedLoopMinimum)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (particles.type[i] != ParticleType::Fluid) continue;
    Vec2 acceleration = Vec2::Zero();  // -(1/rho) grad p, m/s^2
    for (std::uint32_t k = list.begin(i); k < list.end(i); ++k) {
      const std::uint32_t j = list.indices[k];
      if (particles.type[j] == ParticleType::Fluid) {
        acceleration -= m * (s[i] + s[j]) * system.kernel.gradient[k];  // [BK17] eqs. (7)-(8): force along grad rho_i + reactions
      } else if (is_boundary(particles, system, j)) {
        acceleration -= system.boundary_mass[j] * s[i] * system.kernel.gradient[k];  // p_b = p_i, once ([AIA12], authors' code)
      }
    }
    particles.velocity[i] += dt * acceleration;
  }
}

void add_viscous_acceleration(const ParticleSet& particles, const SphSystem& system,
                              const std::vector<double>& density, double kinematic_viscosity, double support,
                              std::vector<Vec2>& acceleration) {
  const auto& list = system.neighbours;
  const double m = system.particle_mass;
  const double rho0 = system.rest_density;
  const double h = 0.5 * support;
  const double eta2 = 0.01 * h * h;  // [MFZ97]: eta = 0.1 h keeps the term finite at r -> 0
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static) if (n >= kThreadedLoopMinimum)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (particles.type[i] != ParticleType::Fluid) continue;
    const double rho_i = density[i];
    Vec2 sum = Vec2::Zero();
    for (std::uint32_t k = list.begin(i); k < list.end(i); ++k) {
      const std::uint32_t j = list.indices[k];
      double mass = 0.0, rho_j = 0.0;
      Vec2 vj = Vec2::Zero();
      if (particles.type[j] == ParticleType::Fluid) {
        mass = m;
        rho_j = density[j];
        vj = particles.velocity[j];
      } else if (is_boundary(particles, system, j)) {
        mass = system.boundary_mass[j];
        rho_j = rho0;
      } else {
        continue;
      }
      const Vec2 r_ij = particles.position[i] - particles.position[j];
      const double weight = r_ij.dot(system.kernel.gradient[k]) / (r_ij.squaredNorm() + eta2);  // 1/m^2
      sum += mass * (rho_i + rho_j) / (rho_i * rho_j) * weight * (particles.velocity[i] - vj);  // [MFZ97] eq. (8)
    }
    acceleration[i] += kinematic_viscosity * sum;
  }
}

void compute_boundary_pressures(ParticleSet& particles, const SphSystem& system, const std::vector<double>& density,
                                double face_length) {
  const auto& list = system.neighbours;
  const double m = system.particle_mass;
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static) if (n >= kThreadedLoopMinimum)
  for (std::ptrdiff_t b = 0; b < n; ++b) {
    if (particles.type[b] != ParticleType::Wall) continue;
    Vec2 force = Vec2::Zero();  // N per metre of depth
    if (system.boundary_mass[b] > 0.0) {
      for (std::uint32_t k = list.begin(b); k < list.end(b); ++k) {
        const std::uint32_t f = list.indices[k];
        if (particles.type[f] != ParticleType::Fluid) continue;
        // Reaction to the boundary term of apply_pressure_velocity_change on f:
        // m Psi_b (p_f / rho_f^2) grad_f W_fb, and grad_f W_fb = -grad_b W_bf (cached for b).
        const double s_f = particles.pressure[f] / (density[f] * density[f]);
        force -= m * system.boundary_mass[b] * s_f * system.kernel.gradient[k];
      }
    }
    particles.pressure[b] = force.norm() / face_length;
  }
}

void count_active_neighbours(const ParticleSet& particles, const SphSystem& system,
                             std::vector<std::uint32_t>& counts) {
  const auto& list = system.neighbours;
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
  // A pair at the very edge of the support (W below 1e-9 W(0), e.g. exactly 2 l0 apart on
  // the initial lattice, where rounding decides whether it is in the list) does not count.
  const double negligible = 1e-9 * system.kernel.self_value;
  counts.resize(particles.size());
#pragma omp parallel for schedule(static) if (n >= kThreadedLoopMinimum)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    std::uint32_t count = 0;
    for (std::uint32_t k = list.begin(i); k < list.end(i); ++k) {
      const std::uint32_t j = list.indices[k];
      if (system.kernel.value[k] <= negligible) continue;
      count += particles.type[j] == ParticleType::Fluid || is_boundary(particles, system, j);
    }
    counts[i] = count;
  }
}

std::uint32_t lattice_neighbour_count(double support, double spacing) {
  const int reach = static_cast<int>(std::ceil(support / spacing)) + 1;
  std::uint32_t count = 0;
  for (int a = -reach; a <= reach; ++a) {
    for (int b = -reach; b <= reach; ++b) count += (a != 0 || b != 0) && spacing * std::hypot(a, b) < support;
  }
  return count;
}

}  // namespace mps_lab::dfsph
