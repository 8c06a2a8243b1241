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

// Both forms of compute_kernel_cache; `boundary_mass` null: every row, without the weighted
// gradients; else the rows of fluid particles only, with them.
void fill_kernel_cache(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                       double particle_mass, const std::vector<double>* boundary_mass, KernelCache& cache) {
  const std::size_t pairs = neighbours.indices.size();
  const bool weighted = boundary_mass != nullptr;
  cache.value.resize(pairs);
  cache.gradient.resize(pairs);
  cache.weighted_gradient.resize(weighted ? pairs : 0);
  cache.self_value = kernel.value(0.0);
  const auto n = static_cast<std::ptrdiff_t>(neighbours.particle_count());
#pragma omp parallel for schedule(static) if (n >= kThreadedLoopMinimum)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (weighted && particles.type[i] != ParticleType::Fluid) continue;
    for_each_neighbour(neighbours, i, [&](std::uint32_t k, std::uint32_t j) {
      evaluate_kernel(kernel, particles.position[i] - particles.position[j], cache.value[k], cache.gradient[k]);
      if (!weighted) return;
      double mass = 0.0;  // kg/m: m (fluid), Psi_b (boundary; 0 for an unused wall layer)
      if (particles.type[j] == ParticleType::Fluid) {
        mass = particle_mass;
      } else if (particles.type[j] == ParticleType::Wall) {
        mass = (*boundary_mass)[j];
      }
      cache.weighted_gradient[k] = mass * cache.gradient[k];
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
      const auto& w = *system.sample_kernel;
      for_each_neighbour(*system.samples, i, [&](std::uint32_t k, const WallSample& sample) {
        const Vec2 uw = sample_velocity(sample, particles.velocity);
        const Vec2 r_iw = particles.position[i] - sample.position;
        const double weight = r_iw.dot(w.gradient[k]) / (r_iw.squaredNorm() + eta2);
        sum += w.mass[k] * (rho_i + rho0) / (rho_i * rho0) * weight * (particles.velocity[i] - uw);
      });
    }
    acceleration[i] += kinematic_viscosity * sum;
  }
}

void compute_boundary_pressures(ParticleSet& particles, const SphSystem& system, const SphKernel& kernel,
                                const std::vector<double>& density, double face_length) {
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
  std::vector<double> s(particles.size(), 0.0);  // p_f / rho_f^2 of the fluid particles
  for (std::size_t f = 0; f < particles.size(); ++f) {
    if (particles.type[f] == ParticleType::Fluid) s[f] = particles.pressure[f] / (density[f] * density[f]);
  }
#pragma omp parallel for schedule(static) if (n >= kThreadedLoopMinimum)
  for (std::ptrdiff_t b = 0; b < n; ++b) {
    if (particles.type[b] != ParticleType::Wall) continue;
    particles.pressure[b] = boundary_pressure_force(particles, system, kernel, b, s).norm() / face_length;
  }
}

Vec2 boundary_pressure_force(const ParticleSet& particles, const SphSystem& system, const SphKernel& kernel,
                             std::size_t b, const std::vector<double>& s) {
  const double m = system.particle_mass;
  Vec2 force = Vec2::Zero();  // N per metre of depth
  if (system.boundary_mass[b] <= 0.0) return force;
  for_each_neighbour(system.neighbours, b, [&](std::uint32_t f) {
    if (particles.type[f] != ParticleType::Fluid) return;
    // Reaction to the boundary term of the solvers' pressure correction on f:
    // m Psi_b s_f grad_f W_fb, and grad_f W_fb = -grad_b W_bf (evaluated here:
    // the step's kernel cache holds the rows of fluid particles only).
    force -= m * system.boundary_mass[b] * s[f] * kernel.gradient(particles.position[b] - particles.position[f]);
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
  const auto n = static_cast<std::ptrdiff_t>(count);
#pragma omp parallel for schedule(static) if (n >= kThreadedLoopMinimum)
  for (std::ptrdiff_t b = 0; b < n; ++b) {
    if (particles.type[b] == ParticleType::Wall)
      reaction[b] += boundary_pressure_force(particles, system, kernel, b, s);
  }
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
  const double rho0 = system.rest_density;
  const auto& w = *system.sample_kernel;
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static) if (n >= kThreadedLoopMinimum)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (particles.type[i] != ParticleType::Fluid) continue;
    Vec2 sum = Vec2::Zero();
    for_each_neighbour(*system.samples, i, [&](std::uint32_t k, const WallSample& sample) {
      const double offset = sample_pressure_offset(sample, particles.position, rho0, gravity);  // Pa
      const double rho_s = density[sample.source];
      sum -= w.mass[k] * offset / (rho_s * rho_s) * w.gradient[k];
    });
    acceleration[i] += sum;
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

}  // namespace mps_lab::dfsph
