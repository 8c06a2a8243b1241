#include "core/diagnostics.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "core/neighbour_search.hpp"

namespace mps_lab {

std::size_t label_fluid_bodies(const ParticleSet& particles, double link_distance, std::vector<int>& label,
                               int& largest) {
  const std::size_t n = particles.size();
  std::vector<ParticleType> fluid_only(particles.type);
  for (auto& kind : fluid_only) {
    if (kind != ParticleType::Fluid) kind = ParticleType::Ghost;  // search fluid only
  }
  const NeighbourList links = find_neighbours(particles.position, fluid_only, link_distance);
  label.assign(n, -1);
  std::vector<std::size_t> sizes;
  std::vector<std::uint32_t> stack;
  for (std::size_t seed = 0; seed < n; ++seed) {
    if (fluid_only[seed] != ParticleType::Fluid || label[seed] >= 0) continue;
    const int component = static_cast<int>(sizes.size());
    sizes.push_back(0);
    stack.assign(1, static_cast<std::uint32_t>(seed));
    label[seed] = component;
    while (!stack.empty()) {
      const std::uint32_t i = stack.back();
      stack.pop_back();
      ++sizes.back();
      for (std::uint32_t k = links.begin(i); k < links.end(i); ++k) {
        const std::uint32_t j = links.indices[k];
        if (label[j] < 0) {
          label[j] = component;
          stack.push_back(j);
        }
      }
    }
  }
  largest = sizes.empty() ? -1
                          : static_cast<int>(std::max_element(sizes.begin(), sizes.end()) - sizes.begin());
  return sizes.size();
}

FlowMeasures measure_flow(const ParticleSet& particles, const Scene& scene) {
  FlowMeasures out;
  const double l0 = scene.particle_spacing;
  const double mass = scene.physics.density * l0 * l0;  // kg per metre of depth
  const double back_wall = scene.domain.min.x();
  const double bed = scene.domain.min.y();
  const double wall_surface = back_wall + 0.5 * l0;
  const double probe_limit = wall_surface + scene.diagnostics.height_probe_width * l0;

  std::vector<int> label;
  int largest = -1;
  label_fluid_bodies(particles, scene.diagnostics.front_link_distance * l0, label, largest);

  double bulk_front = -std::numeric_limits<double>::infinity();
  double any_front = bulk_front;
  double top = -std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < particles.size(); ++i) {
    switch (particles.type[i]) {
      case ParticleType::Wall: ++out.wall; continue;
      case ParticleType::Ghost: ++out.ghost; continue;
      case ParticleType::Fluid: ++out.fluid; break;
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
  }
  out.front = std::isfinite(bulk_front) ? bulk_front - back_wall : 0.0;
  out.front_max_x = std::isfinite(any_front) ? any_front - back_wall : 0.0;
  out.height = std::isfinite(top) ? top - bed : 0.0;
  return out;
}

}  // namespace mps_lab
