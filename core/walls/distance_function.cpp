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
//   blended (default): a partition of unity. A point x of segment s's rows carries the share
//     psi_s(x) / sum_u psi_u(x) of its volume over the segments u near i (partition_share):
//     psi_u = c_u(x) prod_{t != u} f_t(x), c_u the coverage of x by u's rows (row_coverage:
//     whole along the exposed part of u's surface, falling to 0 a band beyond it and, by the
//     angle, towards its line there) and f_t the hand-over to t's rows within a row step of t's
//     exposed surface (hand_over). The shares of the rows that meet at a point add up to 1, so on
//     the lattice (where their points coincide) i's sums are the lattice's; near a face of the
//     solid the face's rows take the whole share, so the points of other rows leave the solid
//     through it with weight 0 (a convex corner); beyond a segment's exposed part its share
//     falls to 0 towards its line, so points crossing that line inside the solid enter its
//     rows continuously (a concave corner). Both hand-overs are shaped so that the first row's
//     point value is its cell's mean, which keeps the volume of a corner on average over i's
//     positions (docs/walls.md, "Distance function at corners").
//   nearest: a point counts for the segment nearest to it among those whose line it lies
//     behind, whose rows could hold it (each corner point once; a segment the point is in front
//     of, such as the bed's surface running on under an obstacle standing on it, never takes
//     it). The rows move with i, so a point that crosses the line where the nearest segment
//     changes jumps in or out with its whole weight: i's wall number density jumps as it moves
//     past a corner (by 1.06 of n0 = 6.54 beside the 25-degree toe of
//     scenes/hydrostatic_slope.json), and MPS's pressure spikes there.
// Each point carries i's own pressure extrapolated hydrostatically,
// p_w = p_i + rho0 (g - a_w) . (x_w - x_i); the wall is at rest (no slip) or moves with the
// mirror of i's velocity (free slip). The segments of a moving obstacle move with it
// (core/walls/wall_samples.hpp: its points carry u_wall, or the mirror of i's velocity relative
// to it, and its acceleration a_w).
#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <vector>

