// The scene's "validation" block (docs/scene-format.md): which experimental pressure record a
// sensor compares with (scenes/dambreak_buchner.json, docs/validation.md "Wall pressure:
// Buchner 2002"). Read and checked by core/io/scene.cpp; written to run.json for the analysis.
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>

#include "core/io/scene.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

TEST_CASE("validation block: the Buchner scene names its records by sensor with resolved paths",
          "[unit][input][validation_block]") {
  const Scene scene = load("dambreak_buchner.json");
  CHECK(scene.validation.length_scale == 0.6);
  CHECK(scene.validation.impact_threshold == 0.1);
  CHECK(scene.validation.quasi_static == Vec2(3.0, 5.5));
  REQUIRE(scene.validation.pressure_records.size() == 2);
  CHECK(scene.validation.pressure_records[0].sensor == "P1");
  CHECK(scene.validation.pressure_records[1].sensor == "P2");
  for (const auto& record : scene.validation.pressure_records) {
    INFO(record.file);
    CHECK(std::filesystem::path(record.file).is_absolute());
    CHECK(std::filesystem::exists(record.file));
  }
  // A scene without the block has none (and pays nothing).
  CHECK(load("dambreak.json").validation.pressure_records.empty());
  CHECK(load("dambreak.json").validation.length_scale == 0.0);
}

TEST_CASE("validation block: wrong keys and records are one-line errors naming the key",
          "[unit][input][validation_block]") {
  const std::string scene = "dambreak_buchner.json";
  CHECK_THROWS_WITH(load(scene, {"validation.pressure_records.0.sensor=P9"}),
                    Catch::Contains("validation.pressure_records[0].sensor: got \"P9\", expected the name of a "
                                    "diagnostics.pressure_sensors entry (P1, P2)"));
  CHECK_THROWS_WITH(load(scene, {"validation.pressure_record=[]"}),
                    Catch::Contains("validation.pressure_record: unknown key"));
  CHECK_THROWS_WITH(load(scene, {"validation.pressure_records.0.sensors=P1"}),
                    Catch::Contains("validation.pressure_records[0].sensors: unknown key"));
  CHECK_THROWS_WITH(
      load(scene, {"validation.pressure_records.0.file=no_such_record.csv"}),
      Catch::Contains("validation.pressure_records[0].file: cannot read") && Catch::Contains("no_such_record.csv"));
  CHECK_THROWS_WITH(load(scene, {"validation.length_scale=0"}),
                    Catch::Contains("validation.length_scale: got 0, expected a number > 0"));
  CHECK_THROWS_WITH(load(scene, {"validation.quasi_static=[5.5,3]"}),
                    Catch::Contains("validation.quasi_static: got [5.5,3.0], expected [T0, T1] with T1 > T0"));
  CHECK_THROWS_WITH(load(scene, {"validation=null"}), Catch::Contains("validation: got null, expected an object"));
  // A record for a scene without sensors: nothing to compare it with.
  CHECK_THROWS_WITH(
      load("dambreak.json", {"validation={\"length_scale\": 0.6, \"pressure_records\": [{\"sensor\": \"P1\", "
                             "\"file\": \"../analysis/validation/buchner_2002_p1.csv\"}]}"}),
      Catch::Contains("validation.pressure_records[0].sensor: got \"P1\", expected the name of a "
                      "diagnostics.pressure_sensors entry (right_wall_bottom)"));
  CHECK_THROWS_WITH(load("hydrostatic.json", {"validation={\"length_scale\": 0.3, \"pressure_records\": "
                                              "[{\"sensor\": \"a\", \"file\": \"x.csv\"}]}"}),
                    Catch::Contains("(the scene has none)"));
  CHECK_THROWS_WITH(load(scene, {"validation={\"pressure_records\": []}"}), Catch::Contains("validation.length_scale"));
}

TEST_CASE("validation block: a record file that is not two columns of numbers is an error naming its line",
          "[unit][input][validation_block]") {
  const auto folder = fresh_directory("validation_block");
  const auto write = [&](const std::string& name, const std::string& text) {
    std::ofstream(folder / name) << text;
    return "validation.pressure_records.0.file=" + (folder / name).string();
  };
  CHECK_THROWS_WITH(load("dambreak_buchner.json", {write("bad_row.csv", "# c\nT,p\n2.0,0.1\n2.1,abc\n")}),
                    Catch::Contains("validation.pressure_records[0].file: ") && Catch::Contains("line 4") &&
                        Catch::Contains("expected two numbers T,p"));
  CHECK_THROWS_WITH(load("dambreak_buchner.json", {write("one_row.csv", "T,p\n2.0,0.1\n")}),
                    Catch::Contains("expected a header line and at least two rows T,p"));
  CHECK_NOTHROW(load("dambreak_buchner.json", {write("good.csv", "# c\nT,p\n2.0,0.1\n2.1,0.2\n")}));
}
