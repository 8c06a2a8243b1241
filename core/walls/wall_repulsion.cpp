// Wall repulsion (MPS spec §6.2): a fluid particle i closer than r_rep = distance l0 to a
// wall particle j is pushed away, one-way (wall -> fluid):
//   overlap = 1 - r / r_rep,  a = C overlap^2,  v_i += dt a (x_i - x_j) / r,
// summed over the wall neighbours. The spec gives C = 196.2 = 0.5 |g| / l0 at l0 = 0.025 m;
// the parameter is the factor 0.5 so that C follows l0 in resolution studies. With a boundary
// model of wall samples (core/walls/wall_samples.hpp) the samples push as wall particles do.
#include <cmath>

#include "core/io/scene.hpp"
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {
namespace {

class WallRepulsion final : public WallTreatment {
 public:
  explicit WallRepulsion(const WallTreatmentSetup& setup)
      : distance_(setup.parameters.number("distance") * setup.scene.particle_spacing),
        coefficient_(setup.parameters.number("coefficient_factor") * setup.scene.physics.gravity.norm() /
                     setup.scene.particle_spacing) {}

  void after_neighbour_search(WallContext& context) override {
    auto& particles = context.particles;
    const NeighbourList& neighbours = *context.neighbours;
    const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      if (particles.type[i] != ParticleType::Fluid) continue;
      Vec2 push = Vec2::Zero();
      for (std::uint32_t k = neighbours.begin(i); k < neighbours.end(i); ++k) {
        const std::uint32_t j = neighbours.indices[k];
        if (particles.type[j] != ParticleType::Wall) continue;
        const Vec2 away = particles.position[i] - particles.position[j];
        const double r = away.norm();
        if (r >= distance_ || r <= 0.0) continue;
        const double overlap = 1.0 - r / distance_;
        push += coefficient_ * overlap * overlap * away / r;  // m/s^2
      }
      if (context.samples != nullptr && context.samples->has_samples()) {  // wall samples act as wall particles
        for (std::uint32_t k = context.samples->begin(i); k < context.samples->end(i); ++k) {
          const Vec2 away = particles.position[i] - context.samples->samples[k].position;
          const double r = away.norm();
          if (r >= distance_ || r <= 0.0) continue;
          const double overlap = 1.0 - r / distance_;
          push += coefficient_ * overlap * overlap * away / r;  // m/s^2
        }
      }
      particles.velocity[i] += context.dt * push;
    }
  }

 private:
  double distance_;     // m
  double coefficient_;  // m/s^2 at full overlap
};

}  // namespace
}  // namespace mps_lab

void mps_lab_register_wall_treatment_wall_repulsion(mps_lab::WallTreatmentRegistry& registry) {
  using namespace mps_lab;
  WallTreatmentInfo info{
      "wall_repulsion",
      "one-way push of fluid particles closer than l0 to a wall particle (MPS spec 6.2)",
      {number_parameter("distance", 1.0, "l0", "range r_rep of the repulsion").above(0.0).at_most(2.0),
       number_parameter("coefficient_factor", 0.5, "",
                        "C = factor |g| / l0 (spec: 0.5, i.e. C = 196.2 at l0 = 0.025 m)")
           .at_least(0.0)},
      20,
      [](const WallTreatmentSetup& setup) { return std::make_unique<WallRepulsion>(setup); }};
  info.hooks = {WallHook::AfterNeighbourSearch};
  registry.add(std::move(info));
}
