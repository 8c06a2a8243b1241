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
//   lattice: blended, and at a lattice corner (find_lattice_corners: two fixed segments at right angles, the solid
//     behind both and nothing else within a band of the apex: the tank's bottom corners, a box's
//     foot) the solid behind both lines is carried by one more member of the partition, the
//     corner lattice: points through i's position on the corner's axes, which slide with i both
//     ways as fluid particles do (add_lattice_points). Each segment's rows reach one row step
//     past its end there, and the corner's other rows and the lattice give way to that reach
//     (Coverage::claims). Rows that slide one way only count the quadrant's edge cells twice near
//     the apex: with q = 1 the corner read 3.4 % above the boundary integral, 2.3 % above the
//     spec's wall lattice; with the lattice 1.6 % and 0.5 %. Measured, not the default
//     (docs/walls.md): MPS splashes less on the dam break, but its still water reads the bed as
//     dummy_layers does (lower than with blended), and ISPH's load setting diverges on the dam break.
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
#include <array>
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

// The corner lattice's index where a segment's is expected (VirtualRows::segment).
constexpr std::size_t kLattice = std::numeric_limits<std::size_t>::max() - 1;

// How fully a segment's rows cover a point (row_coverage): whole, and what they claim past the
// end of an exposed part at a lattice corner, against the corner's other segment (`partner`)
// and the corner lattice, which give way to it.
struct Coverage {
  struct Claim {
    std::size_t partner;
    double value;
  };
  double whole = 0.0;
  std::array<Claim, 4> claims;  // the first claim_count hold (not zeroed: built per row point)
  std::size_t claim_count = 0;

  void add_claim(std::size_t partner, double value) {
    if (claim_count < claims.size()) claims[claim_count++] = {partner, value};
  }
  // The claim against `partner`, or against anyone (kAnyPartner: what the lattice gives way to).
  double claim_against(std::size_t partner) const {
    double claim = 0.0;
    for (std::size_t c = 0; c < claim_count; ++c) {
      if (partner == kAnyPartner || claims[c].partner == partner) claim = std::max(claim, claims[c].value);
    }
    return claim;
  }
  static constexpr std::size_t kAnyPartner = std::numeric_limits<std::size_t>::max() - 2;
};

// A part of a segment's surface that faces the fluid (corners = blended), and at each end the
// other segment of the lattice corner there, if any.
constexpr std::size_t kNoPartner = std::numeric_limits<std::size_t>::max();
struct ExposedPiece {
  double from, to;                        // m along the segment from its end a
  std::size_t from_partner = kNoPartner;  // the other segment of a lattice corner at `from`
  std::size_t to_partner = kNoPartner;    // ... at `to`
};