#include "core/io/scene.hpp"
#include "core/walls/wall_geometry.hpp"
#include "core/walls/wall_sample_model.hpp"
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {
namespace {

constexpr double kPi = 3.14159265358979323846;

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
        blended_corners_(setup.parameters.string("corners") == "blended") {
    if (blended_corners_) find_exposed_pieces();
  }

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
        const double weight = blended_corners_ ? partition_share(point, rows, near)
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

  // corners = blended: the share of segment rows.segment at the row point x,
  // psi_s(x) / sum_u psi_u(x) over the segments u near i, psi_u = c_u(x) prod_{t != u} f_t(x):
  // c_u the coverage of x by u's rows (row_coverage), f_t = hand_over(distance to t's exposed
  // surface, step): t's rows take over within a row step of its face. The shares of the rows
  // that meet at a point add up to 1 (on the lattice their points coincide, so i's sums are the
  // lattice's); next to a face t of the solid every other segment's share goes to 0, so the
  // points of other rows leave the solid through t (a convex corner: an obstacle's top, the
  // gate's bottom) with weight 0.
  double partition_share(const Vec2& x, const VirtualRows& rows, const std::vector<std::size_t>& near) const {
    const double band = rows.rows * rows.step;  // m
    hand_overs_.assign(near.size(), -1.0);      // f_t of near[k], computed when first needed
    double own = 0.0;
    double total = 0.0;
    for (std::size_t j = 0; j < near.size(); ++j) {
      double psi = row_coverage(x, near[j], band, rows.step);
      for (std::size_t k = 0; k < near.size() && psi > 0.0; ++k) {
        if (k == j) continue;
        if (hand_overs_[k] < 0.0) hand_overs_[k] = hand_over(distance_to_exposed(x, near[k]), rows.step);
        psi *= hand_overs_[k];
      }
      total += psi;
      if (near[j] == rows.segment) own = psi;
    }
    return total > 0.0 ? own / total : 0.0;
  }

  // The factor f(d) by which rows give way within a width w (m) of a line: 0 on the line, 1 from
  // w on, f = d / (2 w - d) between. With w one row step, where two segments' rows overlap that
  // makes the share of the rows whose first (or last) row stands for the cell at the line
  // 1 - d / (2 w), linear across that cell, so that row's point value is its cell's mean, and
  // the points of the other rows, which slide along with i, add the rest: the overlap's volume
  // is kept on average over i's positions (a fade linear over half a step lost 2-14 % of a
  // submerged box's buoyancy, docs/walls.md).
  static double hand_over(double d, double w) { return d >= w ? 1.0 : d / (2.0 * w - d); }

  // The coverage by a segment's rows of a point beyond its end, seen from the end at the angle
  // alpha (rad) from the segment's line: 0 up to 30 degrees, 1 from 60, linear between (1 along
  // the segment, alpha = 90 degrees). Where two segments meet at a concave corner their shares
  // are then functions of the angle alone, 0 near the other's line, and each row's share, summed
  // along the row (the direction in which its points slide with i), grows linearly with the
  // row's depth: the row's point stands for its cell, on average over i's positions, wherever
  // the band reaches past the cone (near the apex only roughly: with q = 1 a particle close to
  // both walls reads 3.4 % high there, docs/walls.md).
  static double cone(double alpha) { return std::clamp((alpha - kPi / 6.0) / (kPi / 6.0), 0.0, 1.0); }

  // How fully the rows of segment `k` cover the point x (0 to 1). The rows fill the band of
  // depth `band` (m) behind the segment's line; they cover fully along an exposed piece of its
  // surface (find_exposed_pieces) and reach `band` beyond each piece's ends.
  //   - Along a piece the coverage is whole from the surface (the first row stands for the cell
  //     from the surface down: there the segment's share takes over from every other, a face of
  //     the solid) and hands over to other rows within the last row of the band (hand_over: the
  //     rows that go on there take the share linearly across that row's cell).
  //   - Beyond a piece's end, by e (m): falling linearly to 0 at e = band, so a segment's rows
  //     enter and leave i's sums continuously; and a function of the angle from the end (cone),
  //     0 near the line, so that where the solid runs on across it (a concave corner: the side
  //     wall's slab below the bed's surface, the bed under an obstacle) a point crossing the line
  //     enters the segment's rows continuously.
  // The largest over the segment's pieces; 0 for a segment with none (buried whole).
  double row_coverage(const Vec2& x, std::size_t k, double band, double step) const {
    const WallSegment& segment = geometry_.segments()[k];
    const double depth = (segment.a - x).dot(segment.normal);  // m, > 0 behind the segment's line
    if (depth <= 0.0 || depth >= band) return 0.0;
    const Vec2 along = (segment.b - segment.a).normalized();
    const double position = (x - segment.a).dot(along);  // m from a towards b
    double coverage = 0.0;
    for (const ExposedPiece& piece : exposed_[k]) {
      const double beyond_end = std::max({piece.from - position, position - piece.to, 0.0});
      const double front = cone(std::atan2(depth, beyond_end));
      coverage = std::max(coverage, front * std::max(0.0, 1.0 - beyond_end / band));
    }
    return hand_over(band - depth, step) * coverage;
  }

  // Distance from x to the exposed pieces of segment k, m (infinite for a segment buried whole).
  double distance_to_exposed(const Vec2& x, std::size_t k) const {
    const WallSegment& segment = geometry_.segments()[k];
    const Vec2 along = (segment.b - segment.a).normalized();
    const double position = (x - segment.a).dot(along);
    double nearest = std::numeric_limits<double>::infinity();
    for (const ExposedPiece& piece : exposed_[k]) {
      const Vec2 foot = segment.a + std::clamp(position, piece.from, piece.to) * along;
      nearest = std::min(nearest, (x - foot).norm());
    }
    return nearest;
  }

  // Blended, the exposed pieces follow the moving obstacles (WallSampleModel::follow_moving_walls).
  void geometry_moved() override {
    if (blended_corners_) find_exposed_pieces();
  }

  // corners = blended: the parts of each segment's surface that face the fluid. A segment is
  // cut where another segment meets it; a part with a solid just in front of its middle is
  // buried (an obstacle's face below the bed's surface, the bed under an obstacle standing on
  // it) and is no face of the solid: its rows hand over to nobody there, and the segments that
  // meet at the cut meet as a corner.
  void find_exposed_pieces() {
    const std::vector<WallSegment>& segments = geometry_.segments();
    exposed_.assign(segments.size(), {});
    for (std::size_t k = 0; k < segments.size(); ++k) {
      const WallSegment& segment = segments[k];
      const double length = (segment.b - segment.a).norm();
      const Vec2 along = (segment.b - segment.a) / length;
      std::vector<double> cuts = {0.0, length};
      for (std::size_t other = 0; other < segments.size(); ++other) {
        if (other != k) add_crossing(segment, segments[other], cuts);
      }
      std::sort(cuts.begin(), cuts.end());
      for (std::size_t c = 0; c + 1 < cuts.size(); ++c) {
        if (cuts[c + 1] - cuts[c] <= 1e-9 * spacing_) continue;
        const Vec2 probe = segment.a + 0.5 * (cuts[c] + cuts[c + 1]) * along + 1e-6 * spacing_ * segment.normal;
        if (geometry_.solid_holding(probe)) continue;  // buried
        std::vector<ExposedPiece>& pieces = exposed_[k];
        if (!pieces.empty() && pieces.back().to == cuts[c]) {
          pieces.back().to = cuts[c + 1];
        } else {
          pieces.push_back({cuts[c], cuts[c + 1]});
        }
      }
    }
  }

  // Where segment `other` meets `segment` (m along `segment` from its end a), if it does.
  static void add_crossing(const WallSegment& segment, const WallSegment& other, std::vector<double>& cuts) {
    const Vec2 along = segment.b - segment.a;
    if (const auto t = crossing_parameter(segment.a, along, other.a, other.b - other.a))
      cuts.push_back(*t * along.norm());
  }

  struct ExposedPiece {
    double from, to;  // m along the segment from its end a
  };
  std::vector<std::vector<ExposedPiece>> exposed_;  // per segment (corners = blended)
  mutable std::vector<double> hand_overs_;          // partition_share's f_t of each near segment, reused
  double spacing_;                                  // l0, m
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
      string_parameter("corners", "blended",
                       "where two segments' virtual rows overlap: blended (each point counts with its share of a "
                       "partition of unity: continuous past every corner) or nearest (a point counts for its nearest "
                       "segment: the sums jump as i passes a corner)")
          .one_of({"nearest", "blended"}),
  };
  info.parameters.push_back(crossing_parameter("none"));
  declare_wall_sample_model(info);  // for every method that sums over wall samples (MethodInfo::wall_samples)
  info.create = [](const WallTreatmentSetup& setup) { return std::make_unique<DistanceFunction>(setup); };
  registry.add(std::move(info));
}
