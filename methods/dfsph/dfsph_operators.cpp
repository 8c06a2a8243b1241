#include "methods/dfsph/dfsph_operators.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>
#include <stdexcept>
#include <utility>

#include "core/search/for_each_neighbour.hpp"
#include "core/walls/wall_reactions.hpp"

namespace mps_lab::dfsph {

namespace {

// W_ij and grad_i W_ij of one pair, |r_ij| computed once: = kernel.value(|r_ij|), kernel.gradient(r_ij).
inline void evaluate_kernel(const SphKernel& kernel, const Vec2& r_ij, double& value, Vec2& gradient) {
  const double r = r_ij.norm();  // m
  value = kernel.value(r);
  gradient = r <= 0.0 || r >= kernel.support() ? Vec2::Zero() : Vec2(kernel.derivative(r) / r * r_ij);
}

// Both forms of compute_kernel_cache; `boundary_mass` null: every row, without the neighbour
// masses; else the rows of fluid particles only, with them.
void fill_kernel_cache(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                       double particle_mass, const std::vector<double>* boundary_mass, KernelCache& cache) {
  const std::size_t pairs = neighbours.indices.size();
  const bool weighted = boundary_mass != nullptr;
  cache.value.resize(pairs);
  cache.gradient.resize(pairs);
  cache.self_value = kernel.value(0.0);
  const auto n = static_cast<std::ptrdiff_t>(neighbours.particle_count());
  cache.neighbour_mass.resize(weighted ? static_cast<std::size_t>(n) : 0);
  if (weighted) {
#pragma omp parallel for schedule(static) if (n >= kThreadedLoopMinimum)
    for (std::ptrdiff_t j = 0; j < n; ++j) {
      cache.neighbour_mass[j] = neighbour_mass_of(particles, particle_mass, *boundary_mass, j);
    }
  }
#pragma omp parallel for schedule(static) if (n >= kThreadedLoopMinimum)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (weighted && particles.type[i] != ParticleType::Fluid) continue;
    for_each_neighbour(neighbours, i, [&](std::uint32_t k, std::uint32_t j) {
      evaluate_kernel(kernel, particles.position[i] - particles.position[j], cache.value[k], cache.gradient[k]);
    });
  }
}

}  // namespace

void compute_kernel_cache(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                          KernelCache& cache) {
  fill_kernel_cache(particles, neighbours, kernel, 0.0, nullptr, cache);
}

void compute_kernel_cache(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                          double particle_mass, const std::vector<double>& boundary_mass, KernelCache& cache) {
  fill_kernel_cache(particles, neighbours, kernel, particle_mass, &boundary_mass, cache);
}

void compute_sample_cache(const ParticleSet& particles, const WallSampleList& samples, const SphKernel& kernel,
                          double rest_density, double lattice_volume, SampleCache& cache) {
  const std::size_t count = samples.samples.size();
  cache.value.resize(count);
  cache.gradient.resize(count);
  cache.mass.resize(count);
  cache.own.resize(count);
  cache.reaction.resize(count);
  cache.owner.resize(count);
  cache.by_source_offsets.clear();
  cache.by_source.clear();
  if (!samples.has_samples()) return;
  const std::size_t n = particles.size();
  const auto count_n = static_cast<std::ptrdiff_t>(n);
#pragma omp parallel for schedule(static) if (count_n >= kThreadedLoopMinimum)
  for (std::ptrdiff_t i = 0; i < count_n; ++i) {
    for_each_neighbour(samples, i, [&](std::uint32_t k, const WallSample& w) {
      const Vec2 r_iw = particles.position[i] - w.position;
      const double psi = rest_density * w.volume * lattice_volume;  // Psi_w = rho0 V_w
      const Vec2 gradient = kernel.gradient(r_iw);
      const Vec2 moved = w.velocity_map.transpose() * gradient;  // M^T grad W_iw
      cache.value[k] = kernel.value(r_iw.norm());
      cache.gradient[k] = gradient;
      cache.mass[k] = psi;
      cache.owner[k] = static_cast<std::uint32_t>(i);
      // D rho_i/Dt gets Psi (v_i - M v_s) . grad W: for s = i the sample moves with i itself.
      const bool own = w.source == static_cast<std::uint32_t>(i);
      cache.own[k] = psi * (own ? Vec2(gradient - moved) : gradient);
      cache.reaction[k] = own ? Vec2::Zero() : Vec2(psi * moved);
    });
  }
  // The samples of other particles by source (in owner order: deterministic).
  cache.by_source_offsets.assign(n + 1, 0);
  for (std::size_t k = 0; k < count; ++k) {
    if (samples.samples[k].source != cache.owner[k]) ++cache.by_source_offsets[samples.samples[k].source + 1];
  }
  for (std::size_t j = 0; j < n; ++j) cache.by_source_offsets[j + 1] += cache.by_source_offsets[j];
  cache.by_source.resize(cache.by_source_offsets[n]);
  std::vector<std::uint32_t> fill(cache.by_source_offsets.begin(), cache.by_source_offsets.end() - 1);
  for (std::size_t k = 0; k < count; ++k) {
    const std::uint32_t source = samples.samples[k].source;
    if (source != cache.owner[k]) cache.by_source[fill[source]++] = static_cast<std::uint32_t>(k);
  }
}

