// Malformed scenes, generated deterministically from scenes/dambreak.json and
// scenes/hydrostatic.json: every one either loads, and then the scene's invariants hold, or
// is an InputError whose message is one line starting with the source name (and naming
// the key, for a mutation of one key). Never another exception type, never a crash (the
// suite also runs under AddressSanitizer and UndefinedBehaviorSanitizer: tools/test.sh
// --sanitize).
//
// Cases per run (both scenes; each test prints its count), and how many load:
//   truncation at every 5th byte                      458      1 (cut behind the last brace)
//   every key or array element deleted                109     71 (optional keys)
//   every value replaced by each of 11 values        1199    100 (e.g. end_time 0, gravity -1)
//   every value overridden by --set with 7 texts      763     17 (strings where strings go)
//   random byte flips (mt19937, seed 6)              1000     30 (a digit for a digit)
//   hand-picked structural cases                       14      0
//   total                                            3543    (0.13 s Release; 5.8 s under
//                                                             ASan + UBSan, 1 thread)
// The CLI cases at the end run the real binary: exit code 2 and one line on stderr.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "core/base/error.hpp"
#include "core/io/geometry.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

namespace {

// A value or array element of a scene document, with its key as messages print it
// ("fluid_blocks[0].min") and as --set takes it ("fluid_blocks.0.min").
struct Node {
  nlohmann::json::json_pointer pointer;
  std::string key;
  std::string set_key;
};

void collect_nodes(const nlohmann::json& value, const nlohmann::json::json_pointer& pointer, const std::string& key,
                   const std::string& set_key, std::vector<Node>& nodes) {
  if (!pointer.empty()) nodes.push_back({pointer, key, set_key});
  if (value.is_object()) {
    for (const auto& [name, child] : value.items()) {
      collect_nodes(child, pointer / name, key.empty() ? name : key + "." + name,
                    set_key.empty() ? name : set_key + "." + name, nodes);
    }
  } else if (value.is_array()) {
    for (std::size_t k = 0; k < value.size(); ++k) {
      collect_nodes(value[k], pointer / k, key + "[" + std::to_string(k) + "]", set_key + "." + std::to_string(k),
                    nodes);
    }
  }
}

// The key a message should name for a mutation of `key`: an array element is reported
// under its array ("domain.min: got [0.0,null]"), so trailing indices are dropped.
std::string reported_key(std::string key) {
  while (!key.empty() && key.back() == ']') key.erase(key.rfind('['));
  return key;
}

// Keys checked together (the domain against the spacing, the time step against the end
// time): a mutation of one may be reported under another of its group.
std::string key_group(const std::string& key) {
  for (const char* prefix : {"particle_spacing", "domain", "fluid_blocks", "diagnostics.pressure_sensors"}) {
    if (key.rfind(prefix, 0) == 0) return "geometry";
  }
  for (const char* prefix : {"time.", "output.frame_interval", "output.series_interval"}) {
    if (key.rfind(prefix, 0) == 0) return "time";
  }
  return key;
}

// The key of an InputError message "<source>: <key>: <text>" ("" for file-level errors).
std::string message_key(const std::string& message, const std::string& source) {
  const std::string rest = message.substr(source.size() + 2);
  const auto colon = rest.find(": ");
  return colon == std::string::npos ? "" : rest.substr(0, colon);
}

// What must hold for every scene that loads (docs/scene-format.md). Returns "" or the
// first broken invariant.
std::string broken_invariant(const Scene& scene) {
  const auto finite = [](const Vec2& v) { return std::isfinite(v.x()) && std::isfinite(v.y()); };
  const double l0 = scene.particle_spacing;
  const Vec2 extent = scene.domain.max - scene.domain.min;
  if (!(std::isfinite(l0) && l0 > 0.0)) return "particle_spacing";
  if (!(finite(extent) && extent.x() >= 4.0 * l0 && extent.y() >= 4.0 * l0)) return "domain extent";
  if (extent.x() / l0 * extent.y() / l0 > 5.0e7) return "lattice points";
  if (scene.walls.layers < 1 || scene.walls.layers > 10) return "walls.layers";
  if (scene.fluid_blocks.empty()) return "fluid_blocks";
  for (const auto& block : scene.fluid_blocks) {
    if (!finite(block.velocity)) return "fluid velocity";
    if (!(block.region.max.x() > block.region.min.x() && block.region.max.y() > block.region.min.y())) return "block";
  }
  if (!(scene.physics.density > 0.0 && std::isfinite(scene.physics.density))) return "density";
  if (!(scene.physics.kinematic_viscosity >= 0.0 && std::isfinite(scene.physics.kinematic_viscosity)))
    return "viscosity";
  if (!finite(scene.physics.gravity)) return "gravity";
  const double dt = scene.time.time_step;
  if (!(dt > 0.0 && std::isfinite(dt))) return "time_step";
  if (!(scene.time.end_time >= 0.0 && std::isfinite(scene.time.end_time))) return "end_time";
  if (scene.time.end_time / dt > 1.0e10) return "step count";
  if (scene.output.frame_every_steps < 1 || scene.output.series_every_steps < 1) return "every_steps";
  for (double interval : {scene.output.frame_interval, scene.output.series_interval}) {
    if (!(interval == 0.0 || (interval >= 1e-3 * dt && std::isfinite(interval)))) return "interval";
  }
  if (scene.output.directory.empty()) return "output.directory";
  if (!(scene.diagnostics.density_support > 1.0 && scene.diagnostics.density_support <= 4.0)) return "density_support";
  for (const auto& sensor : scene.diagnostics.pressure_sensors) {
    if (!finite(sensor.position)) return "sensor position";
  }
  if (registries().methods.find(scene.method) == nullptr) return "method";
  if (scene.methods.size() != registries().methods.all().size()) return "method blocks";
  // The particles: at least one fluid particle, all strictly inside the domain, so none
  // on a wall layer (those lie on the domain's sides and outside).
  const ParticleSet particles = build_particles(scene);
  if (particles.count(ParticleType::Fluid) == 0) return "no fluid particle";
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] != ParticleType::Fluid) continue;
    const Vec2& x = particles.position[i];
    if (!(x.x() > scene.domain.min.x() && x.x() < scene.domain.max.x() && x.y() > scene.domain.min.y() &&
          x.y() < scene.domain.max.y())) {
      return "fluid particle outside the domain";
    }
  }
  // The resolved scene (stored in run.json) loads again.
  parse_scene(scene.document, scene.source, registries().methods, registries().walls);
  return "";
}

