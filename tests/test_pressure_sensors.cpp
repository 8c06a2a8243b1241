// Wall pressure sensors (core/run/pressure_sensors.hpp, docs/validation.md "Wall pressure"):
// the extrapolation of Adami et al. (2012) on hand-built particles, then still water in a
// tank with every registered method and every boundary model it supports (no method or
// model is named here: both come from the registries and wall_treatment_supports).
#include <cmath>
#include <limits>
#include <sstream>

#include <catch2/catch.hpp>

#include "core/io/checkpoint.hpp"
#include "core/run/driver.hpp"
#include "core/run/pressure_sensors.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

namespace {

constexpr double kRho = 1000.0;  // kg/m^3
constexpr double kG = 9.81;      // m/s^2
constexpr double kL0 = 0.025;    // m

// Fluid on the lattice above a bed whose surface is y = 0 (first row at y = l0/2), x in
// [0, 1] m, `rows` rows; pressure p(y) = rho g_eff (H - y) with H = rows l0 (the lattice's top edge).
ParticleSet hydrostatic_block(int rows, double g_eff) {
  ParticleSet particles;
  const double top = rows * kL0;
  for (int row = 0; row < rows; ++row) {
    for (int column = 0; column < 40; ++column) {
      particles.add(Vec2((column + 0.5) * kL0, (row + 0.5) * kL0), Vec2::Zero(), ParticleType::Fluid);
    }
  }
  for (std::size_t i = 0; i < particles.size(); ++i) {
    particles.pressure[i] = kRho * g_eff * (top - particles.position[i].y());
  }
  return particles;
}

// The sensors of the still-water tank (scenes/hydrostatic.json: bed surface y = 0.0125 m,
// left wall surface x = 0.0125 m, top particle row y = 0.275 m): three on the left wall,
// one above the water (dry).
const std::vector<double> kSensorHeights = {0.0625, 0.1375, 0.2125};  // m
constexpr double kDryHeight = 0.5;                                    // m, above the water

std::string tank_sensors() {
  std::ostringstream text;
  text << "diagnostics.pressure_sensors=[";
  for (std::size_t k = 0; k < kSensorHeights.size(); ++k) {
    text << "{\"name\": \"s" << k << "\", \"position\": [0.0125, " << kSensorHeights[k] << "]},";
  }
  text << "{\"name\": \"dry\", \"position\": [0.0125, " << kDryHeight << "]}]";
  return text.str();
}

// Depth of a point below the free surface of the tank's water, m. The fluid block is a
// lattice whose top row of particle centres is at y_top; each particle stands for a square
// of side l0, so the free surface is the lattice's top edge, y_top + l0/2 (the same rule
// puts the wall surfaces l0/2 from the first wall layer, core/walls/wall_geometry.hpp).
double depth_below_surface(double y, double top_row, double l0) { return top_row + 0.5 * l0 - y; }

struct SensorRun {
  std::vector<double> mean;      // Pa, the record's time-weighted mean over the window, per sensor (dry last)
  std::vector<double> peak;      // Pa, the record's peak over the window
  std::vector<double> expected;  // Pa, rho g_eff h
  // The same window from the readings of every step, recomputed here (read_pressure_sensors):
  std::vector<double> step_mean;   // Pa, sum reading dt / sum dt
  std::vector<double> step_max;    // Pa
  std::vector<double> step_sigma;  // Pa, time-weighted standard deviation of the readings
  std::string status;
};

// Mean, maximum and standard deviation of the per-step readings, weighted by dt.
void add_step_statistics(const std::vector<std::vector<double>>& readings, const std::vector<double>& dts,
                         SensorRun& run) {
  const std::size_t sensors = readings.empty() ? 0 : readings.front().size();
  for (std::size_t k = 0; k < sensors; ++k) {
    double sum = 0.0, sum2 = 0.0, time = 0.0, most = -std::numeric_limits<double>::infinity();
    for (std::size_t step = 0; step < readings.size(); ++step) {
      sum += readings[step][k] * dts[step];
      sum2 += readings[step][k] * readings[step][k] * dts[step];
      time += dts[step];
      most = std::max(most, readings[step][k]);
    }
    run.step_mean.push_back(sum / time);
    run.step_max.push_back(most);
    run.step_sigma.push_back(std::sqrt(std::max(0.0, sum2 / time - (sum / time) * (sum / time))));
  }
}

// scenes/hydrostatic.json with `overrides`, to `end` seconds; the sensors' mean and peak over
// [start, end] (one series interval: take_row at start and at end).
SensorRun run_tank(const MethodInfo& method, std::vector<std::string> overrides, double g_eff, double start,
                   double end) {
  overrides.push_back(tank_sensors());
  overrides.push_back("time.end_time=" + std::to_string(end));
  const Scene scene = load("hydrostatic.json", overrides);
  Simulation simulation(scene, method);
  const double l0 = scene.particle_spacing;
  const double top_row = fluid_top(simulation.particles());
  SensorRun run;
  std::vector<std::vector<double>> readings;
  std::vector<double> dts;
  try {
    simulation.run_to(start);
    simulation.pressure_sensors().take_row(simulation.particles());
    while (simulation.time() + 1e-6 * simulation.last_time_step() < end) {
      simulation.advance();
      readings.push_back(read_pressure_sensors(simulation.particles(), scene, simulation.pressure_sensors().faces()));
      dts.push_back(simulation.last_time_step());
    }
  } catch (const std::exception& error) {
    run.status = error.what();
    return run;
  }
  const std::vector<double> row = simulation.pressure_sensors().take_row(simulation.particles());
  for (std::size_t k = 0; k + 1 < row.size(); k += 2) {
    run.mean.push_back(row[k]);
    run.peak.push_back(row[k + 1]);
  }
  for (double y : kSensorHeights)
    run.expected.push_back(scene.physics.density * g_eff * depth_below_surface(y, top_row, l0));
  add_step_statistics(readings, dts, run);
  run.status = "completed";
  return run;
}

}  // namespace

