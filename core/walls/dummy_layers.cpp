// Dummy wall layers with extrapolated pressure (docs/walls.md). The wall is walls.layers
// layers of fixed points on the lattice, where the wall particles of the spec would be (tank
// sides and obstacles, core/io/geometry.hpp), but they are not particles of the simulation:
// each fluid particle i sees the points within the operator support as wall samples that
// carry its own pressure extrapolated hydrostatically,
//   p_w = p_i + rho0 g . (x_w - x_i),
// the hydrostatic extrapolation used for MPS dummy walls, and for the SPH methods the
// generalised wall condition of Adami, Hu & Adams (2012, eq. 27) with the fluid sum reduced
// to the particle itself. The wall is at rest (u_w = 0, no slip). No wall pressure is solved
// for: the PPE keeps only fluid unknowns, the wall terms go to its right-hand side.
#include "core/io/geometry.hpp"
#include "core/io/scene.hpp"
#include "core/search/point_grid.hpp"
#include "core/walls/wall_geometry.hpp"
#include "core/walls/wall_sample_model.hpp"
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {
namespace {

class DummyLayers final : public WallSampleModel {
 public:
  explicit DummyLayers(const WallTreatmentSetup& setup) : WallSampleModel(setup), support_(0.0) {
    const ParticleSet lattice = build_particles(setup.scene, true);
    for (std::size_t k = 0; k < lattice.size(); ++k) {
      if (lattice.type[k] == ParticleType::Wall) wall_points_.push_back(lattice.position[k]);
    }
  }

  void build_wall_samples(const WallContext& context, WallSampleList& samples) override {
    if (context.support != support_) {  // the grid's cells must be at least the support
      grid_.build(wall_points_, context.support);
      support_ = context.support;
    }
    const ParticleSet& particles = context.particles;
    samples.offsets.assign(particles.size() + 1, 0);
    samples.samples.clear();
    for (std::size_t i = 0; i < particles.size(); ++i) {
      samples.offsets[i] = static_cast<std::uint32_t>(samples.samples.size());
      if (particles.type[i] != ParticleType::Fluid) continue;
      grid_.for_each_within(particles.position[i], context.support, [&](std::uint32_t k) {
        WallSample sample;
        sample.position = grid_.points()[k];
        sample.source = static_cast<std::uint32_t>(i);
        samples.samples.push_back(sample);  // velocity_map 0 (wall at rest), volume 1
      });
    }
    samples.offsets[particles.size()] = static_cast<std::uint32_t>(samples.samples.size());
  }

 private:
  std::vector<Vec2> wall_points_;  // m
  PointGrid grid_;
  double support_;  // m, the support the grid was built for
};

}  // namespace
}  // namespace mps_lab

void mps_lab_register_wall_treatment_dummy_layers(mps_lab::WallTreatmentRegistry& registry) {
  using namespace mps_lab;
  WallTreatmentInfo info;
  info.name = "dummy_layers";
  info.description =
      "fixed dummy wall layers carrying the fluid pressure extrapolated hydrostatically (MPS; Adami et al. 2012 for "
      "SPH)";
  info.parameters.push_back(crossing_parameter("reflect"));
  declare_wall_sample_model(info);  // for every method that sums over wall samples (MethodInfo::wall_samples)
  info.create = [](const WallTreatmentSetup& setup) { return std::make_unique<DummyLayers>(setup); };
  registry.add(std::move(info));
}
