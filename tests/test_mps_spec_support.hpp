#pragma once
// Shared by tests/test_mps_spec_*.cpp: the tests of the MPS specification item by item, on
// hand-built particle sets, through the real code paths (the registries, the mps method, the
// wall treatments, the operators). Each expected value is derived by hand in a comment.
// These tests are the quick suite of the mutation testing (tools/mutation_test.py).
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "core/run/method.hpp"
#include "core/search/neighbour_search.hpp"
#include "support.hpp"

namespace mps_lab::spec_testing {

constexpr double kSpacing = 0.025;    // l0, m (spec §3)
constexpr double kTimeStep = 5.0e-4;  // dt, s (spec §3)

// The spec's tank with every value left to its default: what the scene loader and the
// method declare, not what scenes/dambreak.json spells out.
inline Scene defaults_scene(const std::vector<std::string>& overrides = {}) {
  nlohmann::json document = nlohmann::json::parse(R"({
    "domain": { "min": [0.0, 0.0], "max": [1.0, 0.6] },
    "fluid_blocks": [ { "min": [0.0, 0.0], "max": [0.25, 0.5] } ],
    "method": "mps"
  })");
  for (const auto& assignment : overrides) apply_override(document, assignment, "defaults.json");
  return parse_scene(document, "defaults.json", testing::registries().methods, testing::registries().walls);
}

// Lattice constants of spec §2 for re = 2.1 l0, by hand: the lattice neighbours inside re are
// 4 at l0 (w = 2.1 - 1 = 1.1), 4 at sqrt(2) l0 (w = 2.1/sqrt(2) - 1) and 4 at 2 l0 (w = 0.05);
// sqrt(5) l0 = 2.236 l0 is outside.
inline double hand_n0() { return 4.0 * 1.1 + 4.0 * (2.1 / std::sqrt(2.0) - 1.0) + 4.0 * 0.05; }  // 6.53970
inline double hand_lambda(double l0) {  // sum r^2 w / sum w = 1.38835 l0^2
  return l0 * l0 * (4.0 * 1.0 * 1.1 + 4.0 * 2.0 * (2.1 / std::sqrt(2.0) - 1.0) + 4.0 * 4.0 * 0.05) / hand_n0();
}

// A particle set with the fields the mps method declares (the driver adds them).
inline ParticleSet mps_particles() {
  ParticleSet particles;
  for (const auto& field : testing::registries().methods.find("mps")->fields) particles.add_field(field.name);
  return particles;
}

// The scene's choices for the mps method with `extra` appended (e.g. a recording treatment).
inline std::unique_ptr<Method> make_mps(const Scene& scene, const std::vector<WallTreatmentChoice>& extra = {}) {
  const MethodConfig& config = scene.method_config("mps");
  MethodSetup setup{scene, config.parameters, config.wall_treatments};
  for (const auto& choice : extra) setup.wall_treatments.push_back(choice);
  return testing::registries().methods.find("mps")->create(setup);
}

// Only the named wall treatment of the scene's mps choices, enabled with its resolved
// parameters (defaults unless the scene sets them).
inline WallTreatmentSet only_treatments(const Scene& scene, const std::vector<std::string>& names) {
  std::vector<WallTreatmentChoice> choices = scene.method_config("mps").wall_treatments;
  for (auto& choice : choices) {
    bool wanted = false;
    for (const auto& name : names) wanted = wanted || choice.info->name == name;
    choice.enabled = wanted;
  }
  return WallTreatmentSet(choices, scene);
}

}  // namespace mps_lab::spec_testing
