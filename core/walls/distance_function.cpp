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
// Points outside the solid or beyond the support are left out. Where the rows of two segments
// overlap (a corner), `corners` decides which count:
//   nearest (default): a point counts for the segment nearest to it among those whose line it
//     lies behind, whose rows could hold it (each corner point once; a segment the point is in
//     front of, such as the bed's surface running on under an obstacle standing on it, never
//     takes it). The rows move with i, so a point that crosses the line where the nearest
//     segment changes jumps in or out with its whole weight: i's wall number density jumps as
//     it moves past a corner (by 1.06 of n0 = 6.54 beside the 25-degree toe of
//     scenes/hydrostatic_slope.json).
//   blended: a segment's rows fill a band one support deep behind it, reaching one band beyond
//     its ends; a point p of segment s's rows carries the share c_s(p) / sum_t c_t(p) of its
//     volume, c_t the coverage of p by the rows of segment t near i: 1 inside t's band, falling
//     to 0 within half a point spacing at its faces and within a band beyond t's ends. A share
//     goes continuously to 1 where p leaves the other rows, so i's wall sums are continuous as
//     it moves past a corner the fluid sees as concave (the solid the union of the half-planes).
//     At a convex corner the points of one face's rows leave the solid through the other face;
//     they fade out linearly within half a point spacing of any other segment's surface, so they
//     leave it with weight 0. On a straight wall every share is 1 and no point is that near
//     another surface: Harada's rows exactly (docs/walls.md, "Distance function at corners").
// Each point carries i's own pressure extrapolated hydrostatically,
// p_w = p_i + rho0 (g - a_w) . (x_w - x_i); the wall is at rest (no slip) or moves with the
// mirror of i's velocity (free slip). The segments of a moving obstacle move with it
// (core/walls/wall_samples.hpp: its points carry u_wall, or the mirror of i's velocity relative
// to it, and its acceleration a_w).
#include <algorithm>
#include <cmath>
#include <optional>
#include <vector>

