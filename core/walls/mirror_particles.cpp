// Mirror (ghost) particles reflected across straight walls (docs/walls.md; Takeda, Miyama &
// Sekiya 1994, Prog. Theor. Phys. 92, 939-960; Randles & Libersky 1996; for MPS e.g. Yildiz,
// Rook & Suleman 2009). Each step every fluid particle j closer than the operator support to
// a wall surface (core/walls/wall_geometry.hpp) gets an image reflected across that surface,
//   x_j' = x_j - 2 d_j n      (d_j: distance to the surface, n: its normal into the fluid),
// and, where j is near two perpendicular surfaces meeting at a corner, the image through the
// corner, x_j'' = 2 c - x_j. An image counts only where it lies inside the solid. A fluid
// particle i then sees the images within its support as wall samples that carry the pressure
// and velocity of their original:
//   p_j' = p_j + rho0 g . (x_j' - x_j)         (hydrostatic extrapolation across the wall)
//   u_j' = (I - 2 n n^T) u_j  (free slip)  or  -u_j  (no slip); -u_j through a corner.
// The images are not particles of the simulation; the PPE couples i to j through them.
#include <cmath>

#include "core/io/scene.hpp"
#include "core/walls/wall_geometry.hpp"
#include "core/walls/wall_sample_model.hpp"
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {
namespace {

struct Image {
  Vec2 position;
  Mat2 velocity_map;
};

class MirrorParticles final : public WallSampleModel {
 public:
  explicit MirrorParticles(const WallTreatmentSetup& setup)
      : WallSampleModel(setup), no_slip_(setup.parameters.string("velocity") == "no_slip") {
    // Corners: pairs of perpendicular surfaces that share an end point, the fluid inside the angle.
    const auto& segments = geometry_.segments();
    const double tolerance = 1e-9 * setup.scene.particle_spacing;
    for (std::size_t a = 0; a < segments.size(); ++a) {
      for (std::size_t b = a + 1; b < segments.size(); ++b) {
        if (std::fabs(segments[a].normal.dot(segments[b].normal)) > 1e-12) continue;
        for (const Vec2& p : {segments[a].a, segments[a].b}) {
          for (const Vec2& q : {segments[b].a, segments[b].b}) {
            if ((p - q).norm() < tolerance) corners_.push_back({a, b, p});
          }
        }
      }
    }
  }

  void build_wall_samples(const WallContext& context, WallSampleList& samples) override {
    const ParticleSet& particles = context.particles;
    const double support = context.support;
    const std::size_t n = particles.size();
    // Images of every fluid particle near a wall, in compressed rows.
    image_offsets_.assign(n + 1, 0);
    images_.clear();
    const auto& segments = geometry_.segments();
    std::vector<double> distance(segments.size());
    for (std::size_t j = 0; j < n; ++j) {
      image_offsets_[j] = static_cast<std::uint32_t>(images_.size());
      if (particles.type[j] != ParticleType::Fluid) continue;
      const Vec2& x = particles.position[j];
      for (std::size_t s = 0; s < segments.size(); ++s) {
        const WallSegment& wall = segments[s];
        distance[s] = -1.0;
        const Vec2 along = wall.b - wall.a;
        const double t = (x - wall.a).dot(along) / along.squaredNorm();
        const double d = (x - wall.a).dot(wall.normal);
        if (t < 0.0 || t > 1.0 || d <= 0.0 || d >= support) continue;  // else no fluid particle reaches the image
        distance[s] = d;
        const Vec2 image = x - 2.0 * d * wall.normal;
        if (!geometry_.inside_solid(image)) continue;
        const Mat2 reflect = Mat2::Identity() - 2.0 * wall.normal * wall.normal.transpose();
        images_.push_back({image, no_slip_ ? Mat2(-Mat2::Identity()) : reflect});
      }
      for (const Corner& corner : corners_) {
        if (distance[corner.a] <= 0.0 || distance[corner.b] <= 0.0) continue;
        const Vec2 image = 2.0 * corner.point - x;
        // No fluid particle reaches the image unless x is within the support of the corner.
        if ((x - corner.point).norm() >= support || !geometry_.inside_solid(image)) continue;
        images_.push_back({image, -Mat2::Identity()});
      }
    }
    image_offsets_[n] = static_cast<std::uint32_t>(images_.size());

    // Samples of i: the images of i and of its fluid neighbours within the support (an image
    // of j is never nearer to i than j itself, so the neighbour list finds them all).
    samples.offsets.assign(n + 1, 0);
    samples.samples.clear();
    const NeighbourList& neighbours = *context.neighbours;
    const double support2 = support * support;
    const auto add_images_of = [&](std::size_t i, std::uint32_t j) {
      for (std::uint32_t k = image_offsets_[j]; k < image_offsets_[j + 1]; ++k) {
        if ((images_[k].position - particles.position[i]).squaredNorm() >= support2) continue;
        WallSample sample;
        sample.position = images_[k].position;
        sample.velocity_map = images_[k].velocity_map;
        sample.source = j;
        samples.samples.push_back(sample);
      }
    };
    for (std::size_t i = 0; i < n; ++i) {
      samples.offsets[i] = static_cast<std::uint32_t>(samples.samples.size());
      if (particles.type[i] != ParticleType::Fluid) continue;
      add_images_of(i, static_cast<std::uint32_t>(i));
      for (std::uint32_t k = neighbours.begin(i); k < neighbours.end(i); ++k) {
        const std::uint32_t j = neighbours.indices[k];
        if (particles.type[j] == ParticleType::Fluid) add_images_of(i, j);
      }
    }
    samples.offsets[n] = static_cast<std::uint32_t>(samples.samples.size());
  }

 private:
  struct Corner {
    std::size_t a, b;  // the two surfaces
    Vec2 point;        // m
  };
  bool no_slip_;
  std::vector<Corner> corners_;
  std::vector<std::uint32_t> image_offsets_;
  std::vector<Image> images_;
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
