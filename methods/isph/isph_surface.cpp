#include "methods/isph/isph_surface.hpp"

#include <algorithm>
#include <cstddef>

#include "core/search/for_each_neighbour.hpp"

namespace mps_lab::isph {
namespace {

// How much of wall point `wall` is wet for the normal of the particle at `x`: the part of the
// point's cell (of side l0, `spacing`) that lies below the water the particle stands for, which
// reaches l0/2 above its centre (against gravity `down`, a unit vector). A point Delta above the
// particle spans [Delta - l0/2, Delta + l0/2]: its share is 1 - Delta/l0, clamped to [0, 1] (1
// level with the particle or below it, 0 a spacing or more above). Without gravity (`down`
// zero) every point is wet. A wall rising above the water would otherwise tilt the normal of the
// particle at the contact line towards the fluid (by ~11 degrees on the still-water lattice, where
// it made that particle's (SURF) pressure 1.19 rho g delta; tests/test_isph_surface.cpp). A cut
// at "level" (before 2026-11-29) was a switch: the top row of still water stands level with a wall
// row, and its jitter of ~1e-5 m turned that row in and out of the normal, the contact-line
// factor jumping by 20 % (docs/methods/isph.md, "The water surface").
double wet_share(const Vec2& wall, const Vec2& x, const Vec2& down, double spacing) {
  const double height_above = -(wall - x).dot(down);  // m
  return std::clamp(1.0 - height_above / spacing, 0.0, 1.0);
}

// The outward unit normal of the colour function at surface particle i: -sum_j m_j grad W_ij over
// the fluid neighbours and the wet share of the wall points (wall particles, and samples weighing
// m V_w), normalised; zero when the sum vanishes. The wall points level with or below it complete
// the fluid's support, as the fluid's mirror image would.
Vec2 outward_normal(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                    const SphKernel& kernel, const Vec2& down, double spacing, std::size_t i) {
  const Vec2& x = particles.position[i];
  Vec2 inward = Vec2::Zero();
  for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
    const ParticleType type = particles.type[j];
    if (type == ParticleType::Fluid) {
      inward += kernel.gradient(x - particles.position[j]);
    } else if (type == ParticleType::Wall) {
      inward += wet_share(particles.position[j], x, down, spacing) * kernel.gradient(x - particles.position[j]);
    }
  });
  for_each_neighbour(samples, i, [&](const WallSample& wall) {
    inward += wet_share(wall.position, x, down, spacing) * wall.volume * kernel.gradient(x - wall.position);
  });
  const double length = inward.norm();
  return length > 0.0 ? Vec2(-inward / length) : Vec2::Zero();
}

// factor_i of (SURF) for surface particle i, or 0 when its neighbours do not lie beneath it.
double surface_factor(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                      const SphKernel& kernel, const Vec2& down, double offset, double spacing, std::size_t i) {
  const Vec2 normal = outward_normal(particles, neighbours, samples, kernel, down, spacing, i);
  const double minimum_depth = kMinimumSurfaceDepth * spacing;  // m
  double weight_sum = 0.0;                                      // sum_j W_ij, 1/m^2
  double depth_sum = 0.0;                                       // sum_j W_ij (x_i - x_j) . n_i, 1/m
  for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
    if (particles.type[j] != ParticleType::Fluid) return;
    const Vec2 between = particles.position[i] - particles.position[j];
    const double w = kernel.value(between.norm());
    weight_sum += w;
    depth_sum += w * between.dot(normal);
  });
  if (weight_sum <= 0.0 || depth_sum < minimum_depth * weight_sum) return 0.0;
  const double depth = depth_sum / weight_sum;  // d_i, m
  return offset / ((offset + depth) * weight_sum);
}

}  // namespace

ParameterSpec free_surface_offset_parameter() {
  return number_parameter("free_surface_offset", 0.0, "l0",
                          "where p = 0 lies beyond a free-surface particle, along its normal: 0 at its centre "
                          "(Shao & Lo 2003), 0.5 at the water surface it stands for (methods/isph/isph_surface.hpp)")
      .at_least(0.0)
      .at_most(1.0);
}

ParameterSpec dry_wall_points_parameter() {
  return string_parameter("dry_wall_points", "clamped",
                          "a wall point above a fluid particle with pressure <= 0 (above the water): clamped (enters "
                          "its pressure gradient with p = 0) or excluded (left out of it: air; for loads with "
                          "free_surface_offset, docs/methods/isph.md)")
      .one_of({"clamped", "excluded"});
}

bool excludes_dry_wall_points(const ParameterValues& parameters) {
  return parameters.string("dry_wall_points") == "excluded";
}

void water_surface_factors(const ParticleSet& particles, const NeighbourList& neighbours, const WallSampleList& samples,
                           const SphKernel& kernel, const Vec2& gravity, const std::vector<double>& free_surface,
                           double offset, double spacing, std::vector<double>& factor) {
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
  factor.assign(particles.size(), 0.0);
  if (offset <= 0.0) return;
  const double g = gravity.norm();
  const Vec2 down = g > 0.0 ? Vec2(gravity / g) : Vec2::Zero();  // zero: every wall point is wet
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (particles.type[i] != ParticleType::Fluid || free_surface[i] == 0.0) continue;
    factor[i] =
        surface_factor(particles, neighbours, samples, kernel, down, offset, spacing, static_cast<std::size_t>(i));
  }
}

double water_surface_pressure(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                              double factor_i, std::size_t i, const std::vector<double>& pressure) {
  double sum = 0.0;
  for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
    if (particles.type[j] != ParticleType::Fluid) return;
    sum += kernel.value((particles.position[i] - particles.position[j]).norm()) * pressure[j];
  });
  return factor_i * sum;  // (SURF)
}

}  // namespace mps_lab::isph
