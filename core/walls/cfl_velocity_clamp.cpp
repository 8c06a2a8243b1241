// CFL velocity clamp (MPS spec §6.1): after the explicit velocity update, a fluid particle
// faster than v_max = CFL l0 / dt keeps its direction and gets speed v_max, so no particle
// moves more than CFL l0 in a step.
#include <cmath>

#include "core/io/scene.hpp"
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {
namespace {

class CflVelocityClamp final : public WallTreatment {
 public:
  explicit CflVelocityClamp(const WallTreatmentSetup& setup)
      : cfl_(setup.parameters.number("cfl")), spacing_(setup.scene.particle_spacing) {}

  void after_explicit_velocity(WallContext& context) override {
    auto& particles = context.particles;
    const double v_max = cfl_ * spacing_ / context.dt;  // m/s
    const auto n = static_cast<std::ptrdiff_t>(particles.size());
    std::size_t limited = 0;
#pragma omp parallel for schedule(static) reduction(+ : limited)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      if (particles.type[i] != ParticleType::Fluid) continue;
      const double speed = particles.velocity[i].norm();
      if (speed > v_max) {
        particles.velocity[i] *= v_max / speed;
        ++limited;
      }
    }
    context.speed_limited += limited;
  }

 private:
  double cfl_;
  double spacing_;  // m
};

}  // namespace
}  // namespace mps_lab

void mps_lab_register_wall_treatment_cfl_velocity_clamp(mps_lab::WallTreatmentRegistry& registry) {
  using namespace mps_lab;
  WallTreatmentInfo info{
      "cfl_velocity_clamp",
      "caps fluid speed at CFL l0/dt after the explicit update (MPS spec 6.1)",
      {number_parameter("cfl", 0.2, "", "Courant number of the cap, v_max = cfl l0 / dt").above(0.0)},
      10,
      [](const WallTreatmentSetup& setup) { return std::make_unique<CflVelocityClamp>(setup); }};
  info.hooks = {WallHook::AfterExplicitVelocity};
  registry.add(std::move(info));
}
