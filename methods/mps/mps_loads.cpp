// The MPS load on obstacles from the wall particles' pressure (methods/mps/mps_loads.hpp).
#include "methods/mps/mps_loads.hpp"

#include <algorithm>
#include <cstddef>
#include <cstdint>

#include "core/search/for_each_neighbour.hpp"

namespace mps_lab::mps {

double surface_pressure(double wall_pressure, double density, const Vec2& gravity, const Vec2& wall_acceleration,
                        const Vec2& normal, double half_spacing) {
  if (wall_pressure <= 0.0) return 0.0;  // dry or on the free surface: no load
  // P_s = P_j + rho (g - a_j) . n l0/2, not below 0 (mps_loads.hpp)
  return std::max(0.0, wall_pressure + density * (gravity - wall_acceleration).dot(normal) * half_spacing);
}

void wetted_wall_particles(const ParticleSet& particles, const NeighbourList& neighbours, double radius,
                           std::vector<char>& wetted) {
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
  wetted.assign(particles.size(), 0);
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t j = 0; j < n; ++j) {
    if (particles.type[j] != ParticleType::Wall) continue;
    const Vec2 xj = particles.position[j];
    char any = 0;
    for_each_neighbour(neighbours, static_cast<std::size_t>(j), [&](std::uint32_t i) {
      if (particles.type[i] == ParticleType::Fluid && (particles.position[i] - xj).norm() < radius) any = 1;
    });
    wetted[j] = any;
  }
}

void add_surface_pressure_loads(const ParticleSet& particles, const std::vector<char>& wetted,
                                const ObstacleSurface& surface, const std::vector<Vec2>& rotation, double density,
                                const Vec2& gravity, double half_spacing, std::vector<Vec2>& reaction) {
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t j = 0; j < n; ++j) {
    if (particles.type[j] != ParticleType::Wall || !wetted[j]) continue;
    const SurfaceElement& element = surface.element_of_id[particles.id[j]];
    for (int e = 0; e < element.count; ++e) {
      const SurfaceShare& share = element.shares[e];
      const Vec2 normal = rotated(share.normal, rotation[element.obstacle]);
      const double p = surface_pressure(particles.pressure[j], density, gravity,
                                        particles.prescribed_wall_acceleration(j), normal, half_spacing);
      reaction[j] -= p * share.length * normal;  // F = - P n s (mps_loads.hpp)
    }
  }
}

}  // namespace mps_lab::mps