BoundaryVolume boundary_volume_from_name(const std::string& name) {
  if (name == "akinci") return BoundaryVolume::Akinci;
  if (name == "lattice") return BoundaryVolume::Lattice;
  throw std::invalid_argument("unknown boundary volume rule '" + name + "' (expected akinci or lattice)");
}

void compute_boundary_masses(const ParticleSet& particles, const NeighbourList& neighbours, const KernelCache& kernel,
                             int wall_layers, double rest_density, BoundaryVolume rule, double lattice_volume,
                             std::vector<double>& boundary_mass) {
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
    for_each_neighbour(neighbours, b, [&](std::uint32_t k, std::uint32_t) {
      if (uses(neighbours.indices[k])) number_density += kernel.value[k];
    });
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
    for_each_neighbour(list, i, [&](std::uint32_t k, std::uint32_t j) {
      if (particles.type[j] == ParticleType::Fluid) {
        fluid_sum += system.kernel.value[k];
      } else if (is_boundary(particles, system, j)) {
        boundary_sum += system.boundary_mass[j] * system.kernel.value[k];
      }
    });
    if (system.has_samples()) {
      const auto& w = *system.sample_kernel;
      for_each_neighbour(*system.samples, i, [&](std::uint32_t k, const WallSample&) {
        boundary_sum += w.mass[k] * w.value[k];  // a wall sample: a boundary particle of mass Psi_w
      });
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
    for_each_neighbour(list, i, [&](std::uint32_t k, std::uint32_t j) {
      if (particles.type[j] == ParticleType::Fluid) {
        const Vec2 term = m * system.kernel.gradient[k];
        gradient_sum += term;
        squared_sum += term.squaredNorm();
      } else if (is_boundary(particles, system, j)) {
        gradient_sum += system.boundary_mass[j] * system.kernel.gradient[k];
      }
    });
    if (system.has_samples()) {
      // First term: G_ii of the samples. Second term: the samples that move with another
      // fluid particle j (images of j) add -Psi M^T grad W_iw to G_ij, grouped with the pair
      // term of j when j is a listed neighbour (docs/methods/dfsph.md, "Wall boundary models").
      const auto& w = *system.sample_kernel;
      const auto& samples = *system.samples;
      bool foreign = false;
      for_each_neighbour(samples, i, [&](std::uint32_t k, const WallSample& wall) {
        gradient_sum += w.own[k];
        foreign = foreign || wall.source != static_cast<std::uint32_t>(i);
      });
      if (foreign) {
        squared_sum = 0.0;  // recomputed with the images grouped by their source
        for_each_neighbour(list, i, [&](std::uint32_t k, std::uint32_t j) {
          if (particles.type[j] != ParticleType::Fluid) return;
          Vec2 term = m * system.kernel.gradient[k];
          for_each_neighbour(samples, i, [&](std::uint32_t q, const WallSample& wall) {
            if (wall.source == j) term += w.reaction[q];
          });
          squared_sum += term.squaredNorm();
        });
        for_each_neighbour(samples, i, [&](std::uint32_t q, const WallSample& wall) {
          const std::uint32_t j = wall.source;
          if (j == static_cast<std::uint32_t>(i)) return;
          const bool listed = any_neighbour(list, i, [&](std::uint32_t neighbour) {
            return neighbour == j && particles.type[j] == ParticleType::Fluid;
          });
          if (!listed) squared_sum += w.reaction[q].squaredNorm();
        });
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
    for_each_neighbour(list, i, [&](std::uint32_t k, std::uint32_t j) {
      if (particles.type[j] == ParticleType::Fluid) {
        sum += m * (vi - particles.velocity[j]).dot(system.kernel.gradient[k]);
      } else if (is_boundary(particles, system, j)) {
        // v_b: 0, or the velocity of a moving obstacle (core/walls/moving_walls.hpp)
        sum += system.boundary_mass[j] * (vi - particles.prescribed_wall_velocity(j)).dot(system.kernel.gradient[k]);
      }
    });
    if (system.has_samples()) {
      const auto& w = *system.sample_kernel;
      for_each_neighbour(*system.samples, i, [&](std::uint32_t k, const WallSample&) {
        const Vec2 uw = sample_velocity(system.samples->samples[k], particles.velocity);  // u_w = M v_s, now
        sum += w.mass[k] * (vi - uw).dot(w.gradient[k]);
      });
    }
    rate[i] = sum;  // [BK17] eq. (9)
  }
}

void add_viscous_acceleration(const ParticleSet& particles, const SphSystem& system, const std::vector<double>& density,
                              double kinematic_viscosity, double support, std::vector<Vec2>& acceleration) {
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
    for_each_neighbour(list, i, [&](std::uint32_t k, std::uint32_t j) {
      double mass = 0.0, rho_j = 0.0;
      Vec2 vj = Vec2::Zero();
      if (particles.type[j] == ParticleType::Fluid) {
        mass = m;
        rho_j = density[j];
        vj = particles.velocity[j];
      } else if (is_boundary(particles, system, j)) {
        mass = system.boundary_mass[j];
        rho_j = rho0;
        vj = particles.prescribed_wall_velocity(j);  // no slip: at rest, or a moving obstacle's velocity
      } else {
        return;
      }
      const Vec2 r_ij = particles.position[i] - particles.position[j];
      sum += viscous_pair(mass, rho_i, rho_j, r_ij, system.kernel.gradient[k], eta2, particles.velocity[i], vj);
    });
    if (system.has_samples()) {
      for_each_neighbour(*system.samples, i, [&](std::uint32_t k, const WallSample&) {
        sum += viscous_sample_pair(particles, system, rho_i, eta2, static_cast<std::size_t>(i), k);
      });
    }
    acceleration[i] += kinematic_viscosity * sum;
  }
}

namespace {

// s_b of every boundary particle (0 elsewhere): 0 under wall_pressure = mirrored; under
// extrapolated the wall's own p_b / rho0^2 from the fluid's s_f = p_f / rho_f^2 ([AHA12] eq. (27),
// extrapolated_wall_stiffness) plus its hydrostatic part, m^5/(kg s^2).
std::vector<double> boundary_wall_stiffness(const SphSystem& system, const std::vector<double>& s,
                                            const std::vector<double>& density) {
  std::vector<double> wall_s(s.size(), 0.0);
  if (system.wall_pressure == nullptr) return wall_s;
  const WallPressureStencil& stencil = *system.wall_pressure;
  for (std::size_t r = 0; r < stencil.boundary.size(); ++r) {
    const std::uint32_t b = stencil.boundary[r];
    wall_s[b] =
        extrapolated_wall_stiffness(stencil, r, s.data(), density, system.rest_density) + stencil.hydrostatic[b];
  }
  return wall_s;
}

// The reaction of every boundary particle to fluid whose s_f is `s` (boundary_pressure_force).
template <class Use>
void for_each_boundary_force(const ParticleSet& particles, const SphSystem& system, const SphKernel& kernel,
                             const std::vector<double>& s, const std::vector<double>& density, Use use) {
  const std::vector<double> wall_s = boundary_wall_stiffness(system, s, density);
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static) if (n >= kThreadedLoopMinimum)
  for (std::ptrdiff_t b = 0; b < n; ++b) {
    if (particles.type[b] == ParticleType::Wall)
      use(b, boundary_pressure_force(particles, system, kernel, b, s, wall_s[b]));
  }
}

}  // namespace

