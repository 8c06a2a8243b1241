#pragma once
// Basic value types shared by the core and every method.
#include <Eigen/Core>
#include <cstdint>
#include <string_view>

namespace mps_lab {

using Vec2 = Eigen::Vector2d;

// Particle types. The values 0, 1, 2 are the specification's (spec §9) and are what the
// CSV/VTK frames write in their `type` column. The enum is one byte wide so later kinds
// (e.g. mirror particles) fit without changing the storage.
enum class ParticleType : std::uint8_t {
  Fluid = 0,  // computed fluid
  Wall = 1,   // fixed wall particle; which wall layers carry pressure is the method's choice
  Ghost = 2,  // left the computation (spec §7.3); never written, never a neighbour
};

constexpr std::string_view to_string(ParticleType type) {
  switch (type) {
    case ParticleType::Fluid:
      return "fluid";
    case ParticleType::Wall:
      return "wall";
    case ParticleType::Ghost:
      return "ghost";
  }
  return "unknown";
}

}  // namespace mps_lab
