// Dummy wall layers with extrapolated pressure (docs/walls.md). The wall is walls.layers
// layers of fixed points on the lattice, where the wall particles of the spec would be (tank
// sides and obstacles, core/io/geometry.hpp), but they are not particles of the simulation:
// each fluid particle i sees the points within the operator support as wall samples that
// carry its own pressure extrapolated hydrostatically,
//   p_w = p_i + rho0 g . (x_w - x_i),
// the hydrostatic extrapolation used for MPS dummy walls, and for the SPH methods the
// generalised wall condition of Adami, Hu & Adams (2012, eq. 27) with the fluid sum reduced
// to the particle itself. The wall is at rest (u_w = 0, no slip), or, the layers of a moving
// obstacle, moves with it: its points are placed by the obstacle's pose every step as its wall
// particles would be (core/walls/moving_walls.hpp) and carry its velocity and acceleration,
// p_w = p_i + rho0 (g - a_w) . (x_w - x_i). No wall pressure is solved for: the PPE keeps only
// fluid unknowns, the wall terms go to its right-hand side.
#include "core/io/geometry.hpp"
#include "core/io/scene.hpp"
#include "core/search/point_grid.hpp"
#include "core/walls/obstacle_membership.hpp"
#include "core/walls/wall_geometry.hpp"
#include "core/walls/wall_sample_model.hpp"
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {
namespace {

class DummyLayers final : public WallSampleModel {
 public:
  explicit DummyLayers(const WallTreatmentSetup& setup) : WallSampleModel(setup), support_(0.0) {
    const ParticleSet lattice = build_particles(setup.scene, true);
    // Each point belongs to the solid its wall particle would belong to (the loads' and the
    // moving walls' membership, core/walls/obstacle_membership.hpp): the tank keeps the points a
    // tank wall holds.
    const std::vector<std::int32_t> owner = obstacle_of_wall_particles(setup.scene, lattice);
    for (std::size_t k = 0; k < lattice.size(); ++k) {
      if (lattice.type[k] != ParticleType::Wall) continue;
      const std::int32_t body = owner[k];
      if (body != kNoObstacle && setup.scene.walls.moving(static_cast<std::size_t>(body))) {
        const Vec2 arm = lattice.position[k] - obstacle_rest_centroid(setup.scene, static_cast<std::size_t>(body));
        moving_points_.push_back({wall_points_.size(), static_cast<std::size_t>(body), lattice.position[k], arm});
      }
      wall_points_.push_back(lattice.position[k]);
      point_obstacle_.push_back(body);
    }
  }

  void build_wall_samples(const WallContext& context, WallSampleList& samples) override {
    const bool moved = place_moving_points(context.particles);
    if (moved || context.support != support_) {  // the grid's cells must be at least the support
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
        sample.obstacle = point_obstacle_[k];
        if (!point_motion_.empty()) {  // u_w = u_wall (velocity_map 0), a_w
          sample.wall_velocity = point_motion_[k].velocity;
          sample.wall_acceleration = point_motion_[k].acceleration;
        }
        samples.samples.push_back(sample);  // velocity_map 0 (no slip), volume 1
      });
    }
    samples.offsets[particles.size()] = static_cast<std::uint32_t>(samples.samples.size());
  }

 private:
  // A point of a moving obstacle's layers: where the scene puts it and its arm r0 = x0 - x_c0.
  struct MovingPoint {
    std::size_t index;  // in wall_points_
    std::size_t body;   // walls.obstacles[body]
    Vec2 rest;          // m
    Vec2 arm;           // m
  };
  struct PointMotion {
    Vec2 velocity = Vec2::Zero();      // m/s
    Vec2 acceleration = Vec2::Zero();  // m/s^2
  };

  // The moving obstacles' points to their poses (x0 + d + (R r0 - r0), the wall particles' rule,
  // core/walls/moving_walls.hpp) with their velocities; false when nothing moves.
  bool place_moving_points(const ParticleSet& particles) {
    if (moving_points_.empty() || particles.obstacle_pose.empty()) return false;
    point_motion_.resize(wall_points_.size());
    for (const MovingPoint& point : moving_points_) {
      const RigidPose& pose = particles.obstacle_pose[point.body];
      const Vec2 r = rotated_arm(pose, point.arm);
      wall_points_[point.index] = point.rest + pose.displacement + (r - point.arm);
      point_motion_[point.index] = {rigid_point_velocity(pose, r), rigid_point_acceleration(pose, r)};
    }
    return true;
  }

  std::vector<Vec2> wall_points_;             // m
  std::vector<std::int32_t> point_obstacle_;  // per wall point: walls.obstacles[k], or kNoObstacle (the tank)
  std::vector<MovingPoint> moving_points_;
  std::vector<PointMotion> point_motion_;  // per wall point while obstacles move (zero for fixed points)
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