void compute_boundary_pressures(ParticleSet& particles, const SphSystem& system, const SphKernel& kernel,
                                const std::vector<double>& density, double face_length) {
  std::vector<double> s(particles.size(), 0.0);  // p_f / rho_f^2 of the fluid particles
  for (std::size_t f = 0; f < particles.size(); ++f) {
    if (particles.type[f] == ParticleType::Fluid) s[f] = particles.pressure[f] / (density[f] * density[f]);
  }
  for_each_boundary_force(particles, system, kernel, s, density, [&](std::ptrdiff_t b, const Vec2& force) {
    particles.pressure[b] = force.norm() / face_length;
  });
}

Vec2 boundary_pressure_force(const ParticleSet& particles, const SphSystem& system, const SphKernel& kernel,
                             std::size_t b, const std::vector<double>& s, double wall_s) {
  const double m = system.particle_mass;
  Vec2 force = Vec2::Zero();  // N per metre of depth
  if (system.boundary_mass[b] <= 0.0) return force;
  for_each_neighbour(system.neighbours, b, [&](std::uint32_t f) {
    if (particles.type[f] != ParticleType::Fluid) return;
    // Reaction to the boundary term of the solvers' pressure correction on f:
    // m Psi_b (s_f + s_b) grad_f W_fb, and grad_f W_fb = -grad_b W_bf (evaluated here:
    // the step's kernel cache holds the rows of fluid particles only).
    force -=
        m * system.boundary_mass[b] * (s[f] + wall_s) * kernel.gradient(particles.position[b] - particles.position[f]);
  });
  return force;
}