class FuzzCounter {
 public:
  // Loads `text` (with `overrides`); `key` is the mutated key, "" when the mutation is not
  // one key's. Records a failure when the outcome breaks the rules above.
  void check(const std::string& what, const std::string& text, const std::string& key,
             const std::vector<std::string>& overrides = {}) {
    ++cases_;
    const std::string failure = outcome(text, key, overrides);
    if (!failure.empty() && failures_.size() < 20) failures_.push_back(what + ": " + failure);
    if (!failure.empty()) ++failed_;
  }
  long cases() const { return cases_; }
  long loaded() const { return loaded_; }
  long failed() const { return failed_; }
  const std::vector<std::string>& failures() const { return failures_; }

  static constexpr const char* kSource = "fuzz/scene.json";

 private:
  std::string outcome(const std::string& text, const std::string& key, const std::vector<std::string>& overrides) {
    Scene scene;
    try {
      scene = load_scene_text(text, kSource, overrides, registries().methods, registries().walls);
    } catch (const InputError& error) {
      const std::string message = error.what();
      if (message.find('\n') != std::string::npos) return "message of several lines: " + message;
      const bool from_set = message.rfind("--set: ", 0) == 0;
      if (!from_set && message.rfind(std::string(kSource) + ": ", 0) != 0)
        return "message without the source: " + message;
      if (key.empty() || from_set) return "";
      const std::string named = message_key(message, kSource);
      const std::string expected = reported_key(key);
      if (message.find(expected) != std::string::npos || key_group(named) == key_group(expected)) return "";
      return "message does not name " + expected + ": " + message;
    } catch (const std::exception& error) {
      return std::string("not an InputError: ") + error.what();
    }
    ++loaded_;
    try {
      const std::string broken = broken_invariant(scene);
      return broken.empty() ? "" : "loaded, but the invariant '" + broken + "' does not hold";
    } catch (const std::exception& error) {
      return std::string("loaded, but then: ") + error.what();  // e.g. build_particles refusing it
    }
  }

  long cases_ = 0;
  long loaded_ = 0;
  long failed_ = 0;
  std::vector<std::string> failures_;
};

void report(const FuzzCounter& counter, const std::string& name) {
  for (const auto& failure : counter.failures()) UNSCOPED_INFO(failure);
  CHECK(counter.failed() == 0);
  WARN(name << ": " << counter.cases() << " cases, " << counter.loaded() << " loaded");
}

const std::vector<std::string>& base_scenes() {
  static const std::vector<std::string> scenes = {read_text(scene_path("dambreak.json")),
                                                  read_text(scene_path("hydrostatic.json"))};
  return scenes;
}

}  // namespace

