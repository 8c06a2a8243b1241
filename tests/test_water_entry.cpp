// Water entry of a circular cylinder at constant velocity (scenes/water_entry.json; docs/validation.md,
// "Water entry"; issue 15 item 4): the fluid's vertical force on the cylinder as the slamming
// coefficient C_s = (F_y - rho g A_seg(d)) / (0.5 rho V^2 D) against the penetration d/D, for every
// registered method that moves walls and reports obstacle loads, against the fit of Campbell &
// Weynberg (1980) to their drop tests, C_s = 5.15 / (1 + 19 d/D) + 0.55 d/D. The definitions are
// those of analysis/mps_lab/studies/water_entry.py (its docstring), which writes the table.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/run/driver.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

namespace {

constexpr double kPi = 3.14159265358979323846;

// Campbell & Weynberg's (1980) fit at x = d/D.
double campbell_weynberg(double x) { return 5.15 / (1.0 + 19.0 * x) + 0.55 * x; }

// The fit's mean over [low, high] in closed form.
double fit_mean(double low, double high) {
  const double integral =
      5.15 / 19.0 * std::log((1.0 + 19.0 * high) / (1.0 + 19.0 * low)) + 0.275 * (high * high - low * low);
  return integral / (high - low);
}

// Area of a circle of radius r below a line at depth d above its lowest point (a segment), m^2.
double segment_area(double d, double r) {
  const double h = std::clamp(d, 0.0, 2.0 * r);
  return r * r * std::acos((r - h) / r) - (r - h) * std::sqrt(std::max(2.0 * r * h - h * h, 0.0));
}

struct EntryHistory {
  std::vector<double> time, force;  // s, N/m: obstacle 0's F_y after every step
  double l0 = 0.0;
  int wall_particles_start = 0, wall_particles_end = 0;  // wall particles within r of the circle's centre
  int fluid_inside_end = 0;                              // fluid_inside_circle at the end
};

int wall_particles_in_circle(const ParticleSet& particles, Vec2 centre, double radius) {
  int count = 0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] == ParticleType::Wall && (particles.position[i] - centre).norm() < radius) ++count;
  }
  return count;
}

// Fluid particles inside the circle deeper than l0/2 under its surface (the first wall particle line is
// l0/2 under it): fluid that went through the moving wall.
int fluid_inside_circle(const ParticleSet& particles, Vec2 centre, double radius, double l0) {
  int count = 0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] == ParticleType::Fluid && (particles.position[i] - centre).norm() < radius - 0.5 * l0)
      ++count;
  }
  return count;
}

EntryHistory run_entry(const MethodInfo& method, const Scene& scene) {
  Simulation simulation(scene, method);
  REQUIRE(simulation.reports_obstacle_loads());
  const Circle& circle = scene.walls.circles[0];
  const WallMotion& motion = scene.walls.motions[0];
  EntryHistory history;
  history.l0 = scene.particle_spacing;
  history.wall_particles_start = wall_particles_in_circle(simulation.particles(), circle.centre, circle.radius);
  while (simulation.time() < scene.time.end_time - 1e-12) {
    simulation.advance();
    history.time.push_back(simulation.time());
    history.force.push_back(simulation.obstacle_loads().force[0].y());
  }
  const Vec2 centre = circle.centre + motion.displacement(simulation.time());
  history.wall_particles_end = wall_particles_in_circle(simulation.particles(), centre, circle.radius);
  history.fluid_inside_end = fluid_inside_circle(simulation.particles(), centre, circle.radius, history.l0);
  return history;
}

struct EntryMeasures {
  double mean_cs = 0.0;  // the filtered C_s's mean over d/D in [0.1, 0.5]
  double fit = 0.0;      // Campbell & Weynberg's mean over the same rows' range
};

// The slamming coefficient of a history as analysis/mps_lab/studies/water_entry.py computes it:
// the moving mean of F_y over a centred window of 0.05 D/V, less the buoyancy of the segment below
// the undisturbed surface y_s (the top fluid row + l0/2), over 0.5 rho V^2 D; its trapezoidal mean
// in d/D over [0.1, 0.5].
EntryMeasures slamming_measures(const Scene& scene, const EntryHistory& history) {
  const Circle& circle = scene.walls.circles[0];
  const double radius = circle.radius, diameter = 2.0 * radius, l0 = history.l0;
  const double speed = std::fabs(scene.walls.motions[0].velocity.y());
  const double rho = scene.physics.density, g = std::fabs(scene.physics.gravity.y());
  const double y_min = scene.domain.min.y();
  const double top_row = y_min + (std::ceil((scene.fluid_blocks[0].region.max.y() - y_min) / l0 - 1e-9) - 1.0) * l0;
  const double surface = top_row + 0.5 * l0;
  const double window = 0.05 * diameter / speed;
  const std::size_t n = history.time.size();
  std::vector<double> x, cs;
  for (std::size_t k = 0; k < n; ++k) {
    double sum = 0.0;
    int count = 0;
    for (std::size_t j = 0; j < n; ++j) {
      if (std::fabs(history.time[j] - history.time[k]) <= 0.5 * window) {
        sum += history.force[j];
        ++count;
      }
    }
    const double bottom = circle.centre.y() - radius + scene.walls.motions[0].displacement(history.time[k]).y();
    const double depth = surface - bottom;
    if (depth / diameter < 0.1 || depth / diameter > 0.5) continue;
    x.push_back(depth / diameter);
    cs.push_back((sum / count - rho * g * segment_area(depth, radius)) / (0.5 * rho * speed * speed * diameter));
  }
  REQUIRE(x.size() >= 2);
  double integral = 0.0;
  for (std::size_t k = 1; k < x.size(); ++k) integral += 0.5 * (cs[k] + cs[k - 1]) * (x[k] - x[k - 1]);
  return {integral / (x.back() - x.front()), fit_mean(x.front(), x.back())};
}

}  // namespace

