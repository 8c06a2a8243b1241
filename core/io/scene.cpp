#include "core/io/scene.hpp"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sstream>

#include "core/base/error.hpp"
#include "core/bodies/mass_properties.hpp"
#include "core/io/geometry.hpp"
#include "core/run/method.hpp"
#include "core/walls/wall_geometry.hpp"
#include "core/walls/wall_polygon.hpp"

namespace mps_lab {

namespace {

// Nominal limits beyond which a scene is "far outside what was tested" (spec §3 note:
// the original C code had 10000 particles and 256 neighbours as fixed arrays).
constexpr double kLargestLatticePoints = 5.0e7;
// A run of more steps than this (end_time / time_step) is a typo, not an experiment: at the
// fastest measured 0.1 ms per step it would take 12 days; 1e308 s would never end.
constexpr double kMostTimeSteps = 1.0e10;
// An output interval this much shorter than the time step is a typo (it would mean "every
// step", which frame_every_steps = 1 says); the driver steps its next output time by the
// interval, so 1e-300 s would loop for ever.
constexpr double kShortestIntervalInSteps = 1.0e-3;
// A scene nests 5 levels deep; anything deeper is refused while parsing, before a deep
// value is printed or copied (both recurse once per level and could exhaust the stack).
constexpr int kDeepestNesting = 32;

std::vector<ParameterSpec> top_level_keys() {
  return {
      string_parameter("description", "", "free text describing the scene and its source"),
      number_parameter("particle_spacing", 0.025, "m", "initial particle spacing l0 (spec §3)").above(0.0),
      string_parameter("method", "mps", "method used when the command line does not name one"),
  };
}

std::vector<ParameterSpec> domain_keys() {
  return {
      vector2_parameter("min", Vec2::Zero(), "m", "lower-left corner; first wall layers lie on the box").mandatory(),
      vector2_parameter("max", Vec2::Zero(), "m", "upper-right corner").mandatory(),
  };
}

std::vector<ParameterSpec> wall_keys() {
  return {
      string_list_parameter("sides", {"bottom", "left", "right"}, "sides of the domain box that are walls")
          .one_of({"bottom", "left", "right", "top"}),
      integer_parameter("layers", 3, "wall particle layers per wall (spec §3)").at_least(1).at_most(10),
  };
}

std::vector<ParameterSpec> obstacle_keys() {
  return {
      vector2_parameter("min", Vec2::Zero(), "m", "lower-left corner: a lattice point inside the domain").mandatory(),
      vector2_parameter("max", Vec2::Zero(), "m", "upper-right corner: a lattice point inside the domain").mandatory(),
  };
}

// walls.obstacles[k].motion (core/walls/wall_motion.hpp): the law and the keys of each law.
std::vector<ParameterSpec> motion_keys() {
  return {
      string_parameter("law", "", "the motion law of the obstacle")
          .one_of({"constant_velocity", "constant_acceleration", "sinusoid", "table"})
          .mandatory(),
      number_parameter("start_time", 0.0, "s", "the obstacle rests at its scene position until this time")
          .at_least(0.0),
      vector2_parameter("velocity", Vec2::Zero(), "m/s", "constant_velocity: the velocity V"),
      vector2_parameter("acceleration", Vec2::Zero(), "m/s^2", "constant_acceleration: the acceleration a"),
      number_parameter("max_speed", 0.0, "m/s", "constant_acceleration: the speed where acceleration stops (0: never)")
          .at_least(0.0),
      vector2_parameter("amplitude", Vec2::Zero(), "m", "sinusoid: the amplitude vector A"),
      number_parameter("period", 1.0, "s", "sinusoid: the period T").above(0.0),
      number_parameter("phase", 0.0, "rad", "sinusoid: the phase phi"),
      string_parameter("file", "", "table: CSV file of rows t,x,y (s, m, m), relative to the scene file"),
  };
}

// walls.obstacles[k].circle: a circle obstacle.
std::vector<ParameterSpec> circle_keys() {
  return {
      vector2_parameter("centre", Vec2::Zero(), "m", "the circle's centre, inside the domain").mandatory(),
      number_parameter("radius", 0.0, "m", "the circle's radius (its wall surface)").above(0.0).mandatory(),
  };
}

// walls.obstacles[k].body (docs/bodies.md): the obstacle is a rigid body.
std::vector<ParameterSpec> body_keys() {
  return {
      number_parameter("density", 0.0, "kg/m^3",
                       "the body's uniform density (2-D: over a unit width; mass in kg per m of width)")
          .above(0.0)
          .mandatory(),
      vector2_parameter("velocity", Vec2::Zero(), "m/s", "initial velocity of the centre of mass"),
      number_parameter("angular_velocity", 0.0, "rad/s", "initial angular velocity, counter-clockwise positive"),
  };
}

// contact (core/bodies/rigid_bodies.hpp): the spring-dashpot contact of rigid bodies.
std::vector<ParameterSpec> contact_keys() {
  return {
      number_parameter("stiffness", 1.0e6, "N/m^2", "normal spring stiffness k_n, N/m per m of width").above(0.0),
      number_parameter("damping_ratio", 0.3, "1", "damping ratio zeta of the normal and tangential dashpots")
          .at_least(0.0),
      number_parameter("friction", 0.5, "1", "Coulomb friction coefficient mu").at_least(0.0),
      number_parameter("tangential_stiffness", 2.0 / 7.0, "1",
                       "tangential spring stiffness as a fraction of the normal one, k_t / k_n")
          .above(0.0),
      integer_parameter("steps_per_period", 20, "body sub-steps per contact period 2 pi sqrt(m_eff / k_n)").at_least(4),
  };
}

std::vector<ParameterSpec> fluid_block_keys() {
  return {
      vector2_parameter("min", Vec2::Zero(), "m", "lower-left corner of the water region").mandatory(),
      vector2_parameter("max", Vec2::Zero(), "m", "upper-right corner of the water region").mandatory(),
      vector2_parameter("velocity", Vec2::Zero(), "m/s", "initial velocity of the block"),
  };
}

std::vector<ParameterSpec> physics_keys() {
  return {
      number_parameter("density", 1000.0, "kg/m^3", "fluid density rho (spec §3)").above(0.0),
      number_parameter("kinematic_viscosity", 1.0e-6, "m^2/s", "kinematic viscosity nu (spec §3)").at_least(0.0),
      vector2_parameter("gravity", Vec2(0.0, -9.81), "m/s^2", "gravitational acceleration (spec §3)"),
  };
}

std::vector<ParameterSpec> time_keys() {
  return {
      number_parameter("time_step", 5.0e-4, "s", "time step dt (spec §3); initial and largest step of adaptive methods")
          .above(0.0),
      number_parameter("end_time", 2.0, "s", "simulated time T_end (spec §3)").at_least(0.0),
  };
}

std::vector<ParameterSpec> output_keys() {
  return {
      string_parameter("directory", "output", "output folder, relative to the working directory"),
      integer_parameter("frame_every_steps", 100, "write a CSV/VTK frame every N steps (spec §3)").at_least(1),
      integer_parameter("series_every_steps", 10, "write a row of series.csv every N steps").at_least(1),
      number_parameter("frame_interval", 0.0, "s",
                       "also write a frame at the first step at or after every multiple of this time (0: off)")
          .at_least(0.0),
      number_parameter("series_interval", 0.0, "s",
                       "also write a series row at the first step at or after every multiple of this time (0: off)")
          .at_least(0.0),
      string_list_parameter("formats", {"csv", "vtk"}, "frame formats (vtu: VTK XML binary, for large runs)")
          .one_of({"csv", "vtk", "vtu"}),
      integer_parameter("checkpoint_every_steps", 0,
                        "write the full state to checkpoint.bin every N steps, for `mps_lab resume` (0: off)")
          .at_least(0),
  };
}

// The run block: how the driver runs any method (core/run/driver.cpp).
std::vector<ParameterSpec> run_keys() {
  return {
      integer_parameter("sort_period", kDefaultSortPeriod,
                        "reorder the particles by cell every N steps (core/search/cell_order.hpp; 0: never)")
          .at_least(0)
          .at_most(1000000000),
  };
}

std::vector<ParameterSpec> diagnostics_keys() {
  return {
      number_parameter("front_link_distance", 1.5, "l0",
                       "fluid particles closer than this are one body of water (front and height ignore "
                       "detached drops)")
          .above(0.0),
      number_parameter("height_probe_width", 1.5, "l0",
                       "water height is measured on particles within this distance of the back-wall surface")
          .above(0.0),
      number_parameter("density_support", 2.4, "l0",
                       "support of the cubic-spline kernel of the method-independent density error")
          .above(1.0)
          .at_most(4.0),
  };
}

std::vector<ParameterSpec> pressure_sensor_keys() {
  // The diameter's default is one particle_spacing: no fixed number (null), read in read_diagnostics.
  ParameterSpec diameter =
      number_parameter("diameter", 0.0, "m", "diameter of the sensor's face on the wall (default: particle_spacing)")
          .above(0.0);
  diameter.default_value = nullptr;
  return {
      string_parameter("name", "", "sensor name; series.csv gets columns pressure_<name> and pressure_<name>_max")
          .mandatory(),
      vector2_parameter("position", Vec2::Zero(), "m", "centre of the sensor's face, on a wall surface").mandatory(),
      diameter,
  };
}

std::vector<ParameterSpec> validation_keys() {
  return {
      number_parameter("length_scale", 0.0, "m",
                       "H of the experiment's variables: time T = t sqrt(g/H), pressure p / (rho g H)")
          .above(0.0)
          .mandatory(),
      number_parameter("impact_threshold", 0.1, "rho g H",
                       "the impact time is the first time a sensor's pressure reaches this")
          .above(0.0),
      vector2_parameter("quasi_static", Vec2(3.0, 5.5), "T",
                        "[T0, T1]: the window of the quasi-static RMS error of p / (rho g H)"),
  };
}

std::vector<ParameterSpec> pressure_record_keys() {
  return {
      string_parameter("sensor", "", "name of the diagnostics.pressure_sensors entry the record belongs to")
          .mandatory(),
      string_parameter("file", "", "CSV of T = t sqrt(g/H) and p / (rho g H), relative to the scene file").mandatory(),
  };
}

std::string join(const std::vector<std::string>& items) {
  std::string text;
  for (const auto& item : items) text += (text.empty() ? "" : ", ") + item;
  return text;
}

std::string describe_point(const Vec2& point) { return describe_json(nlohmann::json::array({point.x(), point.y()})); }

bool inside_box(const Vec2& point, const Box& box, double tolerance) {
  return point.x() >= box.min.x() - tolerance && point.y() >= box.min.y() - tolerance &&
         point.x() <= box.max.x() + tolerance && point.y() <= box.max.y() + tolerance;
}

// Parses JSON text with two checks nlohmann does not make: nesting deeper than
// kDeepestNesting, and a key given twice in one object (nlohmann keeps the later value
// without a word). Those are InputErrors naming `key_prefix` + the path inside the text;
// invalid JSON throws nlohmann::json::exception for the caller to word.
nlohmann::json parse_json(const std::string& text, const std::string& source, const std::string& key_prefix) {
  struct Level {
    bool is_object = false;
    std::set<std::string> keys;  // objects: keys seen so far
    std::string key;             // objects: the current key
    long index = -1;             // arrays: the current element
  };
  std::vector<Level> levels;
  const auto path_of = [&]() {
    std::string path = key_prefix;
    for (const auto& level : levels) {
      if (!level.is_object) {
        path += "[" + std::to_string(level.index) + "]";
      } else if (!level.key.empty()) {
        path += (path.empty() ? "" : ".") + level.key;
      }
    }
    return path;
  };
  using Event = nlohmann::json::parse_event_t;
  const auto check = [&](int depth, Event event, nlohmann::json& parsed) {
    const bool starts = event == Event::object_start || event == Event::array_start;
    if ((starts || event == Event::value) && !levels.empty() && !levels.back().is_object) ++levels.back().index;
    if (starts) {
      if (depth >= kDeepestNesting) {
        std::string path = path_of();  // "description[0][0]...[0]" is named "description"
        while (!path.empty() && path.back() == ']') path.erase(path.rfind('['));
        throw_input_error(source, path,
                          "got values nested deeper than " + std::to_string(kDeepestNesting) +
                              " levels, expected at most the 5 of a scene");
      }
      levels.push_back({event == Event::object_start, {}, {}, -1});
    } else if (event == Event::object_end || event == Event::array_end) {
      levels.pop_back();
    } else if (event == Event::key) {
      const std::string& key = parsed.get_ref<const std::string&>();
      levels.back().key = key;
      if (!levels.back().keys.insert(key).second) {
        throw_input_error(source, path_of(), "given twice in one object, expected each key once");
      }
    }
    return true;
  };
  return nlohmann::json::parse(text, check);
}

const nlohmann::json& block_or_null(const nlohmann::json& document, const std::string& key) {
  static const nlohmann::json null_value;  // immutable
  return document.contains(key) ? document.at(key) : null_value;
}

std::vector<WallTreatmentChoice> resolve_wall_treatments(const MethodInfo& method, const nlohmann::json& block,
                                                         const WallTreatmentRegistry& registry,
                                                         const std::string& source, const std::string& path) {
  if (!block.is_null() && !block.is_object()) {
    throw_input_error(source, path, "got " + describe_json(block) + ", expected an object of wall treatments");
  }
  std::vector<WallTreatmentChoice> choices;
  // A boundary model the scene names and enables replaces the method's default one.
  bool names_boundary = false;
  if (block.is_object()) {
    for (const auto& [name, settings] : block.items()) {
      const WallTreatmentInfo* info = registry.find(name);
      const bool off = settings.is_object() && settings.contains("enabled") && settings.at("enabled") == false;
      if (info != nullptr && info->role == WallTreatmentRole::Boundary && !off) names_boundary = true;
    }
  }
  // Treatments the scene names.
  if (block.is_object()) {
    for (const auto& [name, settings] : block.items()) {
      const WallTreatmentInfo* info = registry.find(name);
      if (info == nullptr) {
        std::vector<std::string> known;
        for (const auto* entry : registry.all()) known.push_back(entry->name);
        throw_input_error(source, path + "." + name, "unknown wall treatment (expected one of: " + join(known) + ")");
      }
      if (!settings.is_object()) {
        throw_input_error(source, path + "." + name, "got " + describe_json(settings) + ", expected an object");
      }
    }
  }
  for (const auto* info : registry.all()) {
    const bool named = block.is_object() && block.contains(info->name);
    bool default_on = false;
    for (const auto& name : method.default_wall_treatments) default_on = default_on || name == info->name;
    if (info->role == WallTreatmentRole::Boundary && names_boundary && !named) default_on = false;
    auto specs = info->parameters;
    specs.push_back(boolean_parameter("enabled", named || default_on, "switch the treatment on or off"));
    const std::string key = path + "." + info->name;
    WallTreatmentChoice choice;
    choice.info = info;
    choice.parameters = resolve_parameters(specs, named ? block.at(info->name) : nlohmann::json(), source, key);
    choice.enabled = choice.parameters.boolean("enabled");
    if (choice.enabled) {
      const std::string gap = wall_treatment_support_gap(*info, method);
      if (!gap.empty()) {
        throw_input_error(
            source, key,
            "wall treatment '" + info->name + "' does not support method '" + method.name + "' (" + gap + ")");
      }
    }
    if (named || default_on) choices.push_back(std::move(choice));
  }
  std::vector<std::string> boundaries;
  for (const auto& choice : choices) {
    if (choice.enabled && choice.info->role == WallTreatmentRole::Boundary) boundaries.push_back(choice.info->name);
  }
  // A method without a default boundary model (it reads the wall particles as it likes, e.g. a
  // test method) may run without one; every other needs exactly one.
  bool method_has_boundary_default = false;
  for (const auto& name : method.default_wall_treatments) {
    const WallTreatmentInfo* info = registry.find(name);
    method_has_boundary_default = method_has_boundary_default || (info && info->role == WallTreatmentRole::Boundary);
  }
  if (boundaries.size() > 1 || (boundaries.empty() && method_has_boundary_default)) {
    std::vector<std::string> supported;
    for (const auto* info : registry.all()) {
      if (info->role == WallTreatmentRole::Boundary && wall_treatment_supports(*info, method)) {
        supported.push_back(info->name);
      }
    }
    throw_input_error(source, path,
                      "got " + std::to_string(boundaries.size()) + " boundary models" +
                          (boundaries.empty() ? std::string() : " (" + join(boundaries) + ")") +
                          ", expected exactly one of: " + join(supported));
  }
  return choices;
}

}  // namespace

std::vector<SceneBlockSpec> shared_scene_keys() {
  return {{"", top_level_keys()},
          {"domain", domain_keys()},
          {"walls", wall_keys()},
          {"walls.obstacles[]", obstacle_keys()},
          {"walls.obstacles[].motion", motion_keys()},
          {"walls.obstacles[].circle", circle_keys()},
          {"walls.obstacles[].body", body_keys()},
          {"contact", contact_keys()},
          {"fluid_blocks[]", fluid_block_keys()},
          {"physics", physics_keys()},
          {"time", time_keys()},
          {"output", output_keys()},
          {"run", run_keys()},
          {"diagnostics", diagnostics_keys()},
          {"diagnostics.pressure_sensors[]", pressure_sensor_keys()},
          {"stability", stability_keys()},
          {"validation", validation_keys()},
          {"validation.pressure_records[]", pressure_record_keys()}};
}

bool TankWalls::any_moving() const {
  for (std::size_t k = 0; k < obstacles.size(); ++k) {
    if (moving(k)) return true;
  }
  return false;
}

const MethodConfig& Scene::method_config(const std::string& name) const {
  auto found = methods.find(name);
  if (found == methods.end()) throw_input_error(source, "method", "unknown method '" + name + "'");
  return found->second;
}

void apply_override(nlohmann::json& document, const std::string& assignment, const std::string& source) {
  const auto equals = assignment.find('=');
  if (equals == std::string::npos || equals == 0) {
    throw_input_error("--set", assignment, "expected key=value, e.g. time.end_time=0.5");
  }
  try {
    (void)nlohmann::json(assignment).dump();  // the scene is stored in run.json: it must be UTF-8
  } catch (const nlohmann::json::type_error&) {
    throw_input_error("--set", describe_json(assignment), "expected UTF-8 text");
  }
  const bool only_if_absent = assignment[equals - 1] == '?';  // "key?=value": a default
  const std::string key = assignment.substr(0, only_if_absent ? equals - 1 : equals);
  if (key.empty()) throw_input_error("--set", assignment, "expected key=value, e.g. time.end_time=0.5");
  const std::string text = assignment.substr(equals + 1);
  nlohmann::json value;
  try {
    value = parse_json(text, "--set", key);
  } catch (const nlohmann::json::exception&) {
    value = text;  // a bare word is a string
  }

  nlohmann::json* node = &document;
  std::stringstream parts(key);
  std::string part;
  std::vector<std::string> path;
  while (std::getline(parts, part, '.')) path.push_back(part);
  for (std::size_t k = 0; k < path.size(); ++k) {
    const std::string& name = path[k];
    if (name.empty()) throw_input_error("--set", key, "empty component in the key");
    const bool last = k + 1 == path.size();
    if (node->is_array()) {
      char* end = nullptr;
      const long index = std::strtol(name.c_str(), &end, 10);
      if (*end != '\0' || index < 0 || static_cast<std::size_t>(index) >= node->size()) {
        throw_input_error(source, key, "'" + name + "' is not an index of an array of " + std::to_string(node->size()));
      }
      node = &(*node)[static_cast<std::size_t>(index)];
    } else {
      if (node->is_null()) *node = nlohmann::json::object();
      if (!node->is_object()) throw_input_error(source, key, "'" + name + "' is inside a value that is not an object");
      node = &(*node)[name];
    }
    if (last && !(only_if_absent && !node->is_null())) *node = value;
  }
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides, const MethodRegistry& methods,
                 const WallTreatmentRegistry& walls) {
  std::error_code ignored;
  if (std::filesystem::is_directory(path, ignored)) throw_input_error(path, "", "is a folder, expected a scene file");
  std::ifstream file(path, std::ios::binary);
  if (!file) throw_input_error(path, "", std::string("cannot open the scene file (") + std::strerror(errno) + ")");
  std::stringstream text;
  text << file.rdbuf();
  if (file.bad()) throw_input_error(path, "", std::string("cannot read the scene file (") + std::strerror(errno) + ")");
  return load_scene_text(text.str(), path, overrides, methods, walls);
}

Scene load_scene_text(const std::string& text, const std::string& source, const std::vector<std::string>& overrides,
                      const MethodRegistry& methods, const WallTreatmentRegistry& walls) {
  nlohmann::json document;
  try {
    document = parse_json(text, source, "");
  } catch (const nlohmann::json::exception& error) {
    // "[json.exception.parse_error.101] parse error at line 3, column 5: ...", or
    // "[json.exception.out_of_range.406] number overflow parsing '1e309'": keep what follows the id.
    const std::string message = error.what();
    const auto id_end = message.find("] ");
    const std::string reason = id_end == std::string::npos ? message : message.substr(id_end + 2);
    throw_input_error(source, "", "not valid JSON: " + reason);
  }
  if (!document.is_object()) {
    throw_input_error(source, "", "got " + describe_json(document) + ", expected a JSON object at the top level");
  }
  for (const auto& assignment : overrides) apply_override(document, assignment, source);
  return parse_scene(std::move(document), source, methods, walls);
}

namespace {

// The steps of parse_scene, in the order it takes them: read each block into the scene
// (resolve_parameters checks every key), then check the geometry, the time and the method
// blocks against each other. Each throws InputError naming the key.

// The top-level keys; every block that is given must be an object (null is not "the
// defaults"; fluid_blocks is an array, read below).
void read_top_level(const nlohmann::json& document, const std::string& source, Scene& scene) {
  const std::set<std::string> blocks = {"domain", "walls",       "fluid_blocks", "physics",    "time",    "output",
                                        "run",    "diagnostics", "stability",    "validation", "methods", "contact"};
  const auto top = resolve_parameters(top_level_keys(), document, source, "", blocks);
  // A block that is given must be an object: null is not "the defaults" (fluid_blocks: below).
  for (const auto& name : blocks) {
    if (name != "fluid_blocks" && document.contains(name) && !document.at(name).is_object()) {
      throw_input_error(source, name, "got " + describe_json(document.at(name)) + ", expected an object");
    }
  }
  scene.description = top.string("description");
  scene.particle_spacing = top.number("particle_spacing");
  scene.method = top.string("method");
}

void read_domain(const nlohmann::json& document, const std::string& source, Scene& scene) {
  if (!document.contains("domain")) throw_input_error(source, "domain", "missing; expected an object with min and max");
  const auto domain = resolve_parameters(domain_keys(), document.at("domain"), source, "domain");
  scene.domain.min = domain.vector2("min");
  scene.domain.max = domain.vector2("max");
}

// The keys each law reads besides law and start_time; any other key given is an error (an
// option that is parsed but ignored).
std::vector<std::string> motion_law_keys(const std::string& law) {
  if (law == "constant_velocity") return {"velocity"};
  if (law == "constant_acceleration") return {"acceleration", "max_speed"};
  if (law == "sinusoid") return {"amplitude", "period", "phase"};
  return {"file"};  // table
}

// walls.obstacles[k].motion: the law, its keys checked against the law, a table read from its file.
WallMotion read_motion(const nlohmann::json& block, const std::string& source, const std::string& path) {
  const auto values = resolve_parameters(motion_keys(), block, source, path);
  const std::string& law = values.string("law");
  const std::vector<std::string> own = motion_law_keys(law);
  for (const auto& [key, value] : block.items()) {
    if (key == "law" || key == "start_time" || std::find(own.begin(), own.end(), key) != own.end()) continue;
    throw_input_error(source, path + "." + key, "is not a key of law " + law + " (expected: " + join(own) + ")");
  }
  const std::string required = law == "sinusoid" ? "period" : law == "table" ? "file" : "";
  if (!required.empty() && !block.contains(required)) {
    throw_input_error(source, path + "." + required, "missing; law " + law + " needs it");
  }
  WallMotion motion;
  motion.start_time = values.number("start_time");
  if (law == "constant_velocity") {
    motion.law = MotionLaw::ConstantVelocity;
    motion.velocity = values.vector2("velocity");
  } else if (law == "constant_acceleration") {
    motion.law = MotionLaw::ConstantAcceleration;
    motion.acceleration = values.vector2("acceleration");
    motion.max_speed = values.number("max_speed");
  } else if (law == "sinusoid") {
    motion.law = MotionLaw::Sinusoid;
    motion.amplitude = values.vector2("amplitude");
    motion.period = values.number("period");
    motion.phase = values.number("phase");
  } else {
    motion.law = MotionLaw::Table;
    const std::filesystem::path file = std::filesystem::path(source).parent_path() / values.string("file");
    read_motion_table(file.string(), source, path + ".file", motion);
  }
  return motion;
}

// walls.obstacles[k].body: a rigid body's density and initial velocities.
BodySpec read_body(const nlohmann::json& block, const std::string& source, const std::string& path) {
  const auto values = resolve_parameters(body_keys(), block, source, path);
  BodySpec body;
  body.density = values.number("density");
  body.velocity = values.vector2("velocity");
  body.angular_velocity = values.number("angular_velocity");
  return body;
}

// An obstacle's "motion" (a prescribed law) or "body" (a rigid body): at most one of them.
void read_obstacle_dynamics(const nlohmann::json& block, const std::string& source, const std::string& path,
                            TankWalls& walls) {
  const bool motion = block.contains("motion"), body = block.contains("body");
  if (motion && body) {
    throw_input_error(source, path + ".body",
                      "is not allowed beside " + path +
                          ".motion (a body moves under its loads, a motion law prescribes; expected one of them)");
  }
  walls.motions.push_back(motion ? read_motion(block.at("motion"), source, path + ".motion") : WallMotion{});
  walls.bodies.push_back(body ? read_body(block.at("body"), source, path + ".body") : BodySpec{});
}

// walls.obstacles[k] = {"polygon": [[x, y], ...]}: the wall surface as a polygon
// (core/walls/wall_polygon.hpp), either orientation, stored counter-clockwise; its shape is
// checked here, its place in the domain by check_obstacles. Beside it only a motion or a body:
// a box's min/max would be ignored.
void read_polygon_obstacle(const nlohmann::json& block, const std::string& source, const std::string& path,
                           TankWalls& walls) {
  for (const auto& [key, value] : block.items()) {
    if (key == "polygon" || key == "motion" || key == "body") continue;
    const bool known = key == "min" || key == "max";
    throw_input_error(source, path + "." + key,
                      known ? "is not allowed beside " + path + ".polygon (a polygon obstacle has no min/max)"
                            : "unknown key of a polygon obstacle (expected: polygon, motion, body)");
  }
  const std::string key = path + ".polygon";
  const nlohmann::json& vertices = block.at("polygon");
  const std::string expected = ", expected an array of at least 3 [x, y] points in m";
  if (!vertices.is_array()) throw_input_error(source, key, "got " + describe_json(vertices) + expected);
  Polygon polygon;
  for (const auto& vertex : vertices) {
    const bool pair = vertex.is_array() && vertex.size() == 2 && vertex[0].is_number() && vertex[1].is_number();
    if (!pair) throw_input_error(source, key, "got vertex " + describe_json(vertex) + expected);
    polygon.emplace_back(vertex[0].get<double>(), vertex[1].get<double>());
    if (!std::isfinite(polygon.back().x()) || !std::isfinite(polygon.back().y())) {
      throw_input_error(source, key, "got vertex " + describe_json(vertex) + expected);
    }
  }
  Vec2 low = polygon.empty() ? Vec2::Zero() : polygon.front(), high = low;
  for (const Vec2& x : polygon) low = low.cwiseMin(x), high = high.cwiseMax(x);
  // Vertices closer than 1e-9 of the polygon's size are one vertex (a typo, not a design).
  const std::string defect = polygon_defect(polygon, 1e-9 * std::max(1e-12, (high - low).norm()));
  if (!defect.empty()) {
    throw_input_error(source, key, "got " + describe_json(vertices) + ", expected a simple polygon (" + defect + ")");
  }
  walls.obstacles.push_back({low, high});  // its bounding box: not the solid (TankWalls::polygons)
  walls.polygons.push_back(counter_clockwise(polygon));
  walls.circles.emplace_back();
  read_obstacle_dynamics(block, source, path, walls);
}

// walls.obstacles[k] = {"circle": {"centre", "radius"}}: a circle; its wall particles are those
// of its inscribed polygon (circle_sides), its place in the domain is checked by check_obstacles.
void read_circle_obstacle(const nlohmann::json& block, const std::string& source, const std::string& path, double l0,
                          TankWalls& walls) {
  for (const auto& [key, value] : block.items()) {
    if (key == "circle" || key == "motion" || key == "body") continue;
    throw_input_error(source, path + "." + key, "unknown key of a circle obstacle (expected: circle, motion, body)");
  }
  const auto values = resolve_parameters(circle_keys(), block.at("circle"), source, path + ".circle");
  const Circle circle{values.vector2("centre"), values.number("radius")};
  walls.obstacles.push_back(
      {circle.centre - Vec2(circle.radius, circle.radius), circle.centre + Vec2(circle.radius, circle.radius)});
  walls.polygons.push_back(circle_polygon(circle.centre, circle.radius, circle_sides(circle.radius, l0)));
  walls.circles.push_back(circle);
  read_obstacle_dynamics(block, source, path, walls);
}

// walls: the tank's layers and sides, and the obstacles.
void read_walls(const nlohmann::json& document, const std::string& source, Scene& scene) {
  const auto& walls_json = block_or_null(document, "walls");
  const auto wall_block = resolve_parameters(wall_keys(), walls_json, source, "walls", {"obstacles"});
  if (walls_json.is_object() && walls_json.contains("obstacles")) {
    const auto& obstacles = walls_json.at("obstacles");
    if (!obstacles.is_array()) {
      throw_input_error(source, "walls.obstacles",
                        "got " + describe_json(obstacles) + ", expected an array of {min, max} boxes");
    }
    for (std::size_t k = 0; k < obstacles.size(); ++k) {
      const std::string path = "walls.obstacles[" + std::to_string(k) + "]";
      const bool polygon = obstacles[k].is_object() && obstacles[k].contains("polygon");
      if (polygon) {
        read_polygon_obstacle(obstacles[k], source, path, scene.walls);
        continue;
      }
      if (obstacles[k].is_object() && obstacles[k].contains("circle")) {
        read_circle_obstacle(obstacles[k], source, path, scene.particle_spacing, scene.walls);
        continue;
      }
      const auto box = resolve_parameters(obstacle_keys(), obstacles[k], source, path, {"motion", "body"});
      scene.walls.obstacles.push_back({box.vector2("min"), box.vector2("max")});
      scene.walls.polygons.emplace_back();
      scene.walls.circles.emplace_back();
      read_obstacle_dynamics(obstacles[k], source, path, scene.walls);
    }
  }
  scene.walls.layers = static_cast<int>(wall_block.integer("layers"));
  scene.walls.bottom = scene.walls.left = scene.walls.right = scene.walls.top = false;
  for (const auto& side : wall_block.string_list("sides")) {
    if (side == "bottom") scene.walls.bottom = true;
    if (side == "left") scene.walls.left = true;
    if (side == "right") scene.walls.right = true;
    if (side == "top") scene.walls.top = true;
  }
}

void read_fluid_blocks(const nlohmann::json& document, const std::string& source, Scene& scene) {
  if (!document.contains("fluid_blocks")) {
    throw_input_error(source, "fluid_blocks", "missing; expected an array of {min, max} blocks");
  }
  const auto& fluid = document.at("fluid_blocks");
  // No fluid is a scene of bodies alone (a disc on a slope): it needs a rigid body to move.
  bool has_body = false;
  for (std::size_t k = 0; k < scene.walls.obstacles.size(); ++k) has_body = has_body || scene.walls.is_body(k);
  if (!fluid.is_array() || (fluid.empty() && !has_body)) {
    throw_input_error(
        source, "fluid_blocks",
        "got " + describe_json(fluid) +
            ", expected a non-empty array of blocks (or [] in a scene with a rigid body: walls.obstacles[k].body)");
  }
  for (std::size_t k = 0; k < fluid.size(); ++k) {
    const std::string path = "fluid_blocks[" + std::to_string(k) + "]";
    const auto block = resolve_parameters(fluid_block_keys(), fluid[k], source, path);
    scene.fluid_blocks.push_back({{block.vector2("min"), block.vector2("max")}, block.vector2("velocity")});
  }
}

void read_physics_and_time(const nlohmann::json& document, const std::string& source, Scene& scene) {
  const auto physics = resolve_parameters(physics_keys(), block_or_null(document, "physics"), source, "physics");
  scene.physics = {physics.number("density"), physics.number("kinematic_viscosity"), physics.vector2("gravity")};

  const auto time = resolve_parameters(time_keys(), block_or_null(document, "time"), source, "time");
  scene.time = {time.number("time_step"), time.number("end_time")};
}

void read_output(const nlohmann::json& document, const std::string& source, Scene& scene) {
  const auto output = resolve_parameters(output_keys(), block_or_null(document, "output"), source, "output");
  scene.output.directory = output.string("directory");
  scene.output.frame_every_steps = output.integer("frame_every_steps");
  scene.output.series_every_steps = output.integer("series_every_steps");
  scene.output.frame_interval = output.number("frame_interval");
  scene.output.series_interval = output.number("series_interval");
  scene.output.checkpoint_every_steps = output.integer("checkpoint_every_steps");
  scene.output.csv = scene.output.vtk = scene.output.vtu = false;
  for (const auto& format : output.string_list("formats")) {
    if (format == "csv") scene.output.csv = true;
    if (format == "vtk") scene.output.vtk = true;
    if (format == "vtu") scene.output.vtu = true;
  }
}

void read_run(const nlohmann::json& document, const std::string& source, Scene& scene) {
  const auto run = resolve_parameters(run_keys(), block_or_null(document, "run"), source, "run");
  scene.run.sort_period = run.integer("sort_period");
}

// diagnostics, with its pressure sensors (names of letters, digits and _, each once).
void read_diagnostics(const nlohmann::json& document, const std::string& source, Scene& scene) {
  const auto& diagnostics_block = block_or_null(document, "diagnostics");
  const auto diagnostics =
      resolve_parameters(diagnostics_keys(), diagnostics_block, source, "diagnostics", {"pressure_sensors"});
  scene.diagnostics.front_link_distance = diagnostics.number("front_link_distance");
  scene.diagnostics.height_probe_width = diagnostics.number("height_probe_width");
  scene.diagnostics.density_support = diagnostics.number("density_support");
  if (diagnostics_block.is_object() && diagnostics_block.contains("pressure_sensors")) {
    const auto& sensors = diagnostics_block.at("pressure_sensors");
    if (!sensors.is_array()) {
      throw_input_error(source, "diagnostics.pressure_sensors",
                        "got " + describe_json(sensors) + ", expected an array");
    }
    std::set<std::string> names;
    for (std::size_t k = 0; k < sensors.size(); ++k) {
      const std::string path = "diagnostics.pressure_sensors[" + std::to_string(k) + "]";
      const auto sensor = resolve_parameters(pressure_sensor_keys(), sensors[k], source, path);
      const std::string& name = sensor.string("name");
      bool valid = !name.empty();
      for (char c : name) valid = valid && (std::isalnum(static_cast<unsigned char>(c)) || c == '_');
      if (!valid) {
        throw_input_error(source, path + ".name", "got " + describe_json(name) + ", expected letters, digits and _");
      }
      if (!names.insert(name).second) {
        throw_input_error(source, path + ".name",
                          "got " + describe_json(name) + ", expected a name no other sensor has");
      }
      const bool has_diameter = sensors[k].is_object() && sensors[k].contains("diameter");
      scene.diagnostics.pressure_sensors.push_back(
          {name, sensor.vector2("position"), has_diameter ? sensor.number("diameter") : scene.particle_spacing});
    }
  }
}

// The domain: a positive, finite extent of at most 5e7 lattice points, at least four
// spacings wide and high.
void check_domain_extent(const std::string& source, const Scene& scene) {
  const double l0 = scene.particle_spacing;
  const Vec2 extent = scene.domain.max - scene.domain.min;
  if (!(extent.x() > 0.0 && extent.y() > 0.0)) {
    throw_input_error(source, "domain.max",
                      "got " + describe_point(scene.domain.max) +
                          ", expected a point above and to the right of domain.min " +
                          describe_point(scene.domain.min));
  }
  if (!std::isfinite(extent.x()) || !std::isfinite(extent.y())) {
    throw_input_error(source, "domain",
                      "got min " + describe_point(scene.domain.min) + " and max " + describe_point(scene.domain.max) +
                          ", expected a finite width and height");
  }
  if (extent.x() / l0 * extent.y() / l0 > kLargestLatticePoints) {
    throw_input_error(source, "particle_spacing",
                      "got " + describe_json(l0) + ", expected a spacing that gives the domain (" +
                          describe_json(extent.x()) + " x " + describe_json(extent.y()) +
                          " m) at most 5e7 lattice points");
  }
  if (extent.x() < 4.0 * l0 || extent.y() < 4.0 * l0) {
    throw_input_error(source, "particle_spacing",
                      "got " + describe_json(l0) + ", expected at most a quarter of the domain's width and height (" +
                          describe_json(extent.x()) + " x " + describe_json(extent.y()) + " m)");
  }
}

std::string describe_domain(const Scene& scene) {
  return describe_point(scene.domain.min) + " to " + describe_point(scene.domain.max);
}

void check_fluid_blocks(const std::string& source, const Scene& scene) {
  const double l0 = scene.particle_spacing;
  const std::string domain_text = describe_domain(scene);
  for (std::size_t k = 0; k < scene.fluid_blocks.size(); ++k) {
    const Box& box = scene.fluid_blocks[k].region;
    const std::string path = "fluid_blocks[" + std::to_string(k) + "]";
    if (!(box.max.x() > box.min.x() && box.max.y() > box.min.y())) {
      throw_input_error(source, path + ".max",
                        "got " + describe_point(box.max) + ", expected a point above and to the right of " + path +
                            ".min " + describe_point(box.min));
    }
    const double tolerance = 1e-9 * l0;
    for (const auto& [corner, point] : {std::pair<const char*, Vec2>{".min", box.min}, {".max", box.max}}) {
      if (!inside_box(point, scene.domain, tolerance)) {
        throw_input_error(source, path + corner,
                          "got " + describe_point(point) + ", expected a point inside the domain " + domain_text);
      }
    }
  }
}

// A polygon obstacle lies inside the domain (its vertices, hence its edges: the domain is convex);
// a circle with all of its disc.
void check_polygon_in_domain(const std::string& source, const Scene& scene, std::size_t k) {
  if (scene.walls.is_circle(k)) {
    const Circle& circle = scene.walls.circles[k];
    const Vec2 reach(circle.radius, circle.radius);
    if (!inside_box(circle.centre - reach, scene.domain, 1e-9 * scene.particle_spacing) ||
        !inside_box(circle.centre + reach, scene.domain, 1e-9 * scene.particle_spacing)) {
      throw_input_error(source, "walls.obstacles[" + std::to_string(k) + "].circle",
                        "got centre " + describe_point(circle.centre) + " radius " + describe_json(circle.radius) +
                            " m, expected a circle inside the domain " + describe_domain(scene));
    }
    return;
  }
  for (const Vec2& vertex : scene.walls.polygons[k]) {
    if (!inside_box(vertex, scene.domain, 1e-9 * scene.particle_spacing)) {
      throw_input_error(
          source, "walls.obstacles[" + std::to_string(k) + "].polygon",
          "got vertex " + describe_point(vertex) + ", expected a polygon inside the domain " + describe_domain(scene));
    }
  }
}

void check_obstacles(const std::string& source, const Scene& scene) {
  const double l0 = scene.particle_spacing;
  const std::string domain_text = describe_domain(scene);
  // Obstacles: boxes with lattice-point corners inside the domain (their wall particles sit on
  // the lattice, their surfaces l0/2 outside the box: core/walls/wall_geometry.hpp).
  for (std::size_t k = 0; k < scene.walls.obstacles.size(); ++k) {
    const Box& box = scene.walls.obstacles[k];
    const std::string path = "walls.obstacles[" + std::to_string(k) + "]";
    if (scene.walls.is_polygon(k)) {
      check_polygon_in_domain(source, scene, k);
      continue;
    }
    if (!(box.max.x() > box.min.x() && box.max.y() > box.min.y())) {
      throw_input_error(source, path + ".max",
                        "got " + describe_point(box.max) + ", expected a point above and to the right of " + path +
                            ".min " + describe_point(box.min));
    }
    for (const auto& [corner, point] : {std::pair<const char*, Vec2>{".min", box.min}, {".max", box.max}}) {
      if (!inside_box(point, scene.domain, 1e-9 * l0)) {
        throw_input_error(source, path + corner,
                          "got " + describe_point(point) + ", expected a point inside the domain " + domain_text);
      }
      const Vec2 steps = (point - scene.domain.min) / l0;
      if (std::fabs(steps.x() - std::round(steps.x())) > 1e-6 || std::fabs(steps.y() - std::round(steps.y())) > 1e-6) {
        throw_input_error(source, path + corner,
                          "got " + describe_point(point) +
                              ", expected a lattice point (domain.min + whole multiples of "
                              "particle_spacing " +
                              describe_json(l0) + " m)");
      }
    }
  }
}

// A sensor lies on a wall: on a wall surface (core/walls/wall_geometry.hpp) or behind it up
// to the wall's first particle line (the domain boundary for a tank side, the box for an
// obstacle), l0/2 further, within 1e-3 l0 (decimal positions such as 0.9875 m); its face is
// centred on the position projected onto that surface, which must lie on the surface's
// segment. A
// position on the first particle line is thus valid at every particle_spacing (a scene run
// with --set particle_spacing=...); and it must be inside the domain.
constexpr double kSensorSurfaceTolerance = 1e-3;  // l0

void check_pressure_sensor(const std::string& source, const Scene& scene, const WallGeometry& geometry, std::size_t k) {
  const PressureSensor& sensor = scene.diagnostics.pressure_sensors[k];
  const std::string key = "diagnostics.pressure_sensors[" + std::to_string(k) + "]";
  if (!inside_box(sensor.position, scene.domain, 0.0)) {
    throw_input_error(
        source, key + ".position",
        "got " + describe_point(sensor.position) + ", expected a point inside the domain " + describe_domain(scene));
  }
  const double tolerance = kSensorSurfaceTolerance * scene.particle_spacing;
  std::size_t nearest = 0;
  const double distance = geometry.segments().empty() ? std::numeric_limits<double>::infinity()
                                                      : geometry.distance(sensor.position, &nearest);
  const bool near = distance <= geometry.surface_offset() + tolerance;
  const WallSegment* segment = near ? &geometry.segments()[nearest] : nullptr;
  if (segment == nullptr || segment->normal.dot(sensor.position - segment->a) > tolerance) {
    throw_input_error(source, key + ".position",
                      "got " + describe_point(sensor.position) +
                          ", expected a point on a wall (walls.sides, walls.obstacles): on its surface or behind it "
                          "up to its first particle line, particle_spacing/2 further");
  }
  // The position projected onto the surface must lie on the surface's segment (not past a
  // corner or an open side); a face longer than the surface around it is cut there
  // (sensor_faces, core/run/pressure_sensors.cpp).
  const Vec2 tangent = (segment->b - segment->a).normalized();
  const double along = tangent.dot(sensor.position - segment->a);
  if (along < -tolerance || along > (segment->b - segment->a).norm() + tolerance) {
    throw_input_error(source, key + ".position",
                      "got " + describe_point(sensor.position) + ", expected a point on a wall surface, from " +
                          describe_point(segment->a) + " to " + describe_point(segment->b) + ", or behind it");
  }
}

void check_pressure_sensors(const std::string& source, const Scene& scene) {
  if (scene.diagnostics.pressure_sensors.empty()) return;
  const WallGeometry geometry(scene);
  for (std::size_t k = 0; k < scene.diagnostics.pressure_sensors.size(); ++k) {
    check_pressure_sensor(source, scene, geometry, k);
  }
}

// A pressure record: a header line and at least two rows of two finite numbers (T,
// p / (rho g H)), '#' lines skipped; a missing file or a bad row is an error naming the key.
void check_pressure_record_file(const std::string& file, const std::string& source, const std::string& key) {
  std::ifstream in(file);
  if (!in) throw_input_error(source, key, "cannot read " + describe_json(file) + ", expected a CSV of T,p");
  std::string line;
  bool header = false;
  int rows = 0;
  for (int number = 1; std::getline(in, line); ++number) {
    if (line.empty() || line[0] == '#') continue;
    if (!header) {
      header = true;
      continue;
    }
    std::istringstream fields(line);
    double t = 0.0;
    double p = 0.0;
    char comma = 0;
    if (!(fields >> t >> comma >> p) || comma != ',' || !std::isfinite(t) || !std::isfinite(p)) {
      throw_input_error(
          source, key,
          file + " line " + std::to_string(number) + ": got " + describe_json(line) + ", expected two numbers T,p");
    }
    ++rows;
  }
  if (rows < 2) throw_input_error(source, key, file + ": expected a header line and at least two rows T,p");
}

// validation: the experiment the sensors compare with; each record names a sensor of
// diagnostics.pressure_sensors and a readable file (relative to the scene file).
void read_validation(const nlohmann::json& document, const std::string& source, Scene& scene) {
  if (!document.contains("validation")) return;
  const auto& block = document.at("validation");
  const auto values = resolve_parameters(validation_keys(), block, source, "validation", {"pressure_records"});
  scene.validation.length_scale = values.number("length_scale");
  scene.validation.impact_threshold = values.number("impact_threshold");
  scene.validation.quasi_static = values.vector2("quasi_static");
  if (!(scene.validation.quasi_static.y() > scene.validation.quasi_static.x())) {
    throw_input_error(source, "validation.quasi_static",
                      "got " + describe_point(scene.validation.quasi_static) + ", expected [T0, T1] with T1 > T0");
  }
  if (!block.contains("pressure_records")) return;
  const auto& records = block.at("pressure_records");
  if (!records.is_array()) {
    throw_input_error(source, "validation.pressure_records", "got " + describe_json(records) + ", expected an array");
  }
  for (std::size_t k = 0; k < records.size(); ++k) {
    const std::string path = "validation.pressure_records[" + std::to_string(k) + "]";
    const auto record = resolve_parameters(pressure_record_keys(), records[k], source, path);
    const std::string& sensor = record.string("sensor");
    std::vector<std::string> names;
    for (const auto& s : scene.diagnostics.pressure_sensors) names.push_back(s.name);
    if (std::find(names.begin(), names.end(), sensor) == names.end()) {
      throw_input_error(source, path + ".sensor",
                        "got " + describe_json(sensor) + ", expected the name of a diagnostics.pressure_sensors entry" +
                            (names.empty() ? std::string(" (the scene has none)") : " (" + join(names) + ")"));
    }
    const std::filesystem::path file = std::filesystem::path(source).parent_path() / record.string("file");
    check_pressure_record_file(file.string(), source, path + ".file");
    scene.validation.pressure_records.push_back({sensor, std::filesystem::absolute(file).lexically_normal().string()});
  }
}

// The time step against the end time and the output intervals; an output folder.
void check_time_and_output(const std::string& source, const Scene& scene) {
  const double dt = scene.time.time_step;
  if (dt > scene.time.end_time && scene.time.end_time > 0.0) {
    throw_input_error(
        source, "time.time_step",
        "got " + describe_json(dt) + ", expected at most time.end_time (" + describe_json(scene.time.end_time) + " s)");
  }
  if (scene.time.end_time / dt > kMostTimeSteps) {
    throw_input_error(source, "time.end_time",
                      "got " + describe_json(scene.time.end_time) +
                          ", expected at most 1e10 steps of time.time_step (" + describe_json(kMostTimeSteps * dt) +
                          " s)");
  }
  const std::pair<const char*, double> intervals[] = {{"output.frame_interval", scene.output.frame_interval},
                                                      {"output.series_interval", scene.output.series_interval}};
  for (const auto& [key, interval] : intervals) {
    if (interval > 0.0 && interval < kShortestIntervalInSteps * dt) {
      throw_input_error(source, key,
                        "got " + describe_json(interval) + ", expected 0 (off) or at least time.time_step / 1000 (" +
                            describe_json(kShortestIntervalInSteps * dt) + " s)");
    }
  }
  if (scene.output.directory.empty()) {
    throw_input_error(source, "output.directory", "got \"\", expected a folder name");
  }
}

// Method blocks: every block must belong to a registered method and is validated even
// when another method runs, so a typo never waits for the day that block is used.
const nlohmann::json& checked_method_blocks(const nlohmann::json& document, const std::string& source,
                                            const MethodRegistry& methods) {
  const auto& method_blocks = block_or_null(document, "methods");
  if (!method_blocks.is_null() && !method_blocks.is_object()) {
    throw_input_error(source, "methods", "got " + describe_json(method_blocks) + ", expected an object");
  }
  if (method_blocks.is_object()) {
    for (const auto& [name, block] : method_blocks.items()) {
      if (methods.find(name) == nullptr) {
        throw_input_error(source, "methods." + name, "unknown method (registered: " + join(methods.names()) + ")");
      }
      if (!block.is_object()) {
        throw_input_error(source, "methods." + name, "got " + describe_json(block) + ", expected an object");
      }
      if (block.contains("wall_treatments") && !block.at("wall_treatments").is_object()) {
        throw_input_error(
            source, "methods." + name + ".wall_treatments",
            "got " + describe_json(block.at("wall_treatments")) + ", expected an object of wall treatments");
      }
    }
  }
  return method_blocks;
}

// Every registered method's parameters and wall treatments, from its block or the defaults.
void read_method_configs(const nlohmann::json& method_blocks, const std::string& source, const MethodRegistry& methods,
                         const WallTreatmentRegistry& walls, Scene& scene) {
  for (const auto* info : methods.all()) {
    const std::string path = "methods." + info->name;
    const nlohmann::json& block = method_blocks.is_object() && method_blocks.contains(info->name)
                                      ? method_blocks.at(info->name)
                                      : nlohmann::json();
    MethodConfig config;
    config.parameters = resolve_parameters(info->parameters, block, source, path, {"wall_treatments"});
    const nlohmann::json& treatments =
        block.is_object() && block.contains("wall_treatments") ? block.at("wall_treatments") : nlohmann::json();
    config.wall_treatments = resolve_wall_treatments(*info, treatments, walls, source, path + ".wall_treatments");
    scene.methods.emplace(info->name, std::move(config));
  }
}

}  // namespace

// contact: the rigid bodies' contact parameters (docs/bodies.md).
void read_contact(const nlohmann::json& document, const std::string& source, Scene& scene) {
  const auto contact = resolve_parameters(contact_keys(), block_or_null(document, "contact"), source, "contact");
  scene.contact.stiffness = contact.number("stiffness");
  scene.contact.damping_ratio = contact.number("damping_ratio");
  scene.contact.friction = contact.number("friction");
  scene.contact.tangential_stiffness = contact.number("tangential_stiffness");
  scene.contact.steps_per_period = static_cast<int>(contact.integer("steps_per_period"));
}

Scene parse_scene(nlohmann::json document, const std::string& source, const MethodRegistry& methods,
                  const WallTreatmentRegistry& walls) {
  if (!document.is_object()) throw_input_error(source, "", "expected a JSON object at the top level");
  Scene scene;
  scene.source = source;
  read_top_level(document, source, scene);
  read_domain(document, source, scene);
  read_walls(document, source, scene);
  read_fluid_blocks(document, source, scene);
  read_physics_and_time(document, source, scene);
  read_output(document, source, scene);
  read_run(document, source, scene);
  read_diagnostics(document, source, scene);
  read_contact(document, source, scene);
  scene.stability = stability_settings(
      resolve_parameters(stability_keys(), block_or_null(document, "stability"), source, "stability"));

  // Geometry that makes sense.
  check_domain_extent(source, scene);
  // Blocks inside the domain cannot reach the wall layers, which lie on its sides and outside.
  check_fluid_blocks(source, scene);
  check_obstacles(source, scene);
  check_pressure_sensors(source, scene);
  read_validation(document, source, scene);  // names the sensors: after them
  check_lattice(scene);                      // the domain a whole number of spacings, a lattice point in every block
  check_time_and_output(source, scene);
  read_method_configs(checked_method_blocks(document, source, methods), source, methods, walls, scene);
  if (methods.find(scene.method) == nullptr) {
    throw_input_error(source, "method",
                      "unknown method '" + scene.method + "' (registered: " + join(methods.names()) + ")");
  }
  scene.document = std::move(document);
  return scene;
}

}  // namespace mps_lab
