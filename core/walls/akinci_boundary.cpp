// Boundary particles of Akinci, Ihmsen, Akinci, Solenthaler & Teschner (2012), ACM TOG 31(4)
// 62: fixed wall particles with the boundary mass Psi_b = rho0 V_b in the density sum and a
// pressure force that mirrors the fluid particle's pressure, as Bender & Koschier (2017) use
// them in DFSPH. The dfsph method implements it (methods/dfsph/dfsph_operators.hpp) and reads
// these parameters; this file declares it as the boundary model dfsph uses by default.
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {
namespace {

class AkinciBoundary final : public WallTreatment {};

}  // namespace
}  // namespace mps_lab

void mps_lab_register_wall_treatment_akinci_boundary(mps_lab::WallTreatmentRegistry& registry) {
  using namespace mps_lab;
  WallTreatmentInfo info;
  info.name = "akinci_boundary";
  info.description = "Akinci et al. (2012) boundary particles with pressure mirroring (Bender & Koschier 2017)";
  info.methods = {"dfsph"};
  info.parameters = {
      integer_parameter("layers", 3, "wall layers (from the fluid) that are boundary particles; outer layers are ignored")
          .at_least(1)
          .at_most(10),
      string_parameter("volume", "lattice",
                       "volume of a boundary particle: \"akinci\" V_b = 1/sum_k W_bk (Akinci 2012), \"lattice\" V_b = l0^2")
          .one_of({"akinci", "lattice"}),
  };
  info.role = WallTreatmentRole::Boundary;
  info.wall_particles = true;
  info.create = [](const WallTreatmentSetup& setup) {
    (void)setup.parameters.integer("layers");  // read by the dfsph method (boundary_parameters)
    (void)setup.parameters.string("volume");
    return std::make_unique<AkinciBoundary>();
  };
  registry.add(std::move(info));
}