TEST_CASE("wall pressure: the Adami extrapolation is exact for a hydrostatic field", "[unit][sensor]") {
  const ParticleSet particles = hydrostatic_block(10, kG);
  const SphKernel kernel = wall_pressure_kernel(kL0);
  // p_w = [sum p_f W + rho g . sum r_wf W] / sum W: for p_f = rho g (H - y_f) and r_wf = x_w - x_f,
  // each term is p_f + rho (-g)(y_w - y_f) = rho g (H - y_w), whatever the weights: exact for a
  // linear field with gradient rho g (Adami et al. 2012). On the bed surface (y = 0) of 10 rows:
  // rho g H = 1000 * 9.81 * 0.25 = 2452.5 Pa; at a lattice-aligned and an unaligned point.
  for (const double x : {0.5, 0.5123}) {
    CHECK(extrapolated_wall_pressure(particles, Vec2(x, 0.0), Vec2(0.0, -kG), kRho, kernel) ==
          Approx(2452.5).epsilon(1e-12));
  }
  // The gravity term matters: without it the wall reads the kernel average of the nearest
  // rows only, rho g (H - ~0.9 l0), about 9 % low here.
  CHECK(extrapolated_wall_pressure(particles, Vec2(0.5, 0.0), Vec2::Zero(), kRho, kernel) < 0.95 * 2452.5);
}

