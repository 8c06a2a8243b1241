// Mirror (ghost) particles reflected across straight walls (docs/walls.md; Takeda, Miyama &
// Sekiya 1994, Prog. Theor. Phys. 92, 939-960; Randles & Libersky 1996; for MPS e.g. Yildiz,
// Rook & Suleman 2009). Each step every fluid particle j closer than the operator support to
// a wall surface (core/walls/wall_geometry.hpp) gets an image reflected across that surface,
//   x_j' = x_j - 2 d_j n      (d_j: distance to the surface, n: its normal into the fluid),
// and, where j is near two perpendicular surfaces meeting at a concave corner, the image
// through the corner, x_j'' = 2 c - x_j. An image counts only where it lies inside the solid,
// and a face image not where another face owns the point and fills it (one image per point of
// the solid at a convex corner or in a thin solid; MirrorParticles::add_face_images). A fluid
// particle i then sees the images within its support as wall samples that carry the pressure
// and velocity of their original:
//   p_j' = p_j + rho0 g . (x_j' - x_j)         (hydrostatic extrapolation across the wall)
//   u_j' = (I - 2 n n^T) u_j  (free slip)  or  -u_j  (no slip); -u_j through a corner.
// Across the surface of a moving obstacle (walls.obstacles[k].motion) the images mirror the
// motion relative to the wall, u_j' = M u_j + (I - M) u_wall, and carry its acceleration in
// the extrapolation, p_j' = p_j + rho0 (g - a_wall) . (x_j' - x_j) (core/walls/wall_samples.hpp);
// through a corner u_wall is the mean of the two surfaces' velocities there.
// The images are not particles of the simulation; the PPE couples i to j through them.
#include <algorithm>
#include <cmath>

