#include "core/run/diagnostics.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

#include "core/kernels/sph_kernels.hpp"
#include "core/search/for_each_neighbour.hpp"
#include "core/search/neighbour_search.hpp"

namespace mps_lab {

namespace {

// Connected bodies of fluid from a neighbour list (pairs closer than link_distance).
std::size_t label_bodies(const ParticleSet& particles, const NeighbourList& links, double link_distance,
                         FlowWorkspace& workspace, int& largest) {
  const std::size_t n = particles.size();
  const double link2 = link_distance * link_distance;
  std::vector<int>& label = workspace.label;
  std::vector<std::size_t>& sizes = workspace.body_sizes;
  std::vector<std::uint32_t>& stack = workspace.stack;
  label.assign(n, -1);
  sizes.clear();
  for (std::size_t seed = 0; seed < n; ++seed) {
    if (particles.type[seed] != ParticleType::Fluid || label[seed] >= 0) continue;
    const int component = static_cast<int>(sizes.size());
    sizes.push_back(0);
    stack.assign(1, static_cast<std::uint32_t>(seed));
    label[seed] = component;
    while (!stack.empty()) {
      const std::uint32_t i = stack.back();
      stack.pop_back();
      ++sizes.back();
      for_each_neighbour(links, i, [&](std::uint32_t j) {
        if (label[j] >= 0 || particles.type[j] != ParticleType::Fluid) return;
        if ((particles.position[j] - particles.position[i]).squaredNorm() >= link2) return;
        label[j] = component;
        stack.push_back(j);
      });
    }
  }
  largest = sizes.empty() ? -1 : static_cast<int>(std::max_element(sizes.begin(), sizes.end()) - sizes.begin());
  return sizes.size();
}

// rho_i / rho_lattice for particle i: the cubic-spline summation density over fluid and
// wall neighbours, divided by the same sum on the undisturbed lattice (diagnostics.hpp).
double relative_density(const ParticleSet& particles, std::size_t i, const NeighbourList& neighbours,
                        const SphKernel& kernel, double lattice_sum) {
  const Vec2& x = particles.position[i];
  double sum = kernel.value(0.0);
  for_each_neighbour(neighbours, i, [&](std::uint32_t j) { sum += kernel.value((particles.position[j] - x).norm()); });
  return sum / lattice_sum;
}

// relative_density of every fluid particle (0 for the others), in parallel: the sums that
// follow add them in index order, so the result does not depend on the thread count.
void relative_densities(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                        double lattice_sum, std::vector<double>& ratios) {
  ratios.resize(particles.size());
  const auto count = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < count; ++i) {
    ratios[i] = particles.type[i] == ParticleType::Fluid
                    ? relative_density(particles, static_cast<std::size_t>(i), neighbours, kernel, lattice_sum)
                    : 0.0;
  }
}

// The measures' neighbour search, into the workspace's reused storage (cell size = radius).
const NeighbourList& search(const ParticleSet& particles, double radius, FlowWorkspace& workspace) {
  workspace.cells.build(particles.position, particles.type, radius);
  workspace.cells.find_neighbours(particles.position, particles.type, radius, workspace.neighbours);
  return workspace.neighbours;
}

// Particles with nearly full support count in the density error (diagnostics.hpp).
constexpr double kFullSupportRatio = 0.9;

SphKernel density_kernel(const Scene& scene) {
  return SphKernel(SphKernelKind::CubicSpline, scene.diagnostics.density_support * scene.particle_spacing);
}

}  // namespace

double common_density_error(const ParticleSet& particles, const Scene& scene) {
  FlowWorkspace workspace;
  return common_density_error(particles, scene, workspace);
}

FlowMeasures measure_flow(const ParticleSet& particles, const Scene& scene) {
  FlowWorkspace workspace;
  return measure_flow(particles, scene, workspace);
}

double common_density_error(const ParticleSet& particles, const Scene& scene, FlowWorkspace& workspace) {
  const SphKernel kernel = density_kernel(scene);
  const NeighbourList& neighbours = search(particles, kernel.support(), workspace);
  const double lattice_sum = lattice_kernel_sum(kernel, scene.particle_spacing);
  relative_densities(particles, neighbours, kernel, lattice_sum, workspace.ratios);
  const std::vector<double>& ratios = workspace.ratios;
  double deviation = 0.0;
  std::size_t full_support = 0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] != ParticleType::Fluid) continue;
    const double ratio = ratios[i];
    if (ratio >= kFullSupportRatio) {
      deviation += std::fabs(ratio - 1.0);
      ++full_support;
    }
  }
  return full_support > 0 ? deviation / static_cast<double>(full_support) : 0.0;
}

FlowMeasures measure_flow(const ParticleSet& particles, const Scene& scene, FlowWorkspace& workspace) {
  FlowMeasures out;
  const double l0 = scene.particle_spacing;
  const double mass = scene.physics.density * l0 * l0;  // kg per metre of depth
  const double back_wall = scene.domain.min.x();
  const double bed = scene.domain.min.y();
  const double wall_surface = back_wall + 0.5 * l0;
  const double probe_limit = wall_surface + scene.diagnostics.height_probe_width * l0;
  const double link = scene.diagnostics.front_link_distance * l0;
  const SphKernel kernel = density_kernel(scene);

  // One search serves the bodies (radius `link`) and the density sums (kernel support).
  const NeighbourList& neighbours = search(particles, std::max(link, kernel.support()), workspace);
  int largest = -1;
  label_bodies(particles, neighbours, link, workspace, largest);
  const std::vector<int>& label = workspace.label;

  const double lattice_sum = lattice_kernel_sum(kernel, l0);  // reference density / m
  relative_densities(particles, neighbours, kernel, lattice_sum, workspace.ratios);
  const std::vector<double>& ratios = workspace.ratios;

  double bulk_front = -std::numeric_limits<double>::infinity();
  double any_front = bulk_front;
  double top = -std::numeric_limits<double>::infinity();
  double density_deviation = 0.0;
  std::size_t full_support = 0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    switch (particles.type[i]) {
      case ParticleType::Wall:
        ++out.wall;
        continue;
      case ParticleType::Ghost:
        ++out.ghost;
        continue;
      case ParticleType::Fluid:
        ++out.fluid;
        break;
    }
    const Vec2& x = particles.position[i];
    const double speed2 = particles.velocity[i].squaredNorm();
    out.kinetic_energy += 0.5 * mass * speed2;
    out.max_speed = std::max(out.max_speed, std::sqrt(speed2));
    any_front = std::max(any_front, x.x());
    if (label[i] == largest) {
      bulk_front = std::max(bulk_front, x.x());
      if (x.x() < probe_limit) top = std::max(top, x.y());
    }
    const double ratio = ratios[i];
    if (ratio >= kFullSupportRatio) {
      density_deviation += std::fabs(ratio - 1.0);
      ++full_support;
    }
  }
  out.front = std::isfinite(bulk_front) ? bulk_front - back_wall : 0.0;
  out.front_max_x = std::isfinite(any_front) ? any_front - back_wall : 0.0;
  out.height = std::isfinite(top) ? top - bed : 0.0;
  out.density_error = full_support > 0 ? density_deviation / static_cast<double>(full_support) : 0.0;

  return out;
}

}  // namespace mps_lab