TEST_CASE("wall pressure: a wall accelerating upward reads rho (g + a) h", "[unit][sensor]") {
  // In the frame of a tank accelerating upward at a, the fluid at rest carries
  // p = rho (g + a)(H - y); the extrapolation's body force is g - a_w = -(g + a) e_y. Exact as above:
  // a = 4.905 m/s^2 (g/2), H = 0.25 m: 1000 * 14.715 * 0.25 = 3678.75 Pa.
  const double a = 0.5 * kG;
  const ParticleSet particles = hydrostatic_block(10, kG + a);
  const SphKernel kernel = wall_pressure_kernel(kL0);
  CHECK(extrapolated_wall_pressure(particles, Vec2(0.5, 0.0), Vec2(0.0, -kG) - Vec2(0.0, a), kRho, kernel) ==
        Approx(3678.75).epsilon(1e-12));
}

TEST_CASE("wall pressure: a dry face reads exactly 0", "[unit][sensor]") {
  const ParticleSet particles = hydrostatic_block(4, kG);  // water up to y = 0.1 m
  const SphKernel kernel = wall_pressure_kernel(kL0);
  // Support 2.4 l0 = 0.06 m: a point 0.1 + 0.06 m up or higher sees no fluid.
  CHECK(extrapolated_wall_pressure(particles, Vec2(0.5, 0.17), Vec2(0.0, -kG), kRho, kernel) == 0.0);
}

TEST_CASE("wall pressure: the faces read in one pass equal the extrapolation point by point", "[unit][sensor]") {
  // SensorReadout visits each fluid particle once and adds it to every face point in reach; each
  // point's sums still run over the fluid in index order, so every face must read the mean of
  // extrapolated_wall_pressure at its points to the bit. A splashing dam break (t = 0.4 s, the
  // surge on the far wall) with faces of 4 and 6 points, one at a corner and one dry; read together
  // and each alone.
  const Scene scene = load("dambreak.json", {"time.end_time=0.4",
                                             "diagnostics.pressure_sensors=["
                                             "{\"name\": \"far\", \"position\": [1.0, 0.0375]},"
                                             "{\"name\": \"corner\", \"position\": [0.97, 0.0], \"diameter\": 0.04},"
                                             "{\"name\": \"dry\", \"position\": [0.0, 0.55]}]"});
  const MethodInfo* method = registries().methods.find(scene.method);
  REQUIRE(method != nullptr);
  Simulation simulation(scene, *method);
  simulation.run_to(0.4);
  const ParticleSet& particles = simulation.particles();
  const std::vector<SensorFace>& faces = simulation.pressure_sensors().faces();
  const std::vector<double> readings = read_pressure_sensors(particles, scene, faces);
  const SphKernel kernel = wall_pressure_kernel(scene.particle_spacing);
  REQUIRE(readings.size() == 3);
  CHECK(faces[1].points.size() == 6);
  for (std::size_t k = 0; k < faces.size(); ++k) {
    double sum = 0.0;
    for (const Vec2& point : faces[k].points)
      sum += extrapolated_wall_pressure(particles, point, scene.physics.gravity, scene.physics.density, kernel);
    CHECK(readings[k] == sum / static_cast<double>(faces[k].points.size()));
    // Alone, the face's points span a box a support wide at most: the pass's cut at the box.
    CHECK(read_pressure_sensors(particles, scene, {faces[k]}).front() == readings[k]);
  }
  CHECK(readings[0] > 0.0);  // wet: the surge is on the far wall
  CHECK(readings[2] == 0.0);
}