void add_boundary_pressure_reactions(const ParticleSet& particles, const SphSystem& system, const SphKernel& kernel,
                                     const std::vector<double>& density, const std::vector<double>& density_stiffness,
                                     const std::vector<double>& divergence_stiffness, std::vector<Vec2>& reaction) {
  const std::size_t count = particles.size();
  std::vector<double> s(count, 0.0);  // the corrections' total s_f, m^5/(kg s^2)
  for (std::size_t f = 0; f < count; ++f) {
    if (particles.type[f] == ParticleType::Fluid) s[f] = (density_stiffness[f] + divergence_stiffness[f]) / density[f];
  }
  for_each_boundary_force(particles, system, kernel, s, density,
                          [&](std::ptrdiff_t b, const Vec2& force) { reaction[b] += force; });
}

void add_boundary_viscous_reactions(const ParticleSet& particles, const SphSystem& system, const SphKernel& kernel,
                                    const std::vector<double>& density, double kinematic_viscosity,
                                    std::vector<Vec2>& reaction) {
  const double h = 0.5 * kernel.support();
  const double eta2 = 0.01 * h * h;  // as add_viscous_acceleration
  const double m = system.particle_mass;
  add_wall_reactions(
      particles, system.neighbours,
      [&](std::size_t f, std::size_t b) -> Vec2 {
        if (!is_boundary(particles, system, b)) return Vec2::Zero();
        const Vec2 r_fb = particles.position[f] - particles.position[b];
        return (m * kinematic_viscosity) * viscous_pair(system.boundary_mass[b], density[f], system.rest_density, r_fb,
                                                        kernel.gradient(r_fb), eta2, particles.velocity[f],
                                                        particles.prescribed_wall_velocity(b));
      },
      reaction);
}

