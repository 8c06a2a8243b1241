// Boundary particles of Akinci, Ihmsen, Akinci, Solenthaler & Teschner (2012), ACM TOG 31(4)
// 62: fixed wall particles with the boundary mass Psi_b = rho0 V_b in the density sum and a
// pressure force that mirrors the fluid particle's pressure, as Bender & Koschier (2017) use
// them in DFSPH. A method that implements the wall-particle model AkinciMirrored (dfsph,
// methods/dfsph/dfsph_operators.hpp) reads from this strategy object which layers are boundary
// particles and the volume rule.
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {
namespace {

class AkinciBoundary final : public WallParticleModel {
 public:
  explicit AkinciBoundary(const WallTreatmentSetup& setup)
      : layers_(static_cast<int>(setup.parameters.integer("layers"))),
        volume_(setup.parameters.string("volume") == "akinci" ? WallParticleVolume::KernelSum
                                                              : WallParticleVolume::Lattice) {}
  WallParticlePressure pressure() const override { return WallParticlePressure::AkinciMirrored; }
  int pressure_layers() const override { return layers_; }
  WallParticleVolume volume() const override { return volume_; }

 private:
  int layers_;  // wall layers, from the fluid, that are boundary particles
  WallParticleVolume volume_;
};

}  // namespace
}  // namespace mps_lab

void mps_lab_register_wall_treatment_akinci_boundary(mps_lab::WallTreatmentRegistry& registry) {
  using namespace mps_lab;
  WallTreatmentInfo info;
  info.name = "akinci_boundary";
  info.description = "Akinci et al. (2012) boundary particles with pressure mirroring (Bender & Koschier 2017)";
  info.parameters = {
      integer_parameter("layers", 3,
                        "wall layers (from the fluid) that are boundary particles; outer layers are ignored")
          .at_least(1)
          .at_most(10),
      string_parameter("volume", "lattice",
                       "volume of a boundary particle: \"akinci\" V_b = 1/sum_k W_bk (Akinci 2012), \"lattice\" V_b = "
                       "the fluid particle's volume (l0^2 at m = rho0 l0^2)")
          .one_of({"akinci", "lattice"}),
  };
  info.role = WallTreatmentRole::Boundary;
  info.moving_walls = true;  // wall particles: the driver moves those of moving obstacles
  info.wall_particle_model = WallParticlePressure::AkinciMirrored;
  info.create = [](const WallTreatmentSetup& setup) { return std::make_unique<AkinciBoundary>(setup); };
  registry.add(std::move(info));
}