TEST_CASE("wall pressure: sensor keys - faces on the wall surface and one-line errors", "[unit][sensor][input]") {
  const Scene scene = load("hydrostatic.json", {tank_sensors()});
  const std::vector<SensorFace> faces = sensor_faces(scene);
  REQUIRE(faces.size() == 4);
  // Default diameter l0 = 0.025 m, sample points at most l0/4 apart: 4 points at +-l0/8, +-3 l0/8.
  REQUIRE(faces[0].points.size() == 4);
  CHECK(faces[0].points[0].x() == Approx(0.0125).epsilon(1e-12));
  CHECK(faces[0].points[0].y() == Approx(0.0625 - 0.375 * 0.025).epsilon(1e-12));
  CHECK(faces[0].points[3].y() == Approx(0.0625 + 0.375 * 0.025).epsilon(1e-12));
  CHECK(faces[0].normal == Vec2(1.0, 0.0));
  const auto sensor = [](const std::string& fields) {
    return "diagnostics.pressure_sensors=[{\"name\": \"a\", " + fields + "}]";
  };
  CHECK_THROWS_WITH(
      load("hydrostatic.json", {sensor("\"position\": [0.0125, 0.1], \"diameter\": 0")}),
      Catch::Contains("diagnostics.pressure_sensors[0].diameter: got 0") && Catch::Contains("expected a number > 0"));
  CHECK_THROWS_WITH(load("hydrostatic.json", {sensor("\"position\": [0.1, 0.1]")}),
                    Catch::Contains("diagnostics.pressure_sensors[0].position: got [0.1,0.1], expected a point on "
                                    "a wall"));
  // In front of the surface (here by l0/10) is not on the wall.
  CHECK_THROWS_WITH(load("hydrostatic.json", {sensor("\"position\": [0.015, 0.1]")}),
                    Catch::Contains("diagnostics.pressure_sensors[0].position: got [0.015,0.1]"));
  CHECK_THROWS_WITH(load("hydrostatic.json", {sensor("\"position\": [-0.1, 0.1]")}),
                    Catch::Contains("diagnostics.pressure_sensors[0].position: got [-0.1,0.1], expected a point "
                                    "inside the domain"));
  // A face longer than the surface around it is cut at the corner: on the bed (surface from
  // x = 0.0125 m) centred at x = 0.02 m with diameter 0.05 m, the face is [0.0125, 0.045] m,
  // 0.0325 m long: 6 parts (at most l0/4 = 0.00625 m each), the first centre 0.0125 + 0.0325/12.
  const std::vector<SensorFace> cut =
      sensor_faces(load("hydrostatic.json", {sensor("\"position\": [0.02, 0.0125], \"diameter\": 0.05")}));
  REQUIRE(cut.front().points.size() == 6);
  CHECK(cut.front().points.front().x() == Approx(0.0125 + 0.0325 / 12.0).epsilon(1e-12));
  CHECK(cut.front().points.back().x() == Approx(0.045 - 0.0325 / 12.0).epsilon(1e-12));
  CHECK(cut.front().points.front().y() == Approx(0.0125).epsilon(1e-12));
  CHECK_NOTHROW(load("hydrostatic.json", {sensor("\"position\": [0.25, 0.0125], \"diameter\": 0.01")}));
  for (const char* name : {"dambreak.json", "dambreak_fine.json", "dambreak_large.json", "dambreak_obstacle.json"}) {
    INFO(name);
    CHECK_NOTHROW(load(name));
  }
  // The scenes put their sensors on the wall's first particle line (x = 1 m), valid at any
  // spacing: the face is projected onto the surface, l0/2 inside (1 - 0.0025 m at l0 = 0.005 m).
  const std::vector<SensorFace> fine = sensor_faces(load("dambreak.json", {"particle_spacing=0.005"}));
  REQUIRE(fine.size() == 1);
  CHECK(fine[0].points.front().x() == Approx(0.9975).epsilon(1e-12));
  CHECK(fine[0].normal == Vec2(-1.0, 0.0));
}

