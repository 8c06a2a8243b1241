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

// What every boundary model of wall samples declares: the role, no wall particles (so a method
// with MethodInfo::wall_samples may use it), and the hooks of WallSampleModel. The reflection
// after the explicit position update is optional: a method whose only position update ends
// the step (advection, then after_correction) reflects once, after the correction.
inline void declare_wall_sample_model(WallTreatmentInfo& info) {
  info.role = WallTreatmentRole::Boundary;
  info.wall_particle_model.reset();
  info.hooks = {WallHook::AfterExplicitPosition, WallHook::AfterCorrection};
  info.optional_hooks = {WallHook::AfterExplicitPosition};
}

// The `crossing` parameter, with the model's default ("reflect" or "none").
inline ParameterSpec crossing_parameter(const std::string& default_choice) {
  return string_parameter("crossing", default_choice,
                          "a fluid particle behind the wall surface: reflect it back and stop its motion into the wall "
                          "(kinematic no-penetration), or none")
      .one_of({"reflect", "none"});
}

}  // namespace mps_lab