// Two fixed segments meeting at right angles, the solid behind both (find_lattice_corners).
struct LatticeCorner {
  std::size_t first, second;  // segments
};

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
        blended_corners_(setup.parameters.string("corners") != "nearest"),
        lattice_corners_enabled_(setup.parameters.string("corners") == "lattice") {
    if (blended_corners_) {
      find_exposed_pieces();
      find_lattice_corners();
    }
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
      if (blended_corners_ && lattice_corner_near(near))
        add_lattice_points(particles, i, VirtualRows{kLattice, rows, step}, near, context, samples);
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

  // corners = lattice: the points of the corner lattice that particle i sees, as samples of i
  // (find_lattice_corners): the lattice through i's position on the axes of the corners, spaced
  // `rows.step`, each point with its share of the partition (rows.segment = kLattice). The
  // corners are fixed: the points are at rest (no slip) or carry -u_i, u_i mirrored across both
  // walls (free slip).
  void add_lattice_points(const ParticleSet& particles, std::size_t i, const VirtualRows& rows,
                          const std::vector<std::size_t>& near, const WallContext& context,
                          WallSampleList& samples) const {
    const Vec2& x = particles.position[i];
    const double volume = 1.0 / (points_per_spacing_ * points_per_spacing_);
    for (int m = -rows.rows; m <= rows.rows; ++m) {
      for (int l = -rows.rows; l <= rows.rows; ++l) {
        const Vec2 point = x + rows.step * (m * lattice_along_ + l * lattice_across_);
        if ((point - x).squaredNorm() >= context.support * context.support) continue;
        if (lattice_coverage(point, near, rows.rows * rows.step, rows.step) <= 0.0) continue;
        const std::optional<int> holder = geometry_.solid_holding(point);
        if (!holder) continue;
        const double weight = partition_share(point, rows, near);
        if (weight <= 0.0) continue;
        WallSample sample;
        sample.position = point;
        sample.velocity_map = free_slip_ ? Mat2(-Mat2::Identity()) : Mat2(Mat2::Zero());
        sample.source = static_cast<std::uint32_t>(i);
        sample.volume = volume * weight;
        sample.obstacle = *holder;
        samples.samples.push_back(sample);
      }
    }
  }

  // corners = blended: the share of segment rows.segment (or of the corner lattice, kLattice) at
  // the point x, psi_s(x) / sum_u psi_u(x) over the members u (the segments near i and the
  // lattice), psi_u = c_u(x) prod_{t != u} f_t(x) (1 - e_tu(x)): c_u the coverage of x by u
  // (row_coverage, lattice_coverage), f_t = hand_over(distance to t's exposed surface, step):
  // t's rows take over within a row step of its face; e_tu the reach of t's rows past a lattice
  // corner, where u is the corner's other segment or the lattice (Coverage::claims). The shares
  // of the members that meet at a point add up to 1 (on the lattice their points coincide, so
  // i's sums are the lattice's); next to a face t of the solid every other segment's share goes
  // to 0, so the points of other rows leave the solid through t (a convex corner: an obstacle's
  // top, the gate's bottom) with weight 0.
  double partition_share(const Vec2& x, const VirtualRows& rows, const std::vector<std::size_t>& near) const {
    const double band = rows.rows * rows.step;  // m
    coverages_.resize(near.size());
    for (std::size_t j = 0; j < near.size(); ++j) coverages_[j] = row_coverage(x, near[j], band, rows.step);
    hand_overs_.assign(near.size(), -1.0);  // f_t of near[k], computed when first needed
    // Without lattice corners (corners = blended, or none in the scene) no member claims anything
    // and the lattice is no member: the loops below skip both.
    const bool lattice_corners = !lattice_corners_.empty();
    const std::size_t members = near.size() + (lattice_corners ? 1 : 0);  // near's rows, then the lattice
    double own = 0.0;
    double total = 0.0;
    for (std::size_t j = 0; j < members; ++j) {
      const bool lattice = j == near.size();
      double psi = lattice ? lattice_coverage(x, near, band, rows.step) : coverages_[j].whole;
      for (std::size_t k = 0; k < near.size() && psi > 0.0; ++k) {
        if (k == j) continue;
        if (hand_overs_[k] < 0.0) hand_overs_[k] = hand_over(distance_to_exposed(x, near[k]), rows.step);
        if (!lattice_corners) {
          psi *= hand_overs_[k];
          continue;
        }
        const double claim = coverages_[k].claim_against(lattice ? Coverage::kAnyPartner : near[j]);
        psi *= hand_overs_[k] * (1.0 - claim);
      }
      total += psi;
      if ((lattice ? kLattice : near[j]) == rows.segment) own = psi;
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
  //   - Beyond an end at a lattice corner: 1 - f(depth behind the other segment's line), one
  //     row step past it, and that much claimed against the other segment and the lattice
  //     (the corner quadrant beyond is the lattice's, find_lattice_corners).
  // The largest over the segment's pieces; 0 for a segment with none (buried whole).
  Coverage row_coverage(const Vec2& x, std::size_t k, double band, double step) const {
    const WallSegment& segment = geometry_.segments()[k];
    const double depth = depth_behind(x, k);  // m, > 0 behind the segment's line
    Coverage coverage;
    if (depth <= 0.0 || depth >= band) return coverage;
    const Vec2 along = (segment.b - segment.a).normalized();
    const double position = (x - segment.a).dot(along);  // m from a towards b
    for (const ExposedPiece& piece : exposed_[k]) {
      const bool before = position < piece.from;
      const double beyond_end = std::max({piece.from - position, position - piece.to, 0.0});
      const std::size_t partner = before ? piece.from_partner : piece.to_partner;
      if (beyond_end > 0.0 && partner != kNoPartner) {
        const double past = 1.0 - hand_over(std::max(0.0, depth_behind(x, partner)), step);
        coverage.add_claim(partner, past);
        coverage.whole = std::max(coverage.whole, past);
        continue;
      }
      const double front = cone(std::atan2(depth, beyond_end));
      coverage.whole = std::max(coverage.whole, front * std::max(0.0, 1.0 - beyond_end / band));
    }
    const double back = hand_over(band - depth, step);
    coverage.whole *= back;
    for (std::size_t c = 0; c < coverage.claim_count; ++c) coverage.claims[c].value *= back;
    return coverage;
  }

  // Depth of x behind the line of segment k, m (< 0 in front of it).
  double depth_behind(const Vec2& x, std::size_t k) const {
    const WallSegment& segment = geometry_.segments()[k];
    return (segment.a - x).dot(segment.normal);
  }

  // How fully the corner lattice covers x (0 to 1): whole behind both segments of a lattice
  // corner near i, within the band of both, handing over at the band's back as the rows do.
  double lattice_coverage(const Vec2& x, const std::vector<std::size_t>& near, double band, double step) const {
    double coverage = 0.0;
    for (const LatticeCorner& corner : lattice_corners_) {
      if (!is_near(corner, near)) continue;
      const double first = depth_behind(x, corner.first);
      const double second = depth_behind(x, corner.second);
      if (first <= 0.0 || second <= 0.0 || first >= band || second >= band) continue;
      coverage = std::max(coverage, hand_over(band - first, step) * hand_over(band - second, step));
    }
    return coverage;
  }

  static bool is_near(const LatticeCorner& corner, const std::vector<std::size_t>& near) {
    return std::find(near.begin(), near.end(), corner.first) != near.end() &&
           std::find(near.begin(), near.end(), corner.second) != near.end();
  }
  bool lattice_corner_near(const std::vector<std::size_t>& near) const {
    return std::any_of(lattice_corners_.begin(), lattice_corners_.end(),
                       [&](const LatticeCorner& corner) { return is_near(corner, near); });
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
    if (blended_corners_) {
      find_exposed_pieces();
      find_lattice_corners();
    }
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

  // corners = lattice: the lattice corners, where two fixed segments meet at right angles with
  // the solid running on behind both (a concave corner of the fluid: the tank's bottom corners,
  // a fixed obstacle's foot) and both exposed parts end. Past such an end a segment's rows reach
  // one row step (the claim 1 - f(depth behind the other's line)), and the solid behind both
  // lines is the corner lattice's: points through i's position, sliding with i in both
  // directions as fluid particles do, so that near the apex the quadrant is sampled as the
  // spec's wall lattice samples it (rows that slide one way only count the cells at the
  // quadrant's edges twice: 3.4 % high, docs/walls.md). Segments that can part (a moving
  // obstacle's) keep the cone, and so do corners whose axes are not the first corner's.
  void find_lattice_corners() {
    lattice_corners_.clear();
    if (!lattice_corners_enabled_) return;
    const std::vector<WallSegment>& segments = geometry_.segments();
    for (std::size_t k = 0; k < segments.size(); ++k) {
      for (std::size_t other = k + 1; other < segments.size(); ++other) add_lattice_corner(k, other);
    }
  }

  void add_lattice_corner(std::size_t k, std::size_t other) {
    const WallSegment& first = geometry_.segments()[k];
    const WallSegment& second = geometry_.segments()[other];
    if (geometry_.can_move(first) || geometry_.can_move(second)) return;
    if (std::abs(first.normal.dot(second.normal)) > 1e-9) return;  // not at right angles
    const Vec2 along(-first.normal.y(), first.normal.x());
    if (!lattice_corners_.empty() && std::abs(along.dot(lattice_along_)) > 1e-9 &&
        std::abs(along.dot(lattice_across_)) > 1e-9)
      return;  // not on the lattice's axes
    const Vec2 apex = first.a + along * ((second.a - first.a).dot(second.normal) / along.dot(second.normal));
    const double offset = 1e-3 * spacing_;  // m
    const bool concave = geometry_.solid_holding(apex + offset * (first.normal - second.normal)) &&
                         geometry_.solid_holding(apex + offset * (second.normal - first.normal)) &&
                         geometry_.solid_holding(apex - offset * (first.normal + second.normal));
    if (!concave || !clear_behind(apex, k, other)) return;
    ExposedPiece* first_end = piece_ending_at(k, apex);
    ExposedPiece* second_end = piece_ending_at(other, apex);
    if (first_end == nullptr || second_end == nullptr) return;
    set_partner(*first_end, k, apex, other);
    set_partner(*second_end, other, apex, k);
    if (lattice_corners_.empty()) {
      lattice_along_ = along;
      lattice_across_ = first.normal;
    }
    lattice_corners_.push_back({k, other});
  }

  // Whether no other segment enters the square behind both segments' lines at the apex, one
  // band (the wall's 3 l0, the largest support) deep behind each: the corner's solid then stands
  // alone (not so at the feet of the dam break's obstacle, 2 l0 wide, whose rows reach through it).
  bool clear_behind(const Vec2& apex, std::size_t k, std::size_t other) const {
    const std::vector<WallSegment>& segments = geometry_.segments();
    const double band = 3.0 * spacing_;  // m
    const auto depths = [&](const Vec2& x) {
      return Vec2((apex - x).dot(segments[k].normal), (apex - x).dot(segments[other].normal));
    };
    for (std::size_t s = 0; s < segments.size(); ++s) {
      if (s == k || s == other) continue;
      if (enters_open_square(depths(segments[s].a), depths(segments[s].b), band)) return false;
    }
    return true;
  }
  // Whether the segment p-q enters the open square (0, side)^2 (Liang-Barsky clipping).
  static bool enters_open_square(const Vec2& p, const Vec2& q, double side) {
    double enter = 0.0;
    double leave = 1.0;
    const Vec2 d = q - p;
    for (int axis = 0; axis < 2; ++axis) {
      for (const double bound : {0.0, side}) {
        const double inside = bound == 0.0 ? p[axis] : side - p[axis];  // > 0 inside this bound at p
        const double rate = bound == 0.0 ? d[axis] : -d[axis];
        if (rate == 0.0) {
          if (inside <= 0.0) return false;
          continue;
        }
        const double t = -inside / rate;
        if (rate > 0.0)
          enter = std::max(enter, t);
        else
          leave = std::min(leave, t);
      }
    }
    return enter < leave;
  }

  // The exposed piece of segment k with an end at x, nullptr if none.
  ExposedPiece* piece_ending_at(std::size_t k, const Vec2& x) {
    for (ExposedPiece& piece : exposed_[k]) {
      if (end_at(k, piece.from, x) || end_at(k, piece.to, x)) return &piece;
    }
    return nullptr;
  }
  bool end_at(std::size_t k, double position, const Vec2& x) const {
    const WallSegment& segment = geometry_.segments()[k];
    const Vec2 end = segment.a + position * (segment.b - segment.a).normalized();
    return (end - x).norm() <= 1e-6 * spacing_;
  }
  void set_partner(ExposedPiece& piece, std::size_t k, const Vec2& apex, std::size_t partner) const {
    (end_at(k, piece.from, apex) ? piece.from_partner : piece.to_partner) = partner;
  }

  // Where segment `other` meets `segment` (m along `segment` from its end a), if it does.
  static void add_crossing(const WallSegment& segment, const WallSegment& other, std::vector<double>& cuts) {
    const Vec2 along = segment.b - segment.a;
    if (const auto t = crossing_parameter(segment.a, along, other.a, other.b - other.a))
      cuts.push_back(*t * along.norm());
  }

  std::vector<std::vector<ExposedPiece>> exposed_;  // per segment (corners = blended)
  std::vector<LatticeCorner> lattice_corners_;      // (corners = blended)
  Vec2 lattice_along_ = Vec2::UnitX();              // the corner lattice's axes (unit)
  Vec2 lattice_across_ = Vec2::UnitY();
  mutable std::vector<Coverage> coverages_;  // partition_share's c_t of each near segment, reused
  mutable std::vector<double> hand_overs_;   // partition_share's f_t of each near segment, reused
  double spacing_;                           // l0, m
  int points_per_spacing_;
  bool free_slip_;
  bool blended_corners_;          // corners = blended or lattice
  bool lattice_corners_enabled_;  // corners = lattice
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
      string_parameter(
          "corners", "blended",
          "where two segments' virtual rows overlap: blended (each point counts with its share of a "
          "partition of unity: continuous past every corner), lattice (blended, and behind a right-angled "
          "concave corner of fixed walls a lattice that slides with i both ways: the corner's volume as the "
          "spec's wall lattice counts it) or nearest (a point counts for its nearest segment: the sums jump "
          "as i passes a corner)")
          .one_of({"nearest", "blended", "lattice"}),
  };
  info.parameters.push_back(crossing_parameter("none"));
  declare_wall_sample_model(info);  // for every method that sums over wall samples (MethodInfo::wall_samples)
  info.create = [](const WallTreatmentSetup& setup) { return std::make_unique<DistanceFunction>(setup); };
  registry.add(std::move(info));
}