// What every run must show, and the accuracy target (1 % of rho g h) reported, not enforced:
// measured (docs/validation.md, "Wall pressure"), no registered method meets it with every
// boundary model today, for causes found and documented there:
//   - a method whose free-surface condition sets p = 0 on the top particle centres reads
//     rho g (h - l0/2) (measured 0.952 / 0.922 / 0.834 at h = 0.225 / 0.15 / 0.075 m, i.e. the
//     surface l0/2 lower: (h - l0/2)/h = 0.944 / 0.917 / 0.833);
//   - a method whose wall term mirrors the particle's own pressure once (Akinci et al. 2012:
//     the lattice wall models) carries 1.5-1.6 rho g h in the fluid next to the wall; with the
//     symmetric wall term of mirror particles the same method reads 1.01-1.03;
//   - a method with the noisy, spike-prone pressure of the MPS source term reads 0.90-1.01.
// The guards: the dry sensor reads 0; the record's peak is the largest per-step reading and its
// mean their time-weighted mean (recomputed here from read_pressure_sensors after every step);
// the peak is at least the mean and, on this steady state, above it by no more than the
// noise: at most 25 standard deviations of the per-step readings (measured at most 8.5, MPS's
// heavy-tailed spikes, until the particles were reordered by cell every 50 steps: the same
// noise in another realisation then gave mps with distance_function 18.3 and 15.8 sigma; 1.3-3.9
// for the others, about a Gaussian noise's largest of ~2000 samples, 3.5 sigma), plus 1e-6 rho g h for water so still
// that sigma is round-off (measured peak - mean 1e-4 Pa); and the mean lies within [0.75, 1.7] rho g h, the spread of
// all methods and models measured (0.771 to 1.62; the lowest, 0.771, is eisph with mirror particles at h = 0.075 m,
// whose one relaxation sweep per step has not brought the near-surface pressure to equilibrium in 1.5 s): a guard
// against a broken sensor (a lost gravity term: -9 %, a sign: below 0), not the target.
void check_still_water(const SensorRun& run, const std::string& label, double peak_sigmas = 25.0) {
  std::ostringstream ratios;
  for (std::size_t k = 0; k < kSensorHeights.size(); ++k) {
    ratios << " " << run.mean[k] / run.expected[k]
           << " (peak - mean: " << (run.peak[k] - run.mean[k]) / std::max(run.step_sigma[k], 1e-300) << " sigma)";
  }
  WARN(label << ": mean / rho g h at h = 0.225, 0.15, 0.075 m:" << ratios.str());
  CHECK(run.mean.back() == 0.0);
  CHECK(run.peak.back() == 0.0);
  for (std::size_t k = 0; k < kSensorHeights.size(); ++k) {
    INFO("sensor at h = " << run.expected[k] / (kRho * 9.81) << " m (for g)");
    CHECK(run.peak[k] == run.step_max[k]);
    CHECK(run.mean[k] == Approx(run.step_mean[k]).epsilon(1e-12));
    CHECK(run.peak[k] >= run.mean[k]);
    CHECK(run.peak[k] - run.mean[k] <= peak_sigmas * run.step_sigma[k] + 1e-6 * run.expected[k]);
    CHECK(run.mean[k] > 0.75 * run.expected[k]);
    CHECK(run.mean[k] < 1.7 * run.expected[k]);
    CHECK_NOFAIL(std::fabs(run.mean[k] / run.expected[k] - 1.0) < 0.01);  // the target, reported
  }
}

TEST_CASE("wall pressure: still water - every method and boundary model - three heights", "[validation][sensor]") {
  // scenes/hydrostatic.json to 1.5 s, each method with its own time-step rule and each boundary
  // model it supports; each sensor's record over [0.5, 1.5] s against rho g h, h the depth
  // below the lattice's top edge (depth_below_surface): 0.225, 0.15 and 0.075 m; the dry sensor
  // (0.5 m, above the water). Checks: check_still_water.
  for (const MethodInfo* method : registries().methods.all()) {
    for (const WallTreatmentInfo* model : boundary_models(*method)) {
      INFO("method " << method->name << ", boundary model " << model->name);
      const SensorRun run = run_tank(
          *method, {"methods." + method->name + ".wall_treatments={\"" + model->name + "\":{}}"}, kG, 0.5, 1.5);
      REQUIRE(run.status == "completed");
      check_still_water(run, method->name + " / " + model->name);
    }
  }
}

