#pragma once
// Geometry builders: the particles of a scene on the lattice of spec §4.
//
// Every particle sits on the lattice x = domain.min + (i, j) l0. Walls: `layers` rows or
// columns of wall particles per wall side, the first on the domain boundary, the others
// outside it; bottom/top rows span the full width including the corners, side columns
// span the open interval between bottom and top. Fluid: the lattice points strictly
// inside each fluid block (spec §4 note). For the spec's dam break this gives exactly
// 171 fluid + 273 wall = 444 particles at l0 = 0.025.
#include "core/base/particles.hpp"
#include "core/io/scene.hpp"

namespace mps_lab {

// Throws InputError if the domain is not a whole number of spacings wide and high
// (walls must close on the lattice) or if a fluid block holds no lattice point. The scene
// loader calls it, so these errors come before anything runs.
void check_lattice(const Scene& scene);

// Throws the errors of check_lattice. `wall_particles` false: fluid only, for boundary models
// that represent the wall by samples (core/walls/wall_samples.hpp). Obstacles (walls.obstacles)
// get `layers` wall layers from their sides inwards; fluid lattice points inside them are
// left out.
ParticleSet build_particles(const Scene& scene, bool wall_particles = true);

// The margin beyond the domain after which a fluid particle leaves the computation,
// l0 (layers + 1) (spec §7.3).
double escape_margin(const Scene& scene);

// Turns fluid particles beyond the escape margin, or with a non-finite position, into
// ghosts (spec §7.3). Returns how many particles became ghosts.
std::size_t mark_escaped_as_ghosts(ParticleSet& particles, const Scene& scene);

// The pressure of still water in the scene's fluid blocks, Pa, per particle: p = rho0 |g| (h_s - h),
// h = x . (-g/|g|) the height against gravity and h_s the block's highest particle centre +
// `surface_offset` (m), 0 above h_s; 0 for particles that are not fluid or lie in no block (a
// particle in two blocks belongs to the first), and everywhere without gravity. The start of
// methods whose pressure carries over from step to step (wcsph's equation of state; eisph's one
// sweep per step, methods.eisph.initial_pressure): still water starts in equilibrium instead of
// falling until the pressure builds. surface_offset is where the method's p = 0 lies above the top
// particle centres (wcsph: l0/2, the water surface).
std::vector<double> hydrostatic_block_pressure(const Scene& scene, const ParticleSet& particles, double surface_offset);

}  // namespace mps_lab
