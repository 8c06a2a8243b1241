// The MPS load on obstacles from the wall particles' pressure (methods/mps/mps_loads.hpp).
#include "methods/mps/mps_loads.hpp"

#include <algorithm>
#include <cstddef>

namespace mps_lab::mps {

double surface_pressure(double wall_pressure, double density, const Vec2& gravity, const Vec2& wall_acceleration,
                        const Vec2& normal, double half_spacing) {
  if (wall_pressure <= 0.0) return 0.0;  // dry or on the free surface: no load
  // P_s = P_j + rho (g - a_j) . n l0/2, not below 0 (mps_loads.hpp)
  return std::max(0.0, wall_pressure + density * (gravity - wall_acceleration).dot(normal) * half_spacing);
}

void add_surface_pressure_loads(const ParticleSet& particles, const ObstacleSurface& surface,
                                const std::vector<Vec2>& rotation, double density, const Vec2& gravity,
                                double half_spacing, std::vector<Vec2>& reaction) {
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t j = 0; j < n; ++j) {
    if (particles.type[j] != ParticleType::Wall) continue;
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