#include "core/io/scene.hpp"
#include "core/walls/wall_geometry.hpp"
#include "core/walls/wall_sample_model.hpp"
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {
namespace {

struct Image {
  Vec2 position;  // m
  Mat2 velocity_map;
  std::uint32_t source;                   // the fluid particle it mirrors
  std::int32_t obstacle = -1;             // the solid it stands for (WallSample::obstacle)
  Vec2 wall_velocity = Vec2::Zero();      // (I - M) u_wall, m/s (core/walls/wall_samples.hpp)
  Vec2 wall_acceleration = Vec2::Zero();  // a_wall, m/s^2
};

// Points (images, fluid particles) in square cells of side `cell`, m: every point closer than
// `cell` to x lies in the 3 x 3 cells around x.
class PointGrid {
 public:
  void build(const std::vector<Vec2>& points, double cell) {
    cell_ = cell;
    starts_.clear();
    order_.clear();
    if (points.empty()) return;
    low_ = points.front();
    Vec2 high = low_;
    for (const Vec2& point : points) {
      low_ = low_.cwiseMin(point);
      high = high.cwiseMax(point);
    }
    columns_ = static_cast<long>(std::floor((high.x() - low_.x()) / cell_)) + 1;
    rows_ = static_cast<long>(std::floor((high.y() - low_.y()) / cell_)) + 1;
    // Counting sort of the images by cell.
    starts_.assign(static_cast<std::size_t>(columns_ * rows_) + 1, 0);
    std::vector<std::uint32_t> cell_of(points.size());
    for (std::size_t k = 0; k < points.size(); ++k) {
      cell_of[k] = static_cast<std::uint32_t>(cell_index(points[k]));
      ++starts_[cell_of[k] + 1];
    }
    for (std::size_t c = 1; c < starts_.size(); ++c) starts_[c] += starts_[c - 1];
    order_.resize(points.size());
    std::vector<std::uint32_t> next(starts_.begin(), starts_.end() - 1);
    for (std::size_t k = 0; k < points.size(); ++k) order_[next[cell_of[k]]++] = static_cast<std::uint32_t>(k);
  }

  // Calls visit(k) for every point k in the 3 x 3 cells around x.
  template <class Visit>
  void for_each_near(const Vec2& x, Visit&& visit) const {
    if (order_.empty()) return;
    const long cx = static_cast<long>(std::floor((x.x() - low_.x()) / cell_));
    const long cy = static_cast<long>(std::floor((x.y() - low_.y()) / cell_));
    for (long y = std::max(cy - 1, 0L); y <= std::min(cy + 1, rows_ - 1); ++y) {
      for (long c = std::max(cx - 1, 0L); c <= std::min(cx + 1, columns_ - 1); ++c) {
        const auto cell = static_cast<std::size_t>(y * columns_ + c);
        for (std::uint32_t m = starts_[cell]; m < starts_[cell + 1]; ++m) visit(order_[m]);
      }
    }
  }

 private:
  long cell_index(const Vec2& x) const {
    const long c = std::min(static_cast<long>(std::floor((x.x() - low_.x()) / cell_)), columns_ - 1);
    const long y = std::min(static_cast<long>(std::floor((x.y() - low_.y()) / cell_)), rows_ - 1);
    return y * columns_ + c;
  }
  double cell_ = 1.0;  // m
  Vec2 low_ = Vec2::Zero();
  long columns_ = 0, rows_ = 0;
  std::vector<std::uint32_t> starts_;  // per cell, into order_
  std::vector<std::uint32_t> order_;   // point indices by cell
};

class MirrorParticles final : public WallSampleModel {
 public:
  explicit MirrorParticles(const WallTreatmentSetup& setup)
      : WallSampleModel(setup),
        no_slip_(setup.parameters.string("velocity") == "no_slip"),
        corner_tolerance_(1e-9 * setup.scene.particle_spacing) {
    find_corners(corner_tolerance_);
  }

  void build_wall_samples(const WallContext& context, WallSampleList& samples) override {
    follow_moving_walls(context.particles);
    const ParticleSet& particles = context.particles;
    const double support = context.support;
    const std::size_t n = particles.size();
    // Images of every fluid particle near a wall, in compressed rows.
    image_offsets_.assign(n + 1, 0);
    images_.clear();
    points_.clear();
    for (std::size_t j = 0; j < n; ++j) {
      if (particles.type[j] == ParticleType::Fluid) points_.push_back(particles.position[j]);
    }
    fluid_grid_.build(points_, support);
    std::vector<double> distance(geometry_.segments().size());
    for (std::size_t j = 0; j < n; ++j) {
      image_offsets_[j] = static_cast<std::uint32_t>(images_.size());
      if (particles.type[j] != ParticleType::Fluid) continue;
      const Vec2& x = particles.position[j];
      add_face_images(x, static_cast<std::uint32_t>(j), support, distance);
      add_corner_images(x, static_cast<std::uint32_t>(j), support, distance);
    }
    image_offsets_[n] = static_cast<std::uint32_t>(images_.size());

    collect_samples(context, samples);
  }

 private:
  struct Corner {
    std::size_t a, b;  // the two surfaces
    Vec2 point;        // m
  };

  // Samples of i: every image within the support of i, carrying its source's pressure and
  // velocity. First the images of i and of its fluid neighbours (an image of j across a face
  // both i and j are in front of is never nearer to i than j, so the neighbour list finds
  // those), then, from a cell grid of the images, those of sources that are no neighbour of i:
  // across a face whose line i lies behind, an image can be nearer than its source (i above
  // the top face of a box, j beside its side face below the corner: j's image in the corner
  // is within the support of i, j is not). Missing them left a hole in the corner's wall.
  // The coupling this makes is not symmetric at a convex corner (j, without an image across
  // the top face, does not see i's): docs/walls.md, "Mirror particles at corners".
  void collect_samples(const WallContext& context, WallSampleList& samples) {
    const ParticleSet& particles = context.particles;
    const std::size_t n = particles.size();
    const double support2 = context.support * context.support;
    const NeighbourList& neighbours = *context.neighbours;
    points_.clear();
    for (const Image& image : images_) points_.push_back(image.position);
    image_grid_.build(points_, context.support);
    neighbour_stamp_.assign(n, 0);
    samples.offsets.assign(n + 1, 0);
    samples.samples.clear();
    const auto add_image = [&](std::size_t i, std::uint32_t k) {
      if ((images_[k].position - particles.position[i]).squaredNorm() >= support2) return;
      WallSample sample;
      sample.position = images_[k].position;
      sample.velocity_map = images_[k].velocity_map;
      sample.source = images_[k].source;
      sample.obstacle = images_[k].obstacle;
      sample.wall_velocity = images_[k].wall_velocity;
      sample.wall_acceleration = images_[k].wall_acceleration;
      samples.samples.push_back(sample);
    };
    for (std::size_t i = 0; i < n; ++i) {
      samples.offsets[i] = static_cast<std::uint32_t>(samples.samples.size());
      if (particles.type[i] != ParticleType::Fluid) continue;
      const auto stamp = static_cast<std::uint32_t>(i + 1);
      neighbour_stamp_[i] = stamp;
      for (std::uint32_t k = image_offsets_[i]; k < image_offsets_[i + 1]; ++k) add_image(i, k);
      for (std::uint32_t m = neighbours.begin(i); m < neighbours.end(i); ++m) {
        const std::uint32_t j = neighbours.indices[m];
        if (particles.type[j] != ParticleType::Fluid) continue;
        neighbour_stamp_[j] = stamp;
        for (std::uint32_t k = image_offsets_[j]; k < image_offsets_[j + 1]; ++k) add_image(i, k);
      }
      image_grid_.for_each_near(particles.position[i], [&](std::uint32_t k) {
        if (neighbour_stamp_[images_[k].source] != stamp) add_image(i, k);
      });
    }
    samples.offsets[n] = static_cast<std::uint32_t>(samples.samples.size());
  }

  // Concave right-angled corners: pairs of perpendicular surfaces whose lines cross at a point
  // on both segments (a shared end point, as the tank's corners, or inside one of them, as
  // where a box's side face, which reaches down into the bed, meets the bed's surface). The
  // fluid lies inside the angle where a particle is in front of both (build_wall_samples).
  void find_corners(double tolerance) {
    corners_.clear();
    const auto& segments = geometry_.segments();
    for (std::size_t a = 0; a < segments.size(); ++a) {
      for (std::size_t b = a + 1; b < segments.size(); ++b) {
        if (std::fabs(segments[a].normal.dot(segments[b].normal)) > 1e-12) continue;
        // The crossing point of the two lines: c = a.a + s (a.b - a.a) with (c - b.a) . n_b = 0.
        const Vec2 along = segments[a].b - segments[a].a;
        const double s = (segments[b].a - segments[a].a).dot(segments[b].normal) / along.dot(segments[b].normal);
        const Vec2 c = segments[a].a + s * along;
        if (geometry_.distance_to(c, a) < tolerance && geometry_.distance_to(c, b) < tolerance) {
          corners_.push_back({a, b, c});
        }
      }
    }
  }

  // The images of x across each surface it is near (distance[s] > 0: its distance to surface
  // s, m; else -1). An image counts where it lies inside the solid and no other face owns and
  // fills it (filled_by_another_face): at a convex corner (a box's top corners, a
  // wedge's crest) the solid near the vertex lies behind both faces, and without the owner
  // rule the images of the fluid above the top face and of the fluid beside the side face
  // both filled it (twice the wall's number density there, a coincident pair on the
  // diagonal); across a solid thinner than the support the images of both sides overlapped in
  // the same way. With it each point of the solid is filled once, from the face whose
  // perpendicular reaches it first: the solid is split along the bisector of a convex corner
  // (the medial axis), as the wall particles' mitred layers split it
  // (core/walls/wall_polygon.hpp), and as fixed ghost particles take their values from the
  // mirror of their nearest boundary point (Marrone et al. 2011, Comput. Methods Appl. Mech.
  // Engrg. 200, 1526-1542; docs/walls.md "Polygon walls").
  void add_face_images(const Vec2& x, std::uint32_t j, double support, std::vector<double>& distance) {
    const auto& segments = geometry_.segments();
    for (std::size_t s = 0; s < segments.size(); ++s) {
      const WallSegment& wall = segments[s];
      distance[s] = -1.0;
      const Vec2 along = wall.b - wall.a;
      const double t = (x - wall.a).dot(along) / along.squaredNorm();
      const double d = (x - wall.a).dot(wall.normal);
      if (t < 0.0 || t > 1.0 || d <= 0.0 || d >= support) continue;  // else no fluid particle reaches the image
      distance[s] = d;
      const Vec2 image = x - 2.0 * d * wall.normal;  // x' = x - 2 d n
      if (!geometry_.inside_solid(image) || filled_by_another_face(image, s, d)) continue;
      const Mat2 reflect = Mat2::Identity() - 2.0 * wall.normal * wall.normal.transpose();
      images_.push_back({image, no_slip_ ? Mat2(-Mat2::Identity()) : reflect, j, wall.body});
      if (geometry_.moves(wall)) {  // the motion relative to the wall, mirrored
        Image& moved = images_.back();
        moved.wall_velocity = (Mat2::Identity() - moved.velocity_map) * geometry_.wall_velocity(wall, image);
        moved.wall_acceleration = geometry_.wall_acceleration(wall, image);
      }
    }
  }

  // Whether the point w of the solid, at depth d (m) behind surface s, is filled by another
  // surface's images: the surface it lies nearest behind (owner_of) is not s, and fluid lies
  // within l0/2 of w's mirror across that surface (its images fill w). Where the owner's side
  // is dry (a thin obstacle the surge has not passed yet) s's image stays, so the fluid that is
  // there sees the whole solid.
  bool filled_by_another_face(const Vec2& w, std::size_t s, double d) const {
    double depth = d;
    const std::size_t owner = owner_of(w, s, depth);
    if (owner == s) return false;
    const Vec2 mirror = w + 2.0 * depth * geometry_.segments()[owner].normal;
    const double reach = geometry_.surface_offset();  // l0 / 2, m
    bool wet = false;
    fluid_grid_.for_each_near(mirror, [&](std::uint32_t k) { wet = wet || (points_[k] - mirror).norm() < reach; });
    return wet;
  }

  // The surface that owns a point w of the solid, w at depth d (m) behind surface s: the
  // surface with the smallest depth among those w lies behind within their extent (foot point
  // on the segment) and whose mirror of w is not itself inside the solid; ties (a point on a
  // corner's bisector, where two lattice images coincide) go to the lower index, so exactly
  // one face keeps it. The owner's depth is left in d.
  std::size_t owner_of(const Vec2& w, std::size_t s, double& d) const {
    const auto& segments = geometry_.segments();
    const double tolerance = 1e-9 * 2.0 * geometry_.surface_offset();
    std::size_t owner = s;
    for (std::size_t k = 0; k < segments.size(); ++k) {
      if (k == s) continue;
      const WallSegment& wall = segments[k];
      const Vec2 along = wall.b - wall.a;
      const double t = (w - wall.a).dot(along) / along.squaredNorm();
      const double behind = (wall.a - w).dot(wall.normal);  // > 0: w is behind surface k, m
      if (t < 0.0 || t > 1.0 || behind <= 0.0) continue;
      // A face claims w only if w's mirror across it lies outside the solid, where fluid can be
      // (at a concave corner of other than 90 degrees, as a slope meeting a tank side, w may lie
      // behind the side too, but its mirror across the side is inside the wedge).
      if (geometry_.inside_solid(w + 2.0 * behind * wall.normal)) continue;
      if (behind < d - tolerance || (std::fabs(behind - d) <= tolerance && k < owner)) {
        owner = k;
        d = std::min(d, behind);
      }
    }
    return owner;
  }

  // The point image through each concave right-angled corner x is near both surfaces of,
  // x'' = 2 c - x, where it lies inside the solid: it fills the quadrant behind both surfaces
  // that neither face image reaches. Velocity -u_j (reflected across both surfaces).
  void add_corner_images(const Vec2& x, std::uint32_t j, double support, const std::vector<double>& distance) {
    for (const Corner& corner : corners_) {
      if (distance[corner.a] <= 0.0 || distance[corner.b] <= 0.0) continue;
      const Vec2 image = 2.0 * corner.point - x;
      // No fluid particle reaches the image unless x is within the support of the corner.
      if ((x - corner.point).norm() >= support || !geometry_.inside_solid(image)) continue;
      const WallSegment& a = geometry_.segments()[corner.a];
      const WallSegment& b = geometry_.segments()[corner.b];
      // The quadrant behind both surfaces belongs to a solid's load only where both surfaces are
      // that solid's (a concave corner of one obstacle). Where an obstacle meets the tank (a box on
      // the bed) it stays with the tank, as the bed's wall particles under a box's foot do
      // (core/walls/obstacle_membership.hpp); between two obstacles it is in neither's load.
      images_.push_back({image, -Mat2::Identity(), j, a.body == b.body ? a.body : -1});
      if (geometry_.moves(a) || geometry_.moves(b)) {  // (I - M) u_wall = 2 u_wall, u_wall the surfaces' mean
        images_.back().wall_velocity =
            geometry_.wall_velocity(a, corner.point) + geometry_.wall_velocity(b, corner.point);
        images_.back().wall_acceleration =
            0.5 * (geometry_.wall_acceleration(a, corner.point) + geometry_.wall_acceleration(b, corner.point));
      }
    }
  }

  // The corners where a moving obstacle's surfaces meet others change as it moves.
  void geometry_moved() override { find_corners(corner_tolerance_); }

  bool no_slip_;
  double corner_tolerance_;  // m
  std::vector<Corner> corners_;
  std::vector<std::uint32_t> image_offsets_;
  std::vector<Image> images_;
  PointGrid image_grid_, fluid_grid_;
  std::vector<Vec2> points_;                    // m, the positions a grid is built from
  std::vector<std::uint32_t> neighbour_stamp_;  // i + 1 for i and its neighbours while i is served
};

}  // namespace
}  // namespace mps_lab

void mps_lab_register_wall_treatment_mirror_particles(mps_lab::WallTreatmentRegistry& registry) {
  using namespace mps_lab;
  WallTreatmentInfo info;
  info.name = "mirror_particles";
  info.description = "images of the fluid reflected across straight walls, carrying their pressure and velocity";
  info.parameters = {string_parameter("velocity", "free_slip",
                                      "image velocity: free_slip (normal part reversed) or no_slip (reversed)")
                         .one_of({"free_slip", "no_slip"})};
  info.parameters.push_back(crossing_parameter("reflect"));
  declare_wall_sample_model(info);  // for every method that sums over wall samples (MethodInfo::wall_samples)
  info.create = [](const WallTreatmentSetup& setup) { return std::make_unique<MirrorParticles>(setup); };
  registry.add(std::move(info));
}
