#pragma once
// The MPS load on obstacles as the integral of the wall's pressure over the wetted surface
// (methods.mps.obstacle_load = wall_pressure; docs/walls.md, "Loads on obstacles"). The practice of
// MPS for the force on a structure (Koshizuka, Nobe & Oka 1998, "Numerical analysis of breaking
// waves using the moving particle semi-implicit method", Int. J. Numer. Meth. Fluids 26; the
// fluid-structure coupling of Lee et al. and Khayyer & Gotoh): the pressure of the wall particles
// that face the fluid times the surface each stands for,
//   F_j = - sum over j's shares e of  P_s,e n_e s_e        (N/m),
// n_e the outward normal (into the fluid) and s_e the length of the share (core/walls/
// obstacle_surface.hpp). The torque follows from F_j at x_j: F_j is along n_e, and the share's
// foot lies at x_j + n_e l0/2, so the moment about any point is the same at either.
//
// P_s,e, the pressure on the surface: the PPE's P_j is at the particle, l0/2 inside the surface;
// it is carried to the surface along the normal by the wall's momentum balance,
//   P_s = P_j + rho (g - a_j) . n_e  l0/2                  (Pa)
// (dP/dn = rho (g - a_w) . n at a wall: the fluid there moves with the wall; the same condition
// as Adami et al. 2012's wall pressure), a_j the wall particle's prescribed acceleration. Without
// it a box of height H would carry rho g (H - l0) W instead of rho g H W (a face's particle row is
// l0/2 inside it). A particle with P_j <= 0 (dry, or on the free surface: spec §5.2-5 sets P = 0
// there) carries no load, and P_s < 0 is taken as 0: a wall does not pull on the water (the
// spec's clamp, §5.2-7, for the same reason), also when clamp_negative_pressure is off. Only a
// wetted wall particle (a fluid particle within re) carries load: where two walls touch (a body
// resting on the bed), the walls' own number density gives their particles a pressure from the
// solve with no water there.
#include <vector>

#include "core/base/particles.hpp"
#include "core/search/neighbour_search.hpp"
#include "core/walls/obstacle_surface.hpp"

namespace mps_lab::mps {

// The surface pressure of a share with outward normal n (rotated to now) at wall particle j, Pa.
double surface_pressure(double wall_pressure, double density, const Vec2& gravity, const Vec2& wall_acceleration,
                        const Vec2& normal, double half_spacing);

// wetted[j] = 1 if wall particle j has a fluid neighbour within `radius` (m), else 0; 0 for fluid.
void wetted_wall_particles(const ParticleSet& particles, const NeighbourList& neighbours, double radius,
                           std::vector<char>& wetted);

// reaction[j] += F_j for every wetted surface wall particle j of an obstacle (the others unchanged):
// P_j = particles.pressure[j]; rotation[k] = (cos, sin) of obstacle k now (obstacle_rotations).
// density rho, kg/m^3; gravity, m/s^2; half_spacing l0/2, m.
void add_surface_pressure_loads(const ParticleSet& particles, const std::vector<char>& wetted,
                                const ObstacleSurface& surface, const std::vector<Vec2>& rotation, double density,
                                const Vec2& gravity, double half_spacing, std::vector<Vec2>& reaction);

}  // namespace mps_lab::mps