TEST_CASE("fuzz: truncated scene files are clean errors", "[scene][input][fuzz]") {
  FuzzCounter counter;
  for (const auto& text : base_scenes()) {
    for (std::size_t length = 0; length < text.size(); length += 5) {
      counter.check("truncated at " + std::to_string(length), text.substr(0, length), "");
    }
  }
  report(counter, "truncation");  // a cut behind the closing brace loads: hydrostatic.json at its last 5th byte
}

TEST_CASE("fuzz: every key and every array element deleted in turn", "[scene][input][fuzz]") {
  FuzzCounter counter;
  for (const auto& text : base_scenes()) {
    const auto document = nlohmann::json::parse(text);
    std::vector<Node> nodes;
    collect_nodes(document, nlohmann::json::json_pointer(), "", "", nodes);
    for (const auto& node : nodes) {
      nlohmann::json mutated = document;
      auto& parent = mutated.at(node.pointer.parent_pointer());
      if (parent.is_object()) {
        parent.erase(node.pointer.back());
      } else {
        parent.erase(std::stoul(node.pointer.back()));
      }
      counter.check("deleted " + node.key, mutated.dump(), node.key);
    }
  }
  report(counter, "deletion");
}

TEST_CASE("fuzz: every value replaced by wrong types - huge - negative and fractional numbers",
          "[scene][input][fuzz]") {
  const std::vector<nlohmann::json> replacements = {
      nullptr, true, "text", nlohmann::json::array(), nlohmann::json::object(), 0, -1, 1e308, -1e308, 2.5, "nan"};
  FuzzCounter counter;
  for (const auto& text : base_scenes()) {
    const auto document = nlohmann::json::parse(text);
    std::vector<Node> nodes;
    collect_nodes(document, nlohmann::json::json_pointer(), "", "", nodes);
    for (const auto& node : nodes) {
      for (const auto& replacement : replacements) {
        nlohmann::json mutated = document;
        mutated.at(node.pointer) = replacement;
        counter.check(node.key + " = " + replacement.dump(), mutated.dump(), node.key);
      }
    }
  }
  report(counter, "replacement");
  CHECK(counter.loaded() > 0);  // e.g. a description of "text", end_time 0, a block velocity of -1
}

TEST_CASE("fuzz: --set overrides with texts JSON cannot hold", "[scene][input][fuzz]") {
  // "nan" and "inf" reach the scene as strings; 1e309 overflows a double; a key given twice,
  // a value nested 40 deep, bytes that are not UTF-8, an empty value.
  const std::vector<std::string> texts = {
      "nan", "inf", "1e309", R"({"a": 1, "a": 2})", std::string(40, '[') + std::string(40, ']'), "\xff\xfe", ""};
  FuzzCounter counter;
  for (const auto& text : base_scenes()) {
    std::vector<Node> nodes;
    collect_nodes(nlohmann::json::parse(text), nlohmann::json::json_pointer(), "", "", nodes);
    for (const auto& node : nodes) {
      for (const auto& value : texts) {
        counter.check("--set " + node.set_key + "=" + value, text, node.key, {node.set_key + "=" + value});
      }
    }
  }
  report(counter, "--set");
}

TEST_CASE("fuzz: random byte flips", "[scene][input][fuzz]") {
  std::mt19937 random(6);  // fixed seed: the same 1000 mutants every run
  FuzzCounter counter;
  for (const auto& text : base_scenes()) {
    std::uniform_int_distribution<std::size_t> position(0, text.size() - 1);
    std::uniform_int_distribution<int> byte(0, 255);
    std::uniform_int_distribution<int> flips(1, 3);
    for (int k = 0; k < 500; ++k) {
      std::string mutated = text;
      std::string what = "flipped";
      for (int f = flips(random); f > 0; --f) {
        const std::size_t at = position(random);
        mutated[at] = static_cast<char>(byte(random));
        what += " " + std::to_string(at);
      }
      counter.check(what, mutated, "");
    }
  }
  report(counter, "byte flips");
}

