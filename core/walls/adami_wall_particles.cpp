// The generalised wall boundary condition of Adami, Hu & Adams (2012), J. Comput. Phys. 231,
// 7057-7075: walls.layers layers of fixed dummy particles whose pressure is the kernel-weighted
// average of the surrounding fluid pressure plus the hydrostatic head (their eq. 27), solved
// together with the fluid in the ISPH pressure system (one row per wall particle). A method
// that implements the wall-particle model AdamiExtrapolated (isph, methods/isph/isph_pressure.hpp)
// uses every layer, with the lattice volume.
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {
namespace {

class AdamiWallParticles final : public WallParticleModel {
 public:
  WallParticlePressure pressure() const override { return WallParticlePressure::AdamiExtrapolated; }
};

}  // namespace
}  // namespace mps_lab

void mps_lab_register_wall_treatment_adami_wall_particles(mps_lab::WallTreatmentRegistry& registry) {
  using namespace mps_lab;
  WallTreatmentInfo info;
  info.name = "adami_wall_particles";
  info.description = "dummy wall particles with the Adami et al. (2012) wall pressure, implicit in the ISPH PPE";
  info.role = WallTreatmentRole::Boundary;
  info.moving_walls = true;  // wall particles: the driver moves those of moving obstacles
  info.wall_particle_model = WallParticlePressure::AdamiExtrapolated;
  info.create = [](const WallTreatmentSetup&) { return std::make_unique<AdamiWallParticles>(); };
  registry.add(std::move(info));
}
