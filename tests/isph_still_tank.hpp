#pragma once
// The still-water tank (scenes/hydrostatic.json) as isph's operators see it at t = 0, for the
// unit tests of its surface (tests/test_isph_surface.cpp) and of the wall samples' pressure
// (tests/test_isph_wall_sample_pressure.cpp).
#include <memory>
#include <string>
#include <vector>

#include "core/io/geometry.hpp"
#include "core/kernels/sph_kernels.hpp"
#include "core/search/neighbour_search.hpp"
#include "core/walls/wall_samples.hpp"
#include "core/walls/wall_treatment.hpp"
#include "support.hpp"

namespace mps_lab::testing {

constexpr double kRho = 1000.0, kG = 9.81;  // kg/m^3, m/s^2

// The still-water tank (scenes/hydrostatic.json) with isph's boundary model `model`, as the method
// sees it at t = 0: the lattice, its neighbours within the support (2.4 l0, the default cubic
// spline) and the model's wall samples (none for adami_wall_particles, which has wall particles).
struct Tank {
  Scene scene;
  ParticleSet particles;
  NeighbourList neighbours;
  WallSampleList samples;
  SphKernel kernel = SphKernel(SphKernelKind::CubicSpline, 2.4 * 0.025);
  double top = 0.0;  // m, the top row's centres
};

inline std::unique_ptr<Tank> still_tank(const std::string& model) {
  auto tank = std::make_unique<Tank>();
  Tank& t = *tank;
  t.scene = load("hydrostatic.json", {"method=isph", "methods.isph.wall_treatments={\"" + model + "\":{}}"});
  WallTreatmentSet walls(t.scene.method_config("isph").wall_treatments, t.scene);
  t.particles = build_particles(t.scene, walls.wall_particles());
  t.neighbours = find_neighbours(t.particles.position, t.particles.type, t.kernel.support());
  if (!walls.wall_particles()) {
    WallContext context{t.particles, &t.neighbours, 0.0, t.scene};
    context.support = t.kernel.support();
    walls.build_wall_samples(context, t.samples);
  }
  t.top = fluid_top(t.particles);
  return tank;
}

inline std::vector<double> top_row(const ParticleSet& particles, double top) {
  std::vector<double> surface(particles.size(), 0.0);
  for (std::size_t i = 0; i < particles.size(); ++i) {
    surface[i] = particles.type[i] == ParticleType::Fluid && particles.position[i].y() > top - 1e-9 ? 1.0 : 0.0;
  }
  return surface;
}

// p = rho g (top + delta - y): hydrostatic under a surface delta above the top row's centres.
inline std::vector<double> hydrostatic(const ParticleSet& particles, double top, double delta) {
  std::vector<double> p(particles.size(), 0.0);
  for (std::size_t i = 0; i < p.size(); ++i) p[i] = kRho * kG * (top + delta - particles.position[i].y());
  return p;
}

}  // namespace mps_lab::testing