void count_active_neighbours(const ParticleSet& particles, const SphSystem& system, std::vector<double>& counts) {
  const auto& list = system.neighbours;
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
  // A pair at the very edge of the support (W below 1e-9 W(0), e.g. exactly 2 l0 apart on
  // the initial lattice, where rounding decides whether it is in the list) does not count.
  const double negligible = 1e-9 * system.kernel.self_value;
  counts.resize(particles.size());
#pragma omp parallel for schedule(static) if (n >= kThreadedLoopMinimum)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    counts[i] = 0.0;
    if (particles.type[i] != ParticleType::Fluid) continue;
    std::uint32_t count = 0;
    for_each_neighbour(list, i, [&](std::uint32_t k, std::uint32_t j) {
      if (system.kernel.value[k] <= negligible) return;
      count += particles.type[j] == ParticleType::Fluid || is_boundary(particles, system, j);
    });
    double weighted = static_cast<double>(count);
    if (system.has_samples()) {
      for_each_neighbour(*system.samples, i, [&](std::uint32_t k, const WallSample&) {
        if (system.sample_kernel->value[k] > negligible) weighted += system.samples->samples[k].volume;
      });
    }
    counts[i] = weighted;
  }
}

void add_sample_hydrostatic_acceleration(const ParticleSet& particles, const SphSystem& system,
                                         const std::vector<double>& density, const Vec2& gravity,
                                         std::vector<Vec2>& acceleration) {
  if (!system.has_samples()) return;
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static) if (n >= kThreadedLoopMinimum)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (particles.type[i] != ParticleType::Fluid) continue;
    Vec2 sum = Vec2::Zero();
    for_each_neighbour(*system.samples, i, [&](std::uint32_t k, const WallSample&) {
      sum -= sample_hydrostatic_pair(particles, system, density, gravity, k);
    });
    acceleration[i] += sum;
  }
}

WallPressure wall_pressure_from_name(const std::string& name) {
  if (name == "mirrored") return WallPressure::Mirrored;
  if (name == "extrapolated") return WallPressure::Extrapolated;
  throw std::invalid_argument("unknown wall pressure '" + name + "' (expected mirrored or extrapolated)");
}

namespace {

// The rows of the wall samples at rest that carry their owner's pressure (WallPressureStencil):
// [AHA12] eq. (27) at x_w over the owner i and its fluid neighbours.
void compute_sample_stencil(const ParticleSet& particles, const SphSystem& system, const SphKernel& kernel,
                            const std::vector<double>& density, const Vec2& gravity, WallPressureStencil& stencil) {
  stencil.sample_offsets.clear();
  stencil.sample_fluid.clear();
  stencil.sample_weight.clear();
  stencil.sample_hydrostatic.clear();
  if (!system.has_samples()) return;
  const WallSampleList& samples = *system.samples;
  const double rho0 = system.rest_density;
  stencil.sample_offsets.assign(samples.samples.size() + 1, 0);
  stencil.sample_hydrostatic.assign(samples.samples.size(), 0.0);
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] != ParticleType::Fluid) continue;
    for_each_neighbour(samples, i, [&](std::uint32_t q, const WallSample& wall) {
      const std::size_t first = stencil.sample_fluid.size();
      if (is_resting_own_sample(wall, static_cast<std::uint32_t>(i))) {
        double weight_sum = 0.0, offset = 0.0;  // 1/m^2, Pa/m^2
        const auto add = [&](std::uint32_t f) {
          const Vec2 r_wf = wall.position - particles.position[f];
          const double w = kernel.value(r_wf.norm());
          if (w <= 0.0) return;
          stencil.sample_fluid.push_back(f);
          stencil.sample_weight.push_back(w);
          weight_sum += w;
          offset += density[f] * gravity.dot(r_wf) * w;  // [AHA12] eq. (27), a_w = 0
        };
        add(static_cast<std::uint32_t>(i));
        for_each_neighbour(system.neighbours, i, [&](std::uint32_t f) {
          if (particles.type[f] == ParticleType::Fluid) add(f);
        });
        for (std::size_t k = first; k < stencil.sample_fluid.size(); ++k) stencil.sample_weight[k] /= weight_sum;
        if (weight_sum > 0.0) stencil.sample_hydrostatic[q] = std::max(offset / weight_sum, 0.0) / (rho0 * rho0);
      }
      stencil.sample_offsets[q + 1] = static_cast<std::uint32_t>(stencil.sample_fluid.size());
    });
  }
}

}  // namespace

