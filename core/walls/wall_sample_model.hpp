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

//
// Moving obstacles (walls.obstacles[k].motion): the geometry holds them and follows the poses
// the driver puts into ParticleSet::obstacle_pose before each step (follow_moving_walls, at
// every hook and before the samples are built), so the samples and the reflection see the
// walls where the step solves for them (t_{n+1}, as the wall particles of the other models).
class WallSampleModel : public WallTreatment {
 public:
  explicit WallSampleModel(const WallTreatmentSetup& setup)
      : geometry_(setup.scene, MovingObstacles::Included), reflect_(setup.parameters.string("crossing") == "reflect") {}

  void after_explicit_position(WallContext& context) override {
    follow_moving_walls(context.particles);
    if (reflect_) reflect_crossed_particles(context.particles, geometry_);
  }
  void after_correction(WallContext& context) override {
    follow_moving_walls(context.particles);
    if (reflect_) reflect_crossed_particles(context.particles, geometry_);
  }

 protected:
  // The moving obstacles to the particles' obstacle_pose; calls geometry_moved() when they moved.
  void follow_moving_walls(const ParticleSet& particles) {
    if (!geometry_.has_moving_obstacles() || particles.obstacle_pose.empty()) return;
    geometry_.move_obstacles(particles.obstacle_pose);
    geometry_moved();
  }
  // What a model derives from the geometry, rebuilt after the walls moved (mirror particles' corners).
  virtual void geometry_moved() {}

  // The wall-velocity term and acceleration of a sample at x_w on the wall surface `segment`,
  // whose velocity is u_w = velocity_map u_s + (I - velocity_map) u_wall (core/walls/wall_samples.hpp):
  // the image of the source's motion relative to the wall. Nothing for a wall at rest.
  void set_wall_motion(WallSample& sample, const WallSegment& segment) const {
    if (!geometry_.moves(segment)) return;
    sample.wall_velocity = (Mat2::Identity() - sample.velocity_map) * geometry_.wall_velocity(segment, sample.position);
    sample.wall_acceleration = geometry_.wall_acceleration(segment, sample.position);
  }

  WallGeometry geometry_;
  bool reflect_;
};

// What every boundary model of wall samples declares: the role, no wall particles (so a method
// with MethodInfo::wall_samples may use it), moving walls, and the hooks of WallSampleModel. The reflection
// after the explicit position update is optional: a method whose only position update ends
// the step (advection, then after_correction) reflects once, after the correction.
inline void declare_wall_sample_model(WallTreatmentInfo& info) {
  info.role = WallTreatmentRole::Boundary;
  info.moving_walls = true;  // the geometry follows the moving obstacles (WallSampleModel)
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