TEST_CASE("wall pressure: a tank accelerating upward at g/2 - every method", "[validation][sensor]") {
  // In the tank's frame a uniform upward acceleration a is gravity g + a: the scene's gravity
  // is -(g + a) e_y with a = g/2 (14.715 m/s^2), the walls at rest in that frame (a_w = 0), and
  // the expected pressure rho (g + a) h. Each method with its default boundary model; the same
  // checks as still water (check_still_water), the ratios measured the same as at g to within
  // 0.05 (docs/validation.md).
  for (const MethodInfo* method : registries().methods.all()) {
    INFO("method " << method->name);
    const SensorRun run = run_tank(*method, {"physics.gravity=[0, -14.715]"}, 1.5 * kG, 0.5, 1.5);
    REQUIRE(run.status == "completed");
    check_still_water(run, method->name + " accelerated at g/2");
  }
}

// check_still_water's guards, and the method's promise (MethodInfo::load_setting) enforced at
// every sensor: |mean / (rho g h) - 1| within its still_water_tolerance. The peak may lie 50
// standard deviations above the mean: a quiet source (the mixed source of mps) keeps sigma small
// and its rare spikes stand further out (measured up to 39.8 sigma over [0.5, 3] s).
void check_promise(const SensorRun& run, const MethodInfo& method, const std::string& label) {
  check_still_water(run, label, 50.0);
  const double tolerance = method.load_setting.still_water_tolerance;
  for (std::size_t k = 0; k < kSensorHeights.size(); ++k) {
    INFO(label << ", sensor at depth " << run.expected[k] / run.expected.front() << " of the deepest's");
    CHECK(std::fabs(run.mean[k] / run.expected[k] - 1.0) <= tolerance);
  }
}

TEST_CASE("wall pressure: each method's load setting keeps its still-water promise - every boundary model",
          "[validation][sensor]") {
  // Every method declares a setting for wall loads and a promise (MethodInfo::load_setting); with
  // it and each boundary model it supports, scenes/hydrostatic.json to 3 s, the sensors' means
  // over [0.5, 3] s (a longer window than the defaults' test: the mean's own scatter between
  // half-second windows is 0.5-1 %). The promises are measured values rounded up by that scatter
  // (docs/validation.md, "Each method's load setting"); the target, 1 %, is reported.
  for (const MethodInfo* method : registries().methods.all()) {
    INFO("method " << method->name << ": " << method->load_setting.basis);
    REQUIRE(method->load_setting.still_water_tolerance > 0.0);
    REQUIRE(method->load_setting.still_water_tolerance <= 0.1);  // a promise, not a guard
    for (const WallTreatmentInfo* model : boundary_models(*method)) {
      INFO("boundary model " << model->name);
      const SensorRun run = run_tank(*method, load_setting_with(*method, model->name), kG, 0.5, 3.0);
      REQUIRE(run.status == "completed");
      check_promise(run, *method, method->name + " (load setting) / " + model->name);
    }
  }
}

TEST_CASE("wall pressure: particle shifting keeps each method's still-water promise - every boundary model",
          "[validation][sensor]") {
  // The measure particle_shifting (core/walls/particle_shifting.cpp, its defaults: A = 2, no
  // velocity correction) on top of each method's load setting, with every boundary model: the
  // promises hold with it. Measured 2026-11-29 (docs/walls.md, "Particle shifting"): mps
  // 0.954-1.020, isph 0.982-1.006, eisph 0.979-1.004, dfsph 0.993-1.011, wcsph 0.999-1.009, against
  // 7, 2, 3, 2 and 1 %. dfsph's load setting has shifting with a fixed part since 2026-12-07 (a
  // default of its block); this test's {} replaces it by the defaults: 0.997-1.012. The measure
  // moves the particles of every method that supports it, so it is held to each one's promise; no
  // method is named.
  const WallTreatmentInfo& shifting = *registries().walls.find("particle_shifting");
  for (const MethodInfo* method : registries().methods.all()) {
    if (!wall_treatment_supports(shifting, *method)) continue;
    INFO("method " << method->name << ": " << method->load_setting.basis);
    for (const WallTreatmentInfo* model : boundary_models(*method)) {
      INFO("boundary model " << model->name);
      std::vector<std::string> overrides = load_setting_with(*method, model->name);
      overrides.push_back("methods." + method->name + ".wall_treatments.particle_shifting={}");
      const SensorRun run = run_tank(*method, overrides, kG, 0.5, 3.0);
      REQUIRE(run.status == "completed");
      check_promise(run, *method, method->name + " (load setting, shifted) / " + model->name);
    }
  }
}

