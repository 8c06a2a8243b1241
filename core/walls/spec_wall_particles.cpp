// The wall of the MPS specification (spec §4, §8): walls.layers layers of fixed wall particles
// on the lattice, in every operator sum like fluid particles; the layers nearest the fluid
// (pressure_layers, spec: 1) are unknowns of the PPE, the outer ones only fill the number
// density. A method that implements the wall-particle model SolvedInPpe (mps, methods/mps/)
// reads pressure_layers from this strategy object.
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {
namespace {

class SpecWallParticles final : public WallParticleModel {
 public:
  explicit SpecWallParticles(const WallTreatmentSetup& setup)
      : pressure_layers_(static_cast<int>(setup.parameters.integer("pressure_layers"))) {}
  WallParticlePressure pressure() const override { return WallParticlePressure::SolvedInPpe; }
  int pressure_layers() const override { return pressure_layers_; }

 private:
  int pressure_layers_;  // wall layers, from the fluid, that are PPE unknowns
};

}  // namespace
}  // namespace mps_lab

void mps_lab_register_wall_treatment_spec_wall_particles(mps_lab::WallTreatmentRegistry& registry) {
  using namespace mps_lab;
  WallTreatmentInfo info;
  info.name = "spec_wall_particles";
  info.description =
      "wall particles in every sum, the first layer solved in the PPE (MPS spec 4, 8; Koshizuka & Oka 1996)";
  info.parameters = {
      integer_parameter("pressure_layers", 1,
                        "wall layers (counted from the fluid) that carry PPE pressure; outer layers only "
                        "fill the number density")
          .at_least(0)
          .at_most(10)};
  info.role = WallTreatmentRole::Boundary;
  info.moving_walls = true;  // wall particles: the driver moves those of moving obstacles
  info.wall_particle_model = WallParticlePressure::SolvedInPpe;
  info.create = [](const WallTreatmentSetup& setup) { return std::make_unique<SpecWallParticles>(setup); };
  registry.add(std::move(info));
}