void compute_wall_pressure_stencil(const ParticleSet& particles, const SphSystem& system, const SphKernel& kernel,
                                   const std::vector<double>& density, const Vec2& gravity,
                                   WallPressureStencil& stencil) {
  const auto& list = system.neighbours;
  const double rho0 = system.rest_density;
  stencil.boundary.clear();
  stencil.offsets.assign(1, 0);
  stencil.fluid.clear();
  stencil.weight.clear();
  stencil.hydrostatic.assign(particles.size(), 0.0);
  for (std::size_t b = 0; b < particles.size(); ++b) {
    if (!is_boundary(particles, system, b)) continue;
    const std::size_t first = stencil.fluid.size();
    double weight_sum = 0.0;  // sum_f W_bf, 1/m^2
    double offset = 0.0;      // sum_f rho_f (g - a_b).(x_b - x_f) W_bf, Pa/m^2
    // a_b: the wall particle's acceleration (a moving obstacle, core/walls/moving_walls.hpp; 0 at rest)
    const Vec2 body_force = gravity - particles.prescribed_wall_acceleration(b);  // m/s^2
    for_each_neighbour(list, b, [&](std::uint32_t f) {
      if (particles.type[f] != ParticleType::Fluid) return;
      const Vec2 r_bf = particles.position[b] - particles.position[f];
      const double w = kernel.value(r_bf.norm());
      if (w <= 0.0) return;
      stencil.fluid.push_back(f);
      stencil.weight.push_back(w);
      weight_sum += w;
      offset += density[f] * body_force.dot(r_bf) * w;  // [AHA12] eq. (27)
    });
    if (weight_sum <= 0.0) continue;
    for (std::size_t k = first; k < stencil.fluid.size(); ++k) stencil.weight[k] /= weight_sum;
    // A wall point above its fluid (near the free surface on a side wall) would get a negative
    // hydrostatic part and pull the fluid onto the wall: clamped at 0, as the pressures are.
    stencil.hydrostatic[b] = std::max(offset / weight_sum, 0.0) / (rho0 * rho0);
    stencil.boundary.push_back(static_cast<std::uint32_t>(b));
    stencil.offsets.push_back(static_cast<std::uint32_t>(stencil.fluid.size()));
  }
  compute_sample_stencil(particles, system, kernel, density, gravity, stencil);
}

void add_wall_hydrostatic_acceleration(const ParticleSet& particles, const SphSystem& system, const Vec2& gravity,
                                       std::vector<Vec2>& acceleration) {
  const auto& list = system.neighbours;
  const WallPressureStencil* stencil = system.wall_pressure;
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static) if (n >= kThreadedLoopMinimum)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (particles.type[i] != ParticleType::Fluid) continue;
    Vec2 sum = Vec2::Zero();  // sum Psi s_hyd grad W, m/s^2
    if (stencil != nullptr) {
      for_each_neighbour(list, i, [&](std::uint32_t k, std::uint32_t j) {
        if (is_boundary(particles, system, j))
          sum += system.boundary_mass[j] * stencil->hydrostatic[j] * system.kernel.gradient[k];
      });
    }
    if (system.has_samples()) {
      for_each_neighbour(*system.samples, i, [&](std::uint32_t k, const WallSample&) {
        sum += wall_hydrostatic_sample_pair(particles, system, gravity, k);
      });
    }
    acceleration[i] -= sum;  // [BGI18]: the wall's own pressure in the symmetric force
  }
}