TEST_CASE("water entry: Campbell and Weynberg's fit and the buoyancy against closed forms", "[entry]") {
  // The fit at d/D = 0.1 and 0.5 by hand: 5.15/2.9 + 0.055 = 1.8309, 5.15/10.5 + 0.275 = 0.7655;
  // its mean over [0.1, 0.5] by the midpoint rule on 4000 intervals (error ~ 1e-7).
  CHECK(campbell_weynberg(0.1) == Approx(5.15 / 2.9 + 0.055).epsilon(1e-12));
  CHECK(campbell_weynberg(0.5) == Approx(5.15 / 10.5 + 0.275).epsilon(1e-12));
  double sum = 0.0;
  for (int k = 0; k < 4000; ++k) sum += campbell_weynberg(0.1 + (k + 0.5) * 1e-4);
  CHECK(fit_mean(0.1, 0.5) == Approx(sum / 4000.0).epsilon(1e-6));
  CHECK(fit_mean(0.1, 0.5) == Approx(1.0369).margin(1e-4));
  // A half-immersed circle displaces pi r^2 / 2; a fully immersed one pi r^2.
  CHECK(segment_area(0.055, 0.055) == Approx(kPi * 0.055 * 0.055 / 2.0).epsilon(1e-12));
  CHECK(segment_area(0.11, 0.055) == Approx(kPi * 0.055 * 0.055).epsilon(1e-12));
  CHECK(segment_area(-0.01, 0.055) == 0.0);
}

namespace {

// The scene at l0 = D/n with the time step 0.02 s/m x l0 (the study's case,
// analysis/mps_lab/studies/water_entry.py) to t = 0.033 s: the bottom reaches d/D = 0.525 (0.55 at
// n = 11), half a filter window past the range's end. A method with a time-step rule runs at the fixed step.
Scene entry_scene(const MethodInfo& method, int divisions) {
  const double l0 = 0.11 / divisions;
  std::vector<std::string> overrides = {"method=" + method.name, "particle_spacing=" + std::to_string(l0),
                                        "time.time_step=" + std::to_string(0.02 * l0), "time.end_time=0.033"};
  for (const auto& spec : method.parameters) {
    if (spec.name == "time_step_rule") overrides.push_back("methods." + method.name + ".time_step_rule=\"fixed\"");
  }
  return load("water_entry.json", overrides);
}

}  // namespace

TEST_CASE("water entry: every method that moves walls against Campbell and Weynberg at D/l0 = 11 and 22",
          "[validation][entry]") {
  int runs = 0;
  for (const MethodInfo* method : registries().methods.all()) {
    if (!method->obstacle_loads || !method->moving_walls) continue;
    const Scene coarse = entry_scene(*method, 11), fine = entry_scene(*method, 22);
    if (!reports_obstacle_loads(fine, *method)) continue;
    const EntryHistory history = run_entry(*method, fine);
    const EntryMeasures measures = slamming_measures(fine, history);
    const EntryMeasures coarse_measures = slamming_measures(coarse, run_entry(*method, coarse));
    const double ratio = measures.mean_cs / measures.fit, coarse_ratio = coarse_measures.mean_cs / coarse_measures.fit;
    WARN(method->name << ": mean C_s over d/D 0.1-0.5 " << measures.mean_cs << " against the fit's " << measures.fit
                      << " (ratio " << ratio << "; " << coarse_ratio << " at D/l0 = 11); wall particles in the circle "
                      << history.wall_particles_start << " -> " << history.wall_particles_end << ", fluid inside "
                      << history.fluid_inside_end);
    // The circle's wall particles move with it (constant_velocity, core/walls/moving_walls.hpp) and no
    // fluid passes through its wall.
    CHECK(history.wall_particles_end == history.wall_particles_start);
    CHECK(history.fluid_inside_end == 0);
    // Agreement: within 50 % of the fit's mean (1.037) at D/l0 = 22. Measured ratios at D/l0 = 11, 22,
    // 44 (docs/validation.md, "Water entry"): isph 1.38, 1.30, 1.27 and dfsph 0.92, 1.30, 1.33
    // converge to 1.27-1.33 (the D/l0 = 22 value within 3 % of the D/l0 = 44 one); the tank's walls
    // move the mean by <= 5 % for isph (the 12 D x 5 D tank) and dfsph's by 17 % (its solver noise:
    // the curves cross each other); 1.33 + 0.17 = 1.50, and the band is taken symmetric. Campbell &
    // Weynberg's scatter about their fit is not available offline, so no experimental band is added.
    // mps with its default load (the fluid's pressure over the circle's surface): 0.88 and 1.02 of the
    // fit at D/l0 = 11 and 22, inside the band. A method outside the band must at least converge
    // toward the fit: its distance from the fit at D/l0 = 22 at most half that at D/l0 = 11 (first
    // order in l0); mps with its wall particles' pressure (obstacle_load wall_pressure) was such a
    // method: 8.83, 3.27, 1.83 times the fit at D/l0 = 11, 22, 44 (distance 7.83, 2.27, 0.83). The
    // WARN above prints both ratios.
    const bool agrees = std::fabs(ratio - 1.0) <= 0.5;
    const bool converges = std::fabs(ratio - 1.0) <= 0.5 * std::fabs(coarse_ratio - 1.0);
    CHECK((agrees || converges));
    ++runs;
  }
  CHECK(runs >= 1);
}
