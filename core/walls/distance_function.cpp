// Distance-function (polygon) walls: no wall particles at all (docs/walls.md). The wall's part
// of every operator sum of a fluid particle i is a function of i's distance d to each wall
// segment (core/walls/wall_geometry.hpp): the sum over a virtual wall that fills the half-plane
// behind the segment with points on lattice rows parallel to it, at depths (k + 1/2) l0 / q
// behind the surface and spaced l0 / q along it, placed relative to i's foot point on the
// segment, each of volume 1/q^2 (q = quadrature points per spacing).
//   q = 1: the wall weight function of Harada, Koshizuka & Shimazaki (2008), "Improvement of
//          wall boundary calculation model for MPS method", Trans. JSCES 2008, 20080006: the
//          number-density contribution Z(d) of the wall rows a particle at distance d would
//          see on the lattice, here evaluated directly instead of from a table.
//   q > 1: a quadrature of the boundary integral over the half-plane, the SPH counterpart
//          (Kulasegaram et al. 2004; Ferrand et al. 2013 use the integral of W over the
//          wall region, gamma(d)).
// Points that lie outside the solid, beyond the support, or nearer to another segment are
// left out (corners are counted once). Each point carries i's own pressure extrapolated
// hydrostatically, p_w = p_i + rho0 (g - a_w) . (x_w - x_i); the wall is at rest (no slip) or
// moves with the mirror of i's velocity (free slip). The segments of a moving obstacle move
// with it (core/walls/wall_samples.hpp: its points carry u_wall, or the mirror of i's velocity
// relative to it, and its acceleration a_w).
#include <cmath>

#include "core/io/scene.hpp"
#include "core/walls/wall_geometry.hpp"
#include "core/walls/wall_sample_model.hpp"
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {
namespace {

class DistanceFunction final : public WallSampleModel {
 public:
  explicit DistanceFunction(const WallTreatmentSetup& setup)
      : WallSampleModel(setup),
        spacing_(setup.scene.particle_spacing),
        points_per_spacing_(static_cast<int>(setup.parameters.integer("quadrature_points"))),
        free_slip_(setup.parameters.string("velocity") == "free_slip") {}

  void build_wall_samples(const WallContext& context, WallSampleList& samples) override {
    follow_moving_walls(context.particles);
    const ParticleSet& particles = context.particles;
    const double support = context.support;
    const double support2 = support * support;
    const std::size_t n = particles.size();
    const double step = spacing_ / points_per_spacing_;
    const double volume = 1.0 / (points_per_spacing_ * points_per_spacing_);
    const int rows = static_cast<int>(std::ceil(support / step));
    const auto& segments = geometry_.segments();
    samples.offsets.assign(n + 1, 0);
    samples.samples.clear();
    for (std::size_t i = 0; i < n; ++i) {
      samples.offsets[i] = static_cast<std::uint32_t>(samples.samples.size());
      if (particles.type[i] != ParticleType::Fluid) continue;
      const Vec2& x = particles.position[i];
      for (std::size_t s = 0; s < segments.size(); ++s) {
        if (geometry_.distance_to(x, s) >= support) continue;
        const WallSegment& wall = segments[s];
        const Vec2 tangent(-wall.normal.y(), wall.normal.x());
        const double d = (x - wall.a).dot(wall.normal);  // signed: < 0 past the surface
        const Vec2 foot = x - d * wall.normal;
        const Mat2 velocity_map =
            free_slip_ ? Mat2(Mat2::Identity() - 2.0 * wall.normal * wall.normal.transpose()) : Mat2(Mat2::Zero());
        for (int k = 0; k < rows; ++k) {
          const Vec2 row = foot - (k + 0.5) * step * wall.normal;
          for (int m = -rows; m <= rows; ++m) {
            const Vec2 point = row + m * step * tangent;
            if ((point - x).squaredNorm() >= support2) continue;
            if (!geometry_.inside_solid(point)) continue;
            std::size_t nearest = 0;
            geometry_.distance(point, &nearest);
            if (nearest != s) continue;  // counted by the nearer segment (corners once)
            WallSample sample;
            sample.position = point;
            sample.velocity_map = velocity_map;
            sample.source = static_cast<std::uint32_t>(i);
            sample.volume = volume;
            sample.obstacle = wall.body;
            set_wall_motion(sample, wall);
            samples.samples.push_back(sample);
          }
        }
      }
    }
    samples.offsets[n] = static_cast<std::uint32_t>(samples.samples.size());
  }

 private:
  double spacing_;  // l0, m
  int points_per_spacing_;
  bool free_slip_;
};

}  // namespace
}  // namespace mps_lab

void mps_lab_register_wall_treatment_distance_function(mps_lab::WallTreatmentRegistry& registry) {
  using namespace mps_lab;
  WallTreatmentInfo info;
  info.name = "distance_function";
  info.description =
      "wall contributions from the distance to each wall segment, no wall particles (Harada et al. 2008; SPH boundary "
      "integral)";
  info.parameters = {
      integer_parameter("quadrature_points", 1,
                        "points per spacing of the virtual wall: 1 = Harada's lattice wall weight, > 1 = quadrature of "
                        "the boundary integral")
          .at_least(1)
          .at_most(4),
      string_parameter("velocity", "no_slip",
                       "wall velocity seen by the fluid: no_slip (0) or free_slip (mirror of u_i)")
          .one_of({"no_slip", "free_slip"}),
  };
  info.parameters.push_back(crossing_parameter("none"));
  declare_wall_sample_model(info);  // for every method that sums over wall samples (MethodInfo::wall_samples)
  info.create = [](const WallTreatmentSetup& setup) { return std::make_unique<DistanceFunction>(setup); };
  registry.add(std::move(info));
}