TEST_CASE("fuzz: structural cases", "[scene][input][fuzz]") {
  const std::string minimal_blocks =
      R"("domain": {"min": [0, 0], "max": [1, 0.6]}, "fluid_blocks": [{"min": [0, 0], "max": [0.25, 0.5]}])";
  struct Case {
    std::string text, expected;
  };
  const std::vector<Case> cases = {
      {"", "not valid JSON"},
      {"[]", "got [], expected a JSON object at the top level"},
      {"null", "got null, expected a JSON object"},
      {"\"scene\"", "expected a JSON object"},
      {"{" + minimal_blocks + ", \"particle_spacing\": 1e309}", "not valid JSON: number overflow parsing '1e309'"},
      {"{" + minimal_blocks + ", \"time\": {\"time_step\": 1e-3, \"time_step\": 1e-4}}", "time.time_step: given twice"},
      {"{" + minimal_blocks + ", \"description\": " + std::string(100000, '[') + std::string(100000, ']') + "}",
       "description: got values nested deeper than 32 levels"},
      {"{" + minimal_blocks + ", \"physics\": null}", "physics: got null, expected an object"},
      {"{" + minimal_blocks + ", \"methods\": {\"mps\": null}}", "methods.mps: got null, expected an object"},
      {"{" + minimal_blocks + R"(, "methods": {"mps": {"wall_treatments": {"wall_repulsion": null}}}})",
       "methods.mps.wall_treatments.wall_repulsion: got null"},
      {"{" + minimal_blocks + ", \"a\\nb\": 1}", "a\\nb: unknown key"},
      {"{" + minimal_blocks + ", \"description\": \"" + std::string(5000, 'x') + "\", \"method\": 1}",
       "method: got 1, expected a string"},
      {"{" + minimal_blocks + R"(, "output": {"series_interval": 1e-300}})", "output.series_interval: got 1e-300"},
      {"{" + minimal_blocks + R"(, "diagnostics": {"pressure_sensors": [{"name": "x", "position": [2, 0]}]}})",
       "diagnostics.pressure_sensors[0].position: got [2.0,0.0], expected a point inside the domain"},
  };
  FuzzCounter counter;
  for (const auto& test : cases) {
    INFO(test.text.substr(0, 200));
    counter.check("structural", test.text, "");
    CHECK_THROWS_WITH(load_scene_text(test.text, "s.json", {}, registries().methods, registries().walls),
                      Catch::StartsWith("s.json: ") && Catch::Contains(test.expected));
  }
  report(counter, "structural");
}

TEST_CASE("bad scenes through the binary: exit code 2 - one line on stderr - no output folder", "[cli][input]") {
  const auto dir = fresh_directory("cli_fuzz_scenes");
  const std::string base = read_text(scene_path("dambreak.json"));
  write_text(dir / "truncated.json", base.substr(0, base.size() / 2));
  write_text(dir / "overflow.json", R"({"particle_spacing": 1e309})");
  write_text(dir / "twice.json", R"({"time": {"end_time": 1, "end_time": 2}})");
  write_text(dir / "deep.json", "{\"description\": " + std::string(5000, '[') + std::string(5000, ']') + "}");
  const std::string scene = scene_path("dambreak.json");
  struct Case {
    std::string arguments, expected;
  };
  const std::vector<Case> cases = {
      {(dir / "truncated.json").string(), "truncated.json: not valid JSON: parse error"},
      {(dir / "overflow.json").string(), "overflow.json: not valid JSON: number overflow parsing '1e309'"},
      {(dir / "twice.json").string(), "twice.json: time.end_time: given twice in one object"},
      {(dir / "deep.json").string(), "deep.json: description: got values nested deeper than 32 levels"},
      {dir.string(), ": is a folder, expected a scene file"},
      {scene + " --set time.time_step=nan", "time.time_step: got \"nan\", expected a number > 0"},
      {scene + " --set walls.layers=2.5", "walls.layers: got 2.5, expected an integer in [1, 10]"},
      {scene + " --set methods.mps.warm_start=1", "methods.mps.warm_start: got 1, expected true or false"},
      {scene + " --set physics=null", "physics: got null, expected an object"},
      {scene + " --set time.end_time=1e308", "time.end_time: got 1e+308, expected at most 1e10 steps"},
      {scene + " --set particle_spacing=0.03", "particle_spacing: got 0.03, expected a spacing that divides"},
      {scene + " --set fluid_blocks.0.min=[-1,0]",
       "fluid_blocks[0].min: got [-1.0,0.0], expected a point inside the domain"},
  };
  const auto out = dir / "never_created";
  for (std::size_t k = 0; k < cases.size(); ++k) {
    INFO(cases[k].arguments);
    const auto result =
        run_mps_lab("run " + cases[k].arguments + " --out " + out.string(), "fuzz_" + std::to_string(k));
    CHECK(result.exit_code == 2);
    CHECK(std::count(result.stderr_text.begin(), result.stderr_text.end(), '\n') == 1);
    CHECK_THAT(result.stderr_text, Catch::StartsWith("mps_lab: error: ") && Catch::Contains(cases[k].expected));
    CHECK_FALSE(std::filesystem::exists(out));  // validation comes before the output folder
  }
}