#include "core/io/scene.hpp"
#include "core/walls/wall_geometry.hpp"
#include "core/walls/wall_sample_model.hpp"
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {
namespace {

// The virtual rows of one segment for one particle: `rows` rows of `step` spacing (m) behind it.
struct VirtualRows {
  std::size_t segment;
  int rows;
  double step;  // m
};

class DistanceFunction final : public WallSampleModel {
 public:
  explicit DistanceFunction(const WallTreatmentSetup& setup)
      : WallSampleModel(setup),
        spacing_(setup.scene.particle_spacing),
        points_per_spacing_(static_cast<int>(setup.parameters.integer("quadrature_points"))),
        free_slip_(setup.parameters.string("velocity") == "free_slip"),
        blended_corners_(setup.parameters.string("corners") == "blended") {}

  void build_wall_samples(const WallContext& context, WallSampleList& samples) override {
    follow_moving_walls(context.particles);
    const ParticleSet& particles = context.particles;
    const double step = spacing_ / points_per_spacing_;
    const int rows = static_cast<int>(std::ceil(context.support / step));
    const std::size_t n = particles.size();
    // The segments whose rows i sees: blended, a segment's rows reach one band (rows x step)
    // beyond its ends, and enter with coverage 0 when it is two bands beyond the support.
    const double reach = context.support + (blended_corners_ ? 2.0 * rows * step : 0.0);  // m
    samples.offsets.assign(n + 1, 0);
    samples.samples.clear();
    std::vector<std::size_t> near;  // the segments within `reach` of i, whose rows i sees
    for (std::size_t i = 0; i < n; ++i) {
      samples.offsets[i] = static_cast<std::uint32_t>(samples.samples.size());
      if (particles.type[i] != ParticleType::Fluid) continue;
      near.clear();
      for (std::size_t s = 0; s < geometry_.segments().size(); ++s) {
        if (geometry_.distance_to(particles.position[i], s) < reach) near.push_back(s);
      }
      for (const std::size_t s : near) add_row_points(particles, i, VirtualRows{s, rows, step}, near, context, samples);
    }
    samples.offsets[n] = static_cast<std::uint32_t>(samples.samples.size());
  }

 private:
  // The points of segment `rows.segment`'s rows that particle i sees, as samples of i.
  void add_row_points(const ParticleSet& particles, std::size_t i, const VirtualRows& rows,
                      const std::vector<std::size_t>& near, const WallContext& context, WallSampleList& samples) const {
    const WallSegment& wall = geometry_.segments()[rows.segment];
    const Vec2& x = particles.position[i];
    const Vec2 tangent(-wall.normal.y(), wall.normal.x());
    const double d = (x - wall.a).dot(wall.normal);  // signed: < 0 past the surface
    const Vec2 foot = x - d * wall.normal;
    const Mat2 velocity_map =
        free_slip_ ? Mat2(Mat2::Identity() - 2.0 * wall.normal * wall.normal.transpose()) : Mat2(Mat2::Zero());
    const double volume = 1.0 / (points_per_spacing_ * points_per_spacing_);
    for (int k = 0; k < rows.rows; ++k) {
      const Vec2 row = foot - (k + 0.5) * rows.step * wall.normal;
      for (int m = -rows.rows; m <= rows.rows; ++m) {
        const Vec2 point = row + m * rows.step * tangent;
        if ((point - x).squaredNorm() >= context.support * context.support) continue;
        const std::optional<int> holder = geometry_.solid_holding(point);
        if (!holder) continue;  // outside every solid
        const double weight = blended_corners_ ? share(point, rows, near) * surface_fade(point, rows, near)
                                               : (geometry_.nearest_behind(point) == rows.segment ? 1.0 : 0.0);
        if (weight <= 0.0) continue;
        WallSample sample;
        sample.position = point;
        sample.velocity_map = velocity_map;
        sample.source = static_cast<std::uint32_t>(i);
        sample.volume = volume * weight;
        // Blended, the sample stands for the solid that holds it: a point of an obstacle
        // face's rows that lies in the bed is bed (at rest, no part of the obstacle's load).
        WallSegment solid = wall;
        if (blended_corners_) solid.body = *holder;
        sample.obstacle = solid.body;
        set_wall_motion(sample, solid);
        samples.samples.push_back(sample);
      }
    }
  }

  // corners = blended: the share of the point p of `rows` (of rows.segment) - its coverage by
  // those rows over the sum of its coverages by the same rows of every segment in `near`.
  double share(const Vec2& p, const VirtualRows& rows, const std::vector<std::size_t>& near) const {
    double own = 0.0;
    double total = 0.0;
    for (const std::size_t t : near) {
      const double coverage = row_coverage(p, geometry_.segments()[t], rows.rows * rows.step, rows.step);
      total += coverage;
      if (t == rows.segment) own = coverage;
    }
    return total > 0.0 ? own / total : 0.0;
  }

  // corners = blended: 1, falling linearly to 0 as p comes within half a row step of the surface
  // of another segment in `near`. The rows of that segment have no point there (their first row
  // is half a step deep), so the points of other rows fade out towards it and leave the solid,
  // where they are cut, with weight 0: at a convex corner (an obstacle's top) the cut is
  // continuous. On the lattice no row point lies nearer than half a step to another surface.
  double surface_fade(const Vec2& p, const VirtualRows& rows, const std::vector<std::size_t>& near) const {
    double fade = 1.0;
    for (const std::size_t t : near) {
      if (t != rows.segment) fade *= std::min(1.0, geometry_.distance_to(p, t) / (0.5 * rows.step));
    }
    return fade;
  }

  // How fully a segment's rows cover the point p (0 to 1). The rows fill the band of depth
  // `band` (m) behind the segment and reach `band` beyond each of its ends; the coverage rises
  // from 0 at either face of the band to 1 half a row `step` inside it, and falls from 1 at an
  // end of the segment to 0 a band beyond it, so a segment's rows enter and leave i's sums
  // continuously.
  static double row_coverage(const Vec2& p, const WallSegment& segment, double band, double step) {
    const double depth = (segment.a - p).dot(segment.normal);  // m, > 0 behind the segment's line
    const double across = std::clamp(std::min(depth, band - depth) / (0.5 * step), 0.0, 1.0);
    const Vec2 along = segment.b - segment.a;
    const double length = along.norm();
    const double position = (p - segment.a).dot(along) / length;  // m from a towards b
    const double beyond_end = std::max({-position, position - length, 0.0});
    return across * std::clamp(1.0 - beyond_end / band, 0.0, 1.0);
  }

  double spacing_;  // l0, m
  int points_per_spacing_;
  bool free_slip_;
  bool blended_corners_;
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
      string_parameter("corners", "nearest",
                       "where two segments' virtual rows overlap: nearest (a point counts for its nearest segment) or "
                       "blended (each counts with its share of the rows covering it: continuous past every corner)")
          .one_of({"nearest", "blended"}),
  };
  info.parameters.push_back(crossing_parameter("none"));
  declare_wall_sample_model(info);  // for every method that sums over wall samples (MethodInfo::wall_samples)
  info.create = [](const WallTreatmentSetup& setup) { return std::make_unique<DistanceFunction>(setup); };
  registry.add(std::move(info));
}
