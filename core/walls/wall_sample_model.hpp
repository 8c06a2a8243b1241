#pragma once
// What the boundary models of wall samples share (core/walls/dummy_layers.cpp,
// mirror_particles.cpp, distance_function.cpp): the scene's wall geometry and the `crossing`
// parameter, the kinematic no-penetration condition applied after the explicit position
// update and after the correction (reflect_crossed_particles, core/walls/wall_geometry.hpp;
// docs/walls.md gives the measurements behind each model's default).
#include <string>

#include "core/base/parameters.hpp"
#include "core/walls/wall_geometry.hpp"
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {

class WallSampleModel : public WallTreatment {
 public:
  explicit WallSampleModel(const WallTreatmentSetup& setup)
      : geometry_(setup.scene), reflect_(setup.parameters.string("crossing") == "reflect") {}

  void after_explicit_position(WallContext& context) override {
    if (reflect_) reflect_crossed_particles(context.particles, geometry_);
  }
  void after_correction(WallContext& context) override {
    if (reflect_) reflect_crossed_particles(context.particles, geometry_);
  }

 protected:
  WallGeometry geometry_;
  bool reflect_;
};

// The `crossing` parameter, with the model's default ("reflect" or "none").
inline ParameterSpec crossing_parameter(const std::string& default_choice) {
  return string_parameter("crossing", default_choice,
                          "a fluid particle behind the wall surface: reflect it back and stop its motion into the wall "
                          "(kinematic no-penetration), or none")
      .one_of({"reflect", "none"});
}

}  // namespace mps_lab
