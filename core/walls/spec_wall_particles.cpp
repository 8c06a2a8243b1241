// The wall of the MPS specification (spec §4, §8): walls.layers layers of fixed wall particles
// on the lattice, in every operator sum like fluid particles; the layers nearest the fluid
// (pressure_layers, spec: 1) are unknowns of the PPE, the outer ones only fill the number
// density. The mps method implements it in its operators (methods/mps/); this file declares
// it as the boundary model mps uses by default.
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {
namespace {

class SpecWallParticles final : public WallTreatment {};

}  // namespace
}  // namespace mps_lab

void mps_lab_register_wall_treatment_spec_wall_particles(mps_lab::WallTreatmentRegistry& registry) {
  using namespace mps_lab;
  WallTreatmentInfo info;
  info.name = "spec_wall_particles";
  info.description = "wall particles in every sum, the first layer solved in the PPE (MPS spec 4, 8; Koshizuka & Oka 1996)";
  info.methods = {"mps"};
  info.parameters = {integer_parameter("pressure_layers", 1,
                                       "wall layers (counted from the fluid) that carry PPE pressure; outer layers only "
                                       "fill the number density")
                         .at_least(0)
                         .at_most(10)};
  info.role = WallTreatmentRole::Boundary;
  info.wall_particles = true;
  info.create = [](const WallTreatmentSetup& setup) {
    (void)setup.parameters.integer("pressure_layers");  // read by the mps method (boundary_parameters)
    return std::make_unique<SpecWallParticles>();
  };
  registry.add(std::move(info));
}
