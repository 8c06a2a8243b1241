// Every scene key and every declared parameter is documented: docs/scene-format.md for the
// shared blocks and the wall treatments, docs/methods/<name>.md for each method.
#include <catch2/catch.hpp>

#include "core/io/scene.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

namespace {
std::string doc(const std::string& relative) {
  return read_text(std::string(MPS_LAB_SOURCE_DIR) + "/docs/" + relative);
}
}  // namespace

TEST_CASE("every shared scene key and wall-treatment parameter is in docs/scene-format.md", "[docs]") {
  const std::string text = doc("scene-format.md");
  REQUIRE_FALSE(text.empty());
  for (const auto& block : shared_scene_keys()) {
    for (const auto& spec : block.keys) {
      INFO("block '" << block.path << "' key '" << spec.name << "'");
      CHECK(text.find("`" + spec.name + "`") != std::string::npos);
    }
    if (!block.path.empty()) {
      INFO("block " << block.path);
      std::string name = block.path.substr(0, block.path.find('['));
      name = name.substr(name.rfind('.') + 1);  // "diagnostics.pressure_sensors" -> "pressure_sensors"
      CHECK(text.find("`" + name) != std::string::npos);
    }
  }
  for (const auto* wall : registries().walls.all()) {
    INFO("wall treatment " << wall->name);
    CHECK(text.find("`" + wall->name + "`") != std::string::npos);
    for (const auto& spec : wall->parameters) {
      INFO("parameter " << spec.name);
      CHECK(text.find("`" + spec.name + "`") != std::string::npos);
    }
  }
}

TEST_CASE("every method has docs/methods/<name>.md listing each of its parameters", "[docs]") {
  for (const auto* method : registries().methods.all()) {
    const std::string text = doc("methods/" + method->name + ".md");
    INFO("method " << method->name);
    REQUIRE_FALSE(text.empty());
    for (const auto& spec : method->parameters) {
      INFO("parameter " << spec.name);
      CHECK(text.find("`" + spec.name + "`") != std::string::npos);
    }
  }
}