TEST_CASE("wall pressure: each method's load setting, the tank accelerating upward at g/2", "[validation][sensor]") {
  // As "a tank accelerating upward at g/2" with each method's load setting and its default
  // boundary model: the promise holds against rho (g + a) h.
  for (const MethodInfo* method : registries().methods.all()) {
    INFO("method " << method->name);
    std::vector<std::string> overrides = load_setting_with(*method, "");
    overrides.push_back("physics.gravity=[0, -14.715]");
    const SensorRun run = run_tank(*method, overrides, 1.5 * kG, 0.5, 3.0);
    REQUIRE(run.status == "completed");
    check_promise(run, *method, method->name + " (load setting) accelerated at g/2");
  }
}

TEST_CASE("wall pressure: the interval's sums resume bit for bit from a checkpoint", "[unit][sensor][checkpoint]") {
  // Two simulations of the dam break: one straight through, one saved at step 7 into a
  // checkpoint and restored into a fresh Simulation; both go on to step 20 and take their row
  // (mean and peak since step 0: the interval spans the checkpoint). The rows agree to the bit.
  const MethodInfo& method = *registries().methods.all().front();
  const Scene scene = load("dambreak.json", {"time.end_time=0.1"});
  Simulation straight(scene, method);
  Simulation first(scene, method);
  for (int step = 0; step < 7; ++step) {
    straight.advance();
    first.advance();
  }
  CheckpointWriter writer;
  first.save_checkpoint(writer);
  CheckpointReader reader(writer.file_content("test"), "memory", "test");
  Simulation resumed(scene, method);
  resumed.restore_checkpoint(reader);
  for (int step = 7; step < 20; ++step) {
    straight.advance();
    resumed.advance();
  }
  const std::vector<double> a = straight.pressure_sensors().take_row(straight.particles());
  const std::vector<double> b = resumed.pressure_sensors().take_row(resumed.particles());
  REQUIRE(a.size() == 2);
  CHECK(a == b);
  CHECK(a[1] >= a[0]);
  // The row right after a restore, before any step, is the saved interval's own (the peak of 0-20
  // above is reached after step 7, so that row would not notice a lost peak): still water with the
  // tank's wet sensors, 7 steps, saved, restored, the rows of both equal to the bit.
  const Scene tank = load("hydrostatic.json", {tank_sensors()});
  Simulation saved(tank, method);
  for (int step = 0; step < 7; ++step) saved.advance();
  CheckpointWriter tank_writer;
  saved.save_checkpoint(tank_writer);
  CheckpointReader tank_reader(tank_writer.file_content("test"), "memory", "test");
  Simulation restored(tank, method);
  restored.restore_checkpoint(tank_reader);
  const std::vector<double> at_save = saved.pressure_sensors().take_row(saved.particles());
  const std::vector<double> from_checkpoint = restored.pressure_sensors().take_row(restored.particles());
  REQUIRE(at_save.size() == 8);  // mean and peak of three wet sensors and the dry one
  CHECK(at_save[1] > at_save[0]);
  CHECK(at_save[0] > 0.0);
  CHECK(from_checkpoint == at_save);
}
