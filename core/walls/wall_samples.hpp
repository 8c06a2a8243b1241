#pragma once
// Wall samples: the wall as a method's operators see it when the boundary model does not put
// wall particles into the ParticleSet (dummy_layers, mirror_particles, distance_function in
// core/walls/; docs/walls.md).
//
// A boundary model fills, after each neighbour search, a list of samples per fluid particle i:
// the points of the wall within the operator support of i. Every operator of every method
// then adds, beside its sum over particle neighbours, the same sum over the samples of i,
// with these rules:
//   position   x_w                       (m)
//   volume     V_w = volume l0^2         (a lattice point has volume 1: it counts as one
//                                         particle in n_i, as m = rho0 V_w in an SPH sum)
//   velocity   u_w = velocity_map u_s + wall_velocity
//                                        (s = source; the zero matrix for a fixed wall,
//                                         a reflection for a mirror image; wall_velocity is 0
//                                         for a wall at rest, (I - velocity_map) u_wall for a
//                                         moving one: the image of u_s relative to the wall)
//   pressure   p_w = p_s + rho0 (g - a_wall) . (x_w - x_s)
//              (hydrostatic extrapolation from the source particle s; Adami, Hu & Adams
//               2012 eq. 27 with the fluid sum restricted to s, a_wall the wall's
//               acceleration; for s = i the wall terms of the PPE become known values)
// s is i itself (dummy layers, distance function: a Neumann wall that carries the particle's
// own pressure) or the fluid particle j the sample mirrors (mirror particles).
//
// Loads on obstacles (core/walls/obstacle_loads.hpp, docs/walls.md "Loads on obstacles"): each
// sample names the solid it stands for, `obstacle` = k for walls.obstacles[k], -1 for the tank.
// The force the fluid puts on the sample (the reaction of its pair terms, one entry per sample)
// is summed per obstacle (sum_wall_sample_loads, core/walls/wall_sample_reactions.hpp).
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "core/base/particles.hpp"
#include "core/base/types.hpp"

namespace mps_lab {

using Mat2 = Eigen::Matrix2d;

struct WallSample {
  Vec2 position = Vec2::Zero();      // x_w, m
  Mat2 velocity_map = Mat2::Zero();  // u_w = velocity_map * u_source
  std::uint32_t source = 0;          // the particle whose pressure and velocity it carries
  std::int32_t obstacle = -1;        // walls.obstacles[obstacle], or -1: the tank (kNoObstacle)
  double volume = 1.0;               // V_w / l0^2
  // A moving wall (walls.obstacles[k].motion): the velocity term of u_w (above) and the wall's
  // acceleration a_wall at x_w; zero for a wall at rest.
  Vec2 wall_velocity = Vec2::Zero();      // m/s
  Vec2 wall_acceleration = Vec2::Zero();  // m/s^2
};

// The obstacle tag fills the padding after `source`: a sample stays 96 bytes (docs/walls.md, the cost
// of moving samples).
static_assert(sizeof(WallSample) == 96, "WallSample grew: measure the samples' memory and time again");

// Compressed rows as NeighbourList: the samples of particle i are
// samples[offsets[i] .. offsets[i+1]). Empty (no offsets) when the boundary model is made of
// particles; then has_samples() is false and every operator skips the wall-sample sums.
struct WallSampleList {
  std::vector<std::uint32_t> offsets;
  std::vector<WallSample> samples;

  bool has_samples() const { return !offsets.empty(); }
  std::uint32_t begin(std::size_t i) const { return offsets[i]; }
  std::uint32_t end(std::size_t i) const { return offsets[i + 1]; }
  void clear() {
    offsets.clear();
    samples.clear();
  }
};

// p_w of a sample (see above), Pa.
inline double sample_pressure(const WallSample& sample, const std::vector<double>& pressure,
                              const std::vector<Vec2>& position, double rest_density, const Vec2& gravity) {
  return pressure[sample.source] +
         rest_density * (gravity - sample.wall_acceleration).dot(sample.position - position[sample.source]);
}

// The hydrostatic part rho0 (g - a_wall) . (x_w - x_s) alone, Pa: what the PPE moves to its
// right-hand side.
inline double sample_pressure_offset(const WallSample& sample, const std::vector<Vec2>& position, double rest_density,
                                     const Vec2& gravity) {
  return rest_density * (gravity - sample.wall_acceleration).dot(sample.position - position[sample.source]);
}

// A dry wall point: one above fluid particle i at x_i (against `gravity`, m/s^2) whose pressure
// p_w (Pa; a sample's hydrostatic extension before any clamp) is not above 0, i.e. in the air
// above the water. The methods' option dry_wall_points "excluded" (isph, eisph, mps) leaves such
// points out of i's pressure gradient and its reaction. Wall particles and samples alike.
// `below` (m, 0 by default): the point counts as dry also when it lies less than that below x_i
// (DryWallRule::level_tolerance below; never without gravity).
inline bool dry_wall_point(const Vec2& x_i, const Vec2& x_w, double p_w, const Vec2& gravity, double below = 0.0) {
  return p_w <= 0.0 && (x_w - x_i).dot(gravity) < below * gravity.norm();
}

// Which wall points enter the pressure gradient of fluid particle i: the methods' parameter
// dry_wall_points (mps: "extended" | "excluded", docs/methods/mps.md, "Dry wall points"; isph and
// eisph: "clamped" | "excluded", docs/methods/isph.md). With exclude = false every wall point enters
// as the method has it; with exclude = true a dry wall point (dry_wall_point above: above i, with a
// pressure not above 0; a sample's the hydrostatic extension p_s + rho0 g . (x_w - x_s), before any
// clamp) is in the air and left out of i's gradient, of what the gradient is built from (mps's
// P_min and GC's M_i, isph's renormalisation) and of the reactions.
//
// `level_tolerance` (m, 0 by default) widens the rule for wall particles: one whose pressure is not
// above 0 is dry also when it lies less than that distance below i. mps sets it to its water
// surface's offset (free_surface_offset): the surface lies that far above the surface particles'
// centres, so a wall particle that close below i holding P <= 0 (a solved wall particle at the
// water line whose P went to 0) is above the water, not the water's zero; left in, it set P_min
// of the fluid beside it to 0 and lifted it along the wall (docs/methods/mps.md, "The water line
// on the wall").
struct DryWallRule {
  bool exclude = false;
  Vec2 gravity = Vec2::Zero();   // m/s^2
  double density = 1000.0;       // kg/m^3: of the samples' hydrostatic extension
  double level_tolerance = 0.0;  // m: wall particles only (above)
  bool excludes(const Vec2& x_i, const Vec2& x_w, double p_w) const {
    return exclude && dry_wall_point(x_i, x_w, p_w, gravity);
  }
  // Neighbour j of fluid particle i: only a wall particle can be dry.
  bool excludes_particle(const ParticleSet& particles, std::size_t i, std::size_t j) const {
    return exclude && particles.type[j] == ParticleType::Wall &&
           dry_wall_point(particles.position[i], particles.position[j], particles.pressure[j], gravity,
                          level_tolerance);
  }
  bool excludes_sample(const ParticleSet& particles, std::size_t i, const WallSample& wall) const {
    return exclude && excludes(particles.position[i], wall.position,
                               sample_pressure(wall, particles.pressure, particles.position, density, gravity));
  }
};

// u_w of a sample, m/s.
inline Vec2 sample_velocity(const WallSample& sample, const std::vector<Vec2>& velocity) {
  return sample.velocity_map * velocity[sample.source] + sample.wall_velocity;
}

}  // namespace mps_lab
