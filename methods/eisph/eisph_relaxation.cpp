#include "methods/eisph/eisph_relaxation.hpp"

#include <algorithm>
#include <cmath>

#include "core/search/for_each_neighbour.hpp"
#include "methods/isph/isph_operators.hpp"
#include "methods/isph/isph_surface.hpp"

namespace mps_lab::eisph {

void adami_wall_pressure(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                         const std::vector<double>& density, const Vec2& gravity, std::vector<double>& pressure) {
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t w = 0; w < n; ++w) {
    if (particles.type[w] != ParticleType::Wall) continue;
    // Adami, Hu & Adams (2012), eq. 27 with a fixed wall:
    //   p_w = (sum_f p_f W_wf + g . sum_f rho_f (x_w - x_f) W_wf) / sum_f W_wf
    double weight_sum = 0.0, weighted_pressure = 0.0;
    Vec2 head = Vec2::Zero();  // sum_f rho_f (x_w - x_f) W_wf, kg/m^2
    for_each_neighbour(neighbours, w, [&](std::uint32_t f) {
      if (particles.type[f] != ParticleType::Fluid) return;
      const Vec2 between = particles.position[w] - particles.position[f];
      const double weight = kernel.value(between.norm());
      weight_sum += weight;
      weighted_pressure += weight * pressure[f];
      head += density[f] * weight * between;
    });
    pressure[w] = weight_sum > 0.0 ? (weighted_pressure + gravity.dot(head)) / weight_sum : 0.0;
  }
}

namespace {

// sum_j a_ij p_j^n and sum_j a_ij of fluid row i over the neighbours and wall samples (with the
// hydrostatic part of a sample's pressure). a_ij in m/kg (per unit depth), a_ij p in 1/s^2.
struct RowSums {
  double weighted = 0.0;  // sum_j a_ij p_j^n (+ the samples' terms), 1/s^2
  double diagonal = 0.0;  // sum_j a_ij (samples of another source only), m/kg
};

RowSums row_sums(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                 const SphKernel& kernel, const std::vector<double>& density, const RelaxationSettings& settings,
                 const std::vector<double>& previous, std::size_t i) {
  RowSums sums;
  for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
    if (particles.type[j] == ParticleType::Ghost) return;
    const double factor =
        isph::laplacian_pair_factor(kernel, particles.position[i] - particles.position[j], settings.eta2);
    // Cummins & Rudman (1999) / Shao & Lo (2003): a_ij = -m 8/(rho_i + rho_j)^2 F_ij
    const double a = isph::ppe_pair_coefficient(settings.mass, density[i], density[j], factor);
    sums.diagonal += a;
    sums.weighted += a * previous[j];
  });
  for_each_neighbour(samples, i, [&](const WallSample& wall) {
    const std::uint32_t s = wall.source;
    if (particles.type[s] == ParticleType::Ghost) return;
    const double factor = isph::laplacian_pair_factor(kernel, particles.position[i] - wall.position, settings.eta2);
    const double a = isph::ppe_pair_coefficient(settings.mass * wall.volume, density[i], settings.rest_density, factor);
    // a_iw (p_w - p_i), p_w = p_s + rho0 g . (x_w - x_s): the hydrostatic part is known
    sums.weighted += a * sample_pressure_offset(wall, particles.position, settings.rest_density, settings.gravity);
    if (s == i) return;  // p_s - p_i cancels: a Neumann wall
    sums.diagonal += a;
    sums.weighted += a * previous[s];
  });
  return sums;
}

}  // namespace

SweepResult relaxation_sweep(const ParticleSet& particles, const NeighbourList& neighbours,
                             const WallSampleList& samples, const SphKernel& kernel, const std::vector<double>& density,
                             const std::vector<double>& free_surface, const std::vector<double>& source,
                             const RelaxationSettings& settings, const std::vector<double>& previous,
                             std::vector<double>& pressure, const std::vector<double>* surface_factor) {
  const double omega = settings.relaxation;
  for_each_fluid_particle(particles, [&](std::ptrdiff_t i) {
    if (free_surface[i] != 0.0) {
      const double factor = surface_factor != nullptr ? (*surface_factor)[i] : 0.0;
      // (SURF) from p^n at the water surface beyond it, or Dirichlet p = 0 at its centre
      pressure[i] = factor > 0.0 ? isph::water_surface_pressure(particles, neighbours, kernel, factor,
                                                                static_cast<std::size_t>(i), previous)
                                 : 0.0;
      return;
    }
    const RowSums sums = row_sums(particles, neighbours, samples, kernel, density, settings, previous, i);
    if (sums.diagonal == 0.0) {  // no neighbour within the support: p = 0
      pressure[i] = 0.0;
      return;
    }
    // Hosseini et al. (2007) / notes step 7.2: one (weighted) Jacobi sweep of (PPE) from p^n
    const double jacobi = (sums.weighted - source[i]) / sums.diagonal;
    pressure[i] = (1.0 - omega) * previous[i] + omega * jacobi;
  });
  // The statistics in particle order (one thread: the same bits for any thread count).
  SweepResult result;
  double change2 = 0.0, pressure2 = 0.0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] != ParticleType::Fluid) continue;
    if (free_surface[i] != 0.0) {
      ++result.surface;
      continue;
    }
    ++result.unknowns;
    const double change = pressure[i] - previous[i];
    change2 += change * change;
    pressure2 += pressure[i] * pressure[i];
    result.largest_change = std::max(result.largest_change, std::fabs(change));
  }
  result.relative_change = pressure2 > 0.0 ? std::sqrt(change2 / pressure2) : 0.0;
  return result;
}

}  // namespace mps_lab::eisph
