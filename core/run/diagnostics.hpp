#pragma once
// What a researcher measures on a free-surface flow, every series step (series.csv).
//
// Coordinates: the back wall is the domain's left side, the bed its bottom. Particle
// centres of the first wall layer lie on the domain boundary; a particle represents a
// square of side l0, so the wall surface is l0/2 inside the boundary and the fluid edge
// l0/2 beyond the outermost particle centre. Hence
//   front  = max x_i over the bulk fluid - domain.min.x   (wall surface to leading edge, m)
//   height = max y_i over the bulk fluid near the back wall - domain.min.y  (bed surface to
//            the water surface, m)
// For the spec's dam break at t = 0: front = 9 l0 = 0.225 m, height = 19 l0 = 0.475 m.
// "Bulk" is the largest connected body of fluid (particles closer than
// diagnostics.front_link_distance are connected), so single splashed drops do not move the
// front; front_max_x is the raw max over all fluid particles, for comparison.
#include <cstddef>
#include <vector>

#include "core/base/particles.hpp"
#include "core/io/scene.hpp"

#include "core/search/neighbour_search.hpp"

namespace mps_lab {

struct FlowMeasures {
  double front = 0.0;           // m, bulk definition (see above)
  double front_max_x = 0.0;     // m, all fluid particles
  double height = 0.0;          // m, bulk fluid within height_probe_width of the back wall
  double kinetic_energy = 0.0;  // J per metre of depth: sum 1/2 rho l0^2 |v|^2 over fluid
  double max_speed = 0.0;       // m/s over fluid particles
  // Method-independent compressibility: mean |rho_i / rho_lattice - 1| over fluid particles
  // with nearly full support (rho_i >= 0.9 rho_lattice), rho_i the summation density of
  // fluid and wall particles with a cubic spline of support diagnostics.density_support,
  // rho_lattice the same sum on the undisturbed lattice. Every method is measured the same way.
  double density_error = 0.0;
  std::size_t fluid = 0;
  std::size_t wall = 0;
  std::size_t ghost = 0;
};

// Storage of the measures' own neighbour search, body labels and density ratios, kept by
// whoever measures repeatedly (the driver, the stability monitor), so that a measurement in
// the time loop allocates nothing once the particle count is reached.
struct FlowWorkspace {
  CellList cells;
  NeighbourList neighbours;
  std::vector<int> label;  // body of each fluid particle (-1: none)
  std::vector<std::size_t> body_sizes;
  std::vector<std::uint32_t> stack;
  std::vector<double> ratios;  // rho_i / rho_lattice (fluid; 0 elsewhere)
};

FlowMeasures measure_flow(const ParticleSet& particles, const Scene& scene, FlowWorkspace& workspace);
FlowMeasures measure_flow(const ParticleSet& particles, const Scene& scene);  // with a workspace of its own

// FlowMeasures::density_error alone (one neighbour search), for the stability monitor.
double common_density_error(const ParticleSet& particles, const Scene& scene, FlowWorkspace& workspace);
double common_density_error(const ParticleSet& particles, const Scene& scene);

}  // namespace mps_lab
