#pragma once
// A scene: the shared physics and geometry of a run plus one parameter block per method.
// Every key is documented in docs/scene-format.md. Loading validates everything before a
// run starts: unknown keys, wrong types, out-of-range values and inconsistent geometry are
// InputErrors whose one-line message names the file and the dotted key.
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/base/parameters.hpp"
#include "core/base/types.hpp"
#include "core/run/stability.hpp"
#include "core/walls/wall_motion.hpp"
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {

class MethodRegistry;

struct Box {
  Vec2 min = Vec2::Zero();  // m
  Vec2 max = Vec2::Zero();  // m
};

// A circle obstacle (walls.obstacles[k].circle): its surface, m. Its wall particles are those
// of a regular polygon inscribed in it (circle_polygon, core/bodies/mass_properties.hpp);
// mass properties and contact use the exact circle.
struct Circle {
  Vec2 centre = Vec2::Zero();  // m
  double radius = 0.0;         // m; 0: the obstacle is not a circle
};

// A rigid body (walls.obstacles[k].body, docs/bodies.md): the obstacle moves under gravity, the
// fluid's load and contact. 2-D: density in kg/m^3 over a unit width (1 m), so a body's mass
// is kg per metre of width.
struct BodySpec {
  double density = 0.0;           // kg/m^3; 0: the obstacle is not a body
  Vec2 velocity = Vec2::Zero();   // initial velocity of the centre of mass, m/s
  double angular_velocity = 0.0;  // initial, rad/s, counter-clockwise
  bool free() const { return density > 0.0; }
};

// Walls of the tank: straight walls along the sides of the domain box, each `layers`
// particles thick, the first layer on the domain boundary (spec §4).
struct TankWalls {
  bool bottom = true, left = true, right = true, top = false;
  int layers = 3;
  // Solid boxes inside the tank (walls.obstacles): corners on the lattice; a boundary model
  // of wall particles fills each with `layers` layers from its surface inwards, the others
  // take its four faces as wall segments (core/walls/wall_geometry.hpp).
  std::vector<Box> obstacles;
  // One per obstacle: empty for a box; for a polygon obstacle (walls.obstacles[k].polygon) its
  // vertices counter-clockwise, m, the wall SURFACE (core/walls/wall_polygon.hpp); obstacles[k]
  // is then its bounding box, which no code treats as the solid.
  std::vector<std::vector<Vec2>> polygons;
  bool is_polygon(std::size_t k) const { return k < polygons.size() && !polygons[k].empty(); }
  // One per obstacle (walls.obstacles[k].motion): its prescribed motion, MotionLaw::None when
  // it is fixed (core/walls/wall_motion.hpp).
  std::vector<WallMotion> motions;
  // One per obstacle: radius 0 unless it is a circle (then polygons[k] is its inscribed polygon).
  std::vector<Circle> circles;
  bool is_circle(std::size_t k) const { return k < circles.size() && circles[k].radius > 0.0; }
  // One per obstacle (walls.obstacles[k].body): density 0 unless it is a rigid body.
  std::vector<BodySpec> bodies;
  bool is_body(std::size_t k) const { return k < bodies.size() && bodies[k].free(); }
  // Whether obstacle k moves: a motion law or a rigid body; its wall particles follow it.
  bool moving(std::size_t k) const { return (k < motions.size() && motions[k].moves()) || is_body(k); }
  bool any_moving() const;
};

// The "contact" block: the spring-dashpot contact of rigid bodies with the walls and each other
// (core/bodies/rigid_bodies.hpp; Cundall & Strack 1979, linear spring, dashpot, Coulomb limit).
struct ContactControl {
  double stiffness = 1.0e6;                 // k_n, N/m per m of width (N/m^2)
  double damping_ratio = 0.3;               // zeta of the normal and tangential dashpots
  double friction = 0.5;                    // Coulomb coefficient mu
  double tangential_stiffness = 2.0 / 7.0;  // k_t / k_n
  int steps_per_period = 20;                // body sub-steps per contact period 2 pi sqrt(m_eff / k)
};

struct FluidBlock {
  Box region;                    // particles at (i l0, j l0) strictly inside (spec §4 note)
  Vec2 velocity = Vec2::Zero();  // initial velocity, m/s
};

struct Physics {
  double density = 1000.0;              // rho, kg/m^3
  double kinematic_viscosity = 1.0e-6;  // nu, m^2/s
  Vec2 gravity = Vec2(0.0, -9.81);      // m/s^2
};

struct TimeControl {
  double time_step = 5.0e-4;  // s (initial/maximum step for adaptive methods)
  double end_time = 2.0;      // s
};

struct OutputControl {
  std::string directory = "output";
  long long frame_every_steps = 100;     // CSV/VTK frames (spec §3)
  long long series_every_steps = 10;     // rows of series.csv
  double frame_interval = 0.0;           // s; > 0: also a frame at the first step at or after each multiple
  double series_interval = 0.0;          // s; > 0: also a series row at the first step at or after each multiple
  long long checkpoint_every_steps = 0;  // > 0: checkpoint.bin every N steps (core/io/checkpoint.hpp)
  bool csv = true;                       // output_XXXXXX.csv (spec §10.1)
  bool vtk = true;                       // output_XXXXXX.vtk, VTK legacy ASCII (spec §10.2), and output.vtk.series
  bool vtu = false;                      // output_XXXXXX.vtu, VTK XML appended binary, and output.pvd
};

// The sort period's default, in steps: chosen by measurement (docs/performance.md, "Cell-ordered
// particles"; tools/bench-cell-order.sh).
constexpr long long kDefaultSortPeriod = 50;

// How the driver runs any method.
struct RunControl {
  // > 0: the particles are reordered by cell (core/search/cell_order.hpp) before every step
  // whose index (steps done) is a positive multiple of it; 0: never.
  long long sort_period = kDefaultSortPeriod;
};

// A wall-pressure sensor: a face of `diameter` on a wall surface, centred on `position`
// (core/run/pressure_sensors.hpp); series.csv columns "pressure_<name>" and "pressure_<name>_max".
struct PressureSensor {
  std::string name;
  Vec2 position = Vec2::Zero();  // m, on a wall surface
  double diameter = 0.0;         // m, > 0 (the scene's default: one particle spacing)
};

// Definitions of the measured quantities in series.csv (see docs/scene-format.md).
struct DiagnosticsControl {
  double front_link_distance = 1.5;  // l0: particles closer than this belong to one body of water
  double height_probe_width = 1.5;   // l0: the back-wall height probes particles this close to the wall
  double density_support = 2.4;      // l0: support of the kernel of the common density measure
  std::vector<PressureSensor> pressure_sensors;
};

// An experimental wall-pressure record to compare a sensor with (scene key validation,
// docs/scene-format.md; read by analysis/mps_lab/pressure.py, not by the simulation).
struct PressureRecord {
  std::string sensor;  // the name of a diagnostics.pressure_sensors entry
  std::string file;    // CSV of T = t sqrt(g/H), p / (rho g H); resolved against the scene file's folder
};

// The "validation" block: which experiment the scene's sensors compare with, and the
// definitions of the comparison (docs/validation.md, "Wall pressure: Buchner 2002").
struct ValidationControl {
  double length_scale = 0.0;           // m, H of T = t sqrt(g/H) and p / (rho g H); 0: no block
  double impact_threshold = 0.1;       // p / (rho g H): the impact is the first crossing of this
  Vec2 quasi_static = Vec2(3.0, 5.5);  // [T0, T1]: the window of the quasi-static RMS error
  std::vector<PressureRecord> pressure_records;
};

// A method's resolved block: its parameters and its wall treatments.
struct MethodConfig {
  ParameterValues parameters;
  std::vector<WallTreatmentChoice> wall_treatments;
};

struct Scene {
  std::string source;  // the file, for messages and run.json
  std::string description;
  double particle_spacing = 0.025;  // l0, m
  Box domain;
  TankWalls walls;
  std::vector<FluidBlock> fluid_blocks;
  Physics physics;
  TimeControl time;
  OutputControl output;
  RunControl run;
  DiagnosticsControl diagnostics;
  StabilitySettings stability;                  // the "stability" block (core/run/stability.hpp)
  ValidationControl validation;                 // the "validation" block (experiments to compare with)
  ContactControl contact;                       // the "contact" block (rigid bodies)
  std::string method;                           // the scene's default method
  std::map<std::string, MethodConfig> methods;  // one entry per registered method
  nlohmann::json document;                      // the JSON after --set overrides

  const MethodConfig& method_config(const std::string& name) const;
};

// Reads, applies overrides ("dotted.key=value", value parsed as JSON, else a string) and
// validates. Throws InputError.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides, const MethodRegistry& methods,
                 const WallTreatmentRegistry& walls);
// The same from the file's text; `source` names it in messages (the fuzz test feeds
// thousands of malformed texts through the very path that reads files).
Scene load_scene_text(const std::string& text, const std::string& source, const std::vector<std::string>& overrides,
                      const MethodRegistry& methods, const WallTreatmentRegistry& walls);
Scene parse_scene(nlohmann::json document, const std::string& source, const MethodRegistry& methods,
                  const WallTreatmentRegistry& walls);
// One --set assignment "dotted.key=value" (value JSON, or a bare word as a string; array
// components by index; missing objects on the way are created). "dotted.key?=value" is a default:
// it sets the key only where the document has no value there yet (a method's load setting for a
// wall treatment's parameter, MethodInfo::load_setting, which a --set replacing the whole block
// must not wipe).
void apply_override(nlohmann::json& document, const std::string& assignment, const std::string& source);

// The declared keys of the shared blocks, for documentation checks and `mps_lab scene-keys`.
struct SceneBlockSpec {
  std::string path;  // "" for the top level
  std::vector<ParameterSpec> keys;
};
std::vector<SceneBlockSpec> shared_scene_keys();

}  // namespace mps_lab