void hydrostatic_stiffness(const ParticleSet& particles, const NeighbourList& neighbours,
                           const std::vector<double>& neighbour_counts, double full_count, double gravity,
                           double spacing, std::vector<double>& stiffness) {
  const std::size_t n = particles.size();
  const double unreached = std::numeric_limits<double>::infinity();
  std::vector<double> depth(n, unreached);  // m
  using Entry = std::pair<double, std::uint32_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> front;
  for (std::size_t i = 0; i < n; ++i) {  // the free surface: fluid particles short of neighbours
    if (particles.type[i] != ParticleType::Fluid || neighbour_counts[i] >= full_count - 1e-9) continue;
    depth[i] = 0.5 * spacing;  // the surface is half a spacing beyond the particle's centre
    front.emplace(depth[i], static_cast<std::uint32_t>(i));
  }
  while (!front.empty()) {  // Dijkstra over the fluid pairs of the neighbour list
    const auto [d, i] = front.top();
    front.pop();
    if (d > depth[i]) continue;
    for_each_neighbour(neighbours, i, [&](std::uint32_t, std::uint32_t j) {
      if (particles.type[j] != ParticleType::Fluid) return;
      const double through_i = d + (particles.position[i] - particles.position[j]).norm();
      if (through_i < depth[j]) {
        depth[j] = through_i;
        front.emplace(through_i, j);
      }
    });
  }
  stiffness.assign(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    if (depth[i] < unreached) stiffness[i] = gravity * depth[i];  // kappa = |g| d, m^2/s^2
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

void add_sample_pressure_reactions(const ParticleSet& particles, const SphSystem& system,
                                   const std::vector<double>& density, const std::vector<double>& density_stiffness,
                                   const std::vector<double>& divergence_stiffness, std::vector<Vec2>& scratch,
                                   WallSampleLoads& loads) {
  if (!system.has_samples()) return;
  std::vector<double> s(particles.size(), 0.0);  // the corrections' total s_f, m^5/(kg s^2)
  for (std::size_t f = 0; f < particles.size(); ++f) {
    if (particles.type[f] == ParticleType::Fluid) s[f] = (density_stiffness[f] + divergence_stiffness[f]) / density[f];
  }
  const SampleCache& cache = *system.sample_kernel;
  const WallPressureStencil* stencil = system.wall_pressure;
  const double m = system.particle_mass;
  add_wall_sample_reactions(
      particles, *system.samples,
      [&](std::size_t i, std::uint32_t q, const WallSample&) -> Vec2 {
        // dfsph_solvers.cpp, correct: i moved by -dt (s_i + s_w) own[q]; the source, if another
        // particle, by +dt s_i reaction[q] (its image's constraint); s_w the sample's own
        // extrapolated p_w / rho0^2 (wall_pressure = extrapolated), else 0.
        const double s_w = stencil != nullptr
                               ? extrapolated_sample_stiffness(*stencil, q, s.data(), density, system.rest_density)
                               : 0.0;
        return m * (s[i] * cache.reaction[q] - (s[i] + s_w) * cache.own[q]);
      },
      scratch, loads);
}

void add_sample_viscous_reactions(const ParticleSet& particles, const SphSystem& system,
                                  const std::vector<double>& density, double kinematic_viscosity, double support,
                                  std::vector<Vec2>& scratch, WallSampleLoads& loads) {
  if (!system.has_samples()) return;
  const double h = 0.5 * support;
  const double eta2 = 0.01 * h * h;  // as add_viscous_acceleration
  const double m = system.particle_mass;
  add_wall_sample_reactions(
      particles, *system.samples,
      [&](std::size_t i, std::uint32_t q, const WallSample&) -> Vec2 {
        return (m * kinematic_viscosity) * viscous_sample_pair(particles, system, density[i], eta2, i, q);
      },
      scratch, loads);
}

void add_sample_hydrostatic_reactions(const ParticleSet& particles, const SphSystem& system,
                                      const std::vector<double>& density, const Vec2& gravity, bool sample_offset,
                                      bool wall_pressure, std::vector<Vec2>& scratch, WallSampleLoads& loads) {
  if (!system.has_samples() || (!sample_offset && !wall_pressure)) return;
  const double m = system.particle_mass;
  add_wall_sample_reactions(
      particles, *system.samples,
      [&](std::size_t, std::uint32_t q, const WallSample&) -> Vec2 {
        Vec2 acceleration = Vec2::Zero();  // m/s^2, as the two explicit accelerations give i
        if (sample_offset) acceleration -= sample_hydrostatic_pair(particles, system, density, gravity, q);
        if (wall_pressure) acceleration -= wall_hydrostatic_sample_pair(particles, system, gravity, q);
        return m * acceleration;
      },
      scratch, loads);
}

}  // namespace mps_lab::dfsph
