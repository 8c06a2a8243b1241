// Particle-particle collision (MPS spec §6.4): when a fluid particle i and a neighbour j
// (fluid or wall) are closer than distance l0 (spec 0.5 l0) and approaching, the normal
// part of their relative velocity is reversed and damped with restitution e (spec 0.2):
//   e_ij = (x_j - x_i)/r,  v_n = (v_i - v_j) . e_ij > 0,
//   v_i += -(1 + e) v_n (m_j / (m_i + m_j)) e_ij      (equal masses: factor 0.5).
// Every fluid particle is updated from the velocities before any collision of this step
// (Jacobi sweep), so the result does not depend on particle order or thread count; wall
// particles do not move. Positions are not changed (the spec changes velocities only).
// With a boundary model of wall samples the samples take the wall particles' part.
#include <cmath>
#include <vector>

#include "core/io/scene.hpp"
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {
namespace {

class ParticleCollision final : public WallTreatment {
 public:
  explicit ParticleCollision(const WallTreatmentSetup& setup)
      : distance_(setup.parameters.number("distance") * setup.scene.particle_spacing),
        restitution_(setup.parameters.number("restitution")) {}

  void after_neighbour_search(WallContext& context) override {
    auto& particles = context.particles;
    const NeighbourList& neighbours = *context.neighbours;
    before_ = particles.velocity;
    const double distance2 = distance_ * distance_;
    const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      if (particles.type[i] != ParticleType::Fluid) continue;
      Vec2 change = Vec2::Zero();
      for (std::uint32_t k = neighbours.begin(i); k < neighbours.end(i); ++k) {
        const std::uint32_t j = neighbours.indices[k];
        if (particles.type[j] == ParticleType::Ghost) continue;
        const Vec2 between = particles.position[j] - particles.position[i];
        const double r2 = between.squaredNorm();
        if (r2 >= distance2 || r2 <= 0.0) continue;
        const Vec2 normal = between / std::sqrt(r2);
        const double approach = (before_[i] - before_[j]).dot(normal);
        if (approach <= 0.0) continue;
        change -= (1.0 + restitution_) * approach * 0.5 * normal;
      }
      // Wall samples (boundary models without wall particles) collide as wall particles do,
      // with their own velocity (0, a mirror image's reflected velocity, a moving wall's).
      if (context.samples != nullptr && context.samples->has_samples()) {
        for (std::uint32_t k = context.samples->begin(i); k < context.samples->end(i); ++k) {
          const WallSample& sample = context.samples->samples[k];
          const Vec2 between = sample.position - particles.position[i];
          const double r2 = between.squaredNorm();
          if (r2 >= distance2 || r2 <= 0.0) continue;
          const Vec2 normal = between / std::sqrt(r2);
          const double approach =
              (before_[i] - (sample.velocity_map * before_[sample.source] + sample.wall_velocity)).dot(normal);
          if (approach <= 0.0) continue;
          change -= (1.0 + restitution_) * approach * 0.5 * normal;
        }
      }
      particles.velocity[i] += change;
    }
  }

 private:
  double distance_;  // m
  double restitution_;
  std::vector<Vec2> before_;  // velocities before this step's collisions (reused storage)
};

}  // namespace
}  // namespace mps_lab

void mps_lab_register_wall_treatment_particle_collision(mps_lab::WallTreatmentRegistry& registry) {
  using namespace mps_lab;
  WallTreatmentInfo info{
      "particle_collision",
      "damped reflection of approaching particle pairs closer than 0.5 l0 (MPS spec 6.4)",
      {number_parameter("distance", 0.5, "l0", "collision distance").above(0.0).at_most(2.0),
       number_parameter("restitution", 0.2, "", "coefficient of restitution e").at_least(0.0).at_most(1.0)},
      30,
      [](const WallTreatmentSetup& setup) { return std::make_unique<ParticleCollision>(setup); }};
  info.hooks = {WallHook::AfterNeighbourSearch};
  registry.add(std::move(info));
}
