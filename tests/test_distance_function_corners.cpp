// The distance function's corner rule (core/walls/distance_function.cpp, `corners`; docs/walls.md,
// "Distance function at corners"): with `nearest` each virtual row point counts for its nearest
// segment, and i's wall number density jumps where a point that moves with i crosses the line where
// the nearest segment changes; with `blended` (the default) the rows that overlap share each point by
// a partition of unity and the sum is continuous, which keeps MPS's still water over the 25-degree
// slope from its velocity spikes; with `lattice` the solid behind a right-angled concave corner of
// fixed walls is a lattice that slides with the particle, and the corner reads the spec walls'
// volume.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "core/base/rigid_pose.hpp"
#include "core/run/driver.hpp"
#include "core/walls/wall_treatment.hpp"
#include "methods/mps/mps_kernels.hpp"
#include "still_water_obstacles.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

namespace {

std::string distance_function(const std::string& corners) {
  return "methods.mps.wall_treatments={\"distance_function\":{\"corners\":\"" + corners + "\"}}";
}

// The wall part of the MPS number density (spec §2, re = 2.1 l0) of the lone fluid particle of
// `particles` (index 0), from the wall samples `set` builds for it.
double wall_number_density(const Scene& scene, WallTreatmentSet& set, ParticleSet& particles) {
  const double l0 = scene.particle_spacing, re = 2.1 * l0;
  WallContext context{particles, nullptr, 5e-4, scene};
  context.support = re;
  WallSampleList samples;
  set.build_wall_samples(context, samples);
  double n = 0.0;
  for (std::uint32_t k = samples.begin(0); k < samples.end(0); ++k) {
    const WallSample& sample = samples.samples[k];
    n += sample.volume * mps_weight((sample.position - particles.position[0]).norm(), re, 0.01 * l0);
  }
  return n;
}

// The largest change of that wall number density between neighbouring values of a parameter s
// = 0, step, ... up to `end`, the lone particle and its walls given by particles_at(s).
template <typename ParticlesAt>
double largest_change(const Scene& scene, double end, double step, ParticlesAt particles_at) {
  WallTreatmentSet set(scene.method_config("mps").wall_treatments, scene);
  double previous = 0.0, largest = 0.0;
  for (double s = 0.0; s <= end; s += step) {
    ParticleSet particles = particles_at(s);
    const double n = wall_number_density(scene, set, particles);
    if (s > 0.0) largest = std::max(largest, std::fabs(n - previous));
    previous = n;
  }
  return largest;
}

// A lone particle moved along the straight path from + s direction, s = 0 to `length` m in steps
// of `step` m, on `scene_name` with the distance function's corner rule `corners`.
double largest_change_along(const char* scene_name, const std::string& corners, Vec2 from, Vec2 direction,
                            double length, double step) {
  const Scene scene = load(scene_name, {distance_function(corners)});
  return largest_change(scene, length, step, [&](double s) {
    ParticleSet particles;
    particles.add(from + s * direction, Vec2::Zero(), ParticleType::Fluid);
    return particles;
  });
}

// Along the path y = 0.025 m (half a spacing above the bed's surface) of
// scenes/hydrostatic_slope.json, x from 0.05 to 0.16 m (the slope's toe is at x = 0.15 m on the
// bed's surface), in steps of `step` m.
double largest_change_to_the_toe(const std::string& corners, double step) {
  return largest_change_along("hydrostatic_slope.json", corners, Vec2(0.05, 0.025), Vec2(1.0, 0.0), 0.11, step);
}

// A particle at the foot of the gate of scenes/dambreak_gate.json (x = 0.225 m, y = 0.025 m: half
// a spacing from the gate's left face and from the bed) as the gate is lifted from 0 to 50 mm in
// steps of `step` m. The gate's bottom is a convex corner that passes the particle's rows.
double largest_change_as_the_gate_lifts(const std::string& corners, double step) {
  const Scene scene = load("dambreak_gate.json", {distance_function(corners)});
  return largest_change(scene, 0.05, step, [&scene](double lift) {
    ParticleSet particles;
    particles.add(Vec2(0.225, 0.025), Vec2::Zero(), ParticleType::Fluid);
    particles.obstacle_pose.assign(scene.walls.obstacles.size(), RigidPose{});
    particles.obstacle_pose[0].displacement = Vec2(0.0, lift);
    return particles;
  });
}

// Along the path y = 0.025 m (half a spacing above the bed's surface) of scenes/dambreak_obstacle.json,
// x from 0.3 m to the obstacle's foot (its face at x = 0.4875 m, the particle half a spacing from
// it at 0.475 m), in steps of `step` m: a concave corner where the bed's surface runs on under the
// obstacle, buried there.
double largest_change_to_the_foot(const std::string& corners, double step) {
  return largest_change_along("dambreak_obstacle.json", corners, Vec2(0.3, 0.025), Vec2(1.0, 0.0), 0.175, step);
}

// The largest change of a probe (one of the above) under each corner rule at a coarse step and
// at one ten times finer: a continuous function changes by at most its slope times the step, so
// its largest change shrinks tenfold; a jump keeps its size.
struct ChangesByRule {
  double nearest_coarse, nearest_fine, rule_coarse, rule_fine;  // rule: blended, or the one asked for
};

template <typename Probe>
ChangesByRule changes_by_rule(Probe probe, double coarse_step, const char* steps, const char* rule = "blended") {
  const ChangesByRule c{probe("nearest", coarse_step), probe("nearest", 0.1 * coarse_step), probe(rule, coarse_step),
                        probe(rule, 0.1 * coarse_step)};
  WARN("largest change of the wall number density per step, " << steps << ": nearest " << c.nearest_coarse << " / "
                                                              << c.nearest_fine << ", " << rule << " " << c.rule_coarse
                                                              << " / " << c.rule_fine);
  return c;
}

// The wall number density of a particle within 0.5-1.5 l0 of both the bed and the side wall of
// scenes/hydrostatic.json (the tank's bottom-left corner), averaged over 20 x 20 positions in that
// cell, as a multiple of the same average 0.5-1.5 l0 above the bed far from the corner.
double corner_to_bed_ratio(const std::string& corners) {
  const Scene scene = load("hydrostatic.json", {distance_function(corners)});
  WallTreatmentSet set(scene.method_config("mps").wall_treatments, scene);
  const double l0 = scene.particle_spacing;
  const int cells = 20;
  const auto cell_average = [&](Vec2 corner_of_cell) {
    double sum = 0.0;
    for (int a = 0; a < cells; ++a) {
      for (int b = 0; b < cells; ++b) {
        ParticleSet particles;
        particles.add(corner_of_cell + l0 * Vec2((a + 0.5) / cells, (b + 0.5) / cells), Vec2::Zero(),
                      ParticleType::Fluid);
        sum += wall_number_density(scene, set, particles);
      }
    }
    return sum / (cells * cells);
  };
  return cell_average(Vec2(0.025, 0.025)) / cell_average(Vec2(0.15, 0.025));
}

}  // namespace

TEST_CASE("distance function corners: the wall number density is continuous past a convex corner only when blended",
          "[walls][moving]") {
  // As above, by step refinement. Measured: nearest 0.51 at 1 mm and 0.49 at 0.1 mm steps (the
  // gate's bottom passing the particle's rows), blended 0.101 and 0.011: the points of the face's
  // rows hand over to the gate bottom's before they leave the solid.
  const ChangesByRule c = changes_by_rule(largest_change_as_the_gate_lifts, 1e-3, "1 mm / 0.1 mm of lift");
  CHECK(c.nearest_fine > 0.5 * c.nearest_coarse);
  CHECK(c.rule_fine < 0.2 * c.rule_coarse);
}

TEST_CASE("distance function corners: the wall number density is continuous past a concave corner only when blended",
          "[walls][polygon]") {
  // Measured (n0 = 6.54): nearest 1.064 at 0.5 mm and at 0.05 mm (a point of the slope's rows entering at x = 0.1445 m
  // and leaving at 0.156 m, others of 0.16-0.48), blended 0.077 and 0.0078 (with the coverage
  // whole up to the line beyond a segment's end, not by the angle, 0.25 at both steps).
  const ChangesByRule c = changes_by_rule(largest_change_to_the_toe, 5e-4, "0.5 mm / 0.05 mm");
  CHECK(c.nearest_fine > 0.5 * c.nearest_coarse);  // a jump
  CHECK(c.nearest_fine > 0.5);
  CHECK(c.rule_fine < 0.2 * c.rule_coarse);  // continuous: 0.1 for a function with a bounded slope
  CHECK(c.rule_coarse < 0.1);
}

TEST_CASE("distance function corners: the wall number density is continuous past an obstacle's foot only when blended",
          "[walls]") {
  // The obstacle of the dam break stands on the bed with its faces reaching a spacing below the
  // bed's surface, and the bed's surface runs on under it: blended takes the buried parts for no
  // face (find_exposed_pieces), so the bed and the face meet as a concave corner. Measured: nearest
  // 0.456 at 0.5 mm and 0.482 at 0.05 mm steps (a jump at x = 0.4625 m), blended 0.053 and 0.0057;
  // with the buried parts taken for faces, blended jumps by 0.33-0.36 there (the bed's rows
  // handing over to the face's below the bed's surface, where the face's rows stop).
  const ChangesByRule c = changes_by_rule(largest_change_to_the_foot, 5e-4, "0.5 mm / 0.05 mm");
  CHECK(c.nearest_fine > 0.5 * c.nearest_coarse);  // a jump
  CHECK(c.rule_fine < 0.2 * c.rule_coarse);        // continuous
  CHECK(c.rule_coarse < 0.1);
}

TEST_CASE("distance function corners: lattice is continuous into a lattice corner and at a narrow foot", "[walls]") {
  // The tank's bottom-left corner of scenes/hydrostatic.json (surfaces x = y = 0.0125 m) and the
  // left foot of the box on the bed (hydrostatic_box.json, face x = 0.1875 m) are lattice corners
  // with corners = lattice (find_lattice_corners): behind both lines the points of the corner
  // lattice slide with i, the rows reach a step past the ends. Paths: along the bed half a spacing
  // above it (x 0.2 -> 0.025 m), down the diagonal to half a spacing from both walls, to the box's
  // foot along (0.6, -0.8), and to the foot of the dam break's obstacle, 2 l0 wide, whose feet are
  // no lattice corners (its rows reach through it: taken for one, the foot jumps by 0.16).
  // Measured (n0 = 6.54), per 0.5 mm / 0.05 mm: 0.064 / 0.0067, 0.094 / 0.0095, 0.100 / 0.010 and
  // 0.053 / 0.0057 (nearest jumps by 0.16 on the diagonal and 0.53 at the box's foot).
  const auto along = [](const char* scene_name, Vec2 from, Vec2 direction, double length) {
    return [=](const std::string& corners, double step) {
      return largest_change_along(scene_name, corners, from, direction, length, step);
    };
  };
  const Vec2 diagonal = Vec2(-1.0, -1.0).normalized();
  for (const auto& path : {along("hydrostatic.json", Vec2(0.2, 0.025), Vec2(-1.0, 0.0), 0.175),
                           along("hydrostatic.json", Vec2(0.1, 0.1), diagonal, 0.075 * std::sqrt(2.0)),
                           along("hydrostatic_box.json", Vec2(0.15, 0.06), Vec2(0.6, -0.8), 0.045),
                           along("dambreak_obstacle.json", Vec2(0.3, 0.025), Vec2(1.0, 0.0), 0.175)}) {
    const ChangesByRule c = changes_by_rule(path, 5e-4, "0.5 mm / 0.05 mm", "lattice");
    CHECK(c.rule_fine < 0.2 * c.rule_coarse);  // continuous
  }
}

TEST_CASE("distance function corners: lattice reads the spec walls' number density at a right-angled concave corner",
          "[walls]") {
  // corner_to_bed_ratio: the tank's bottom-left corner against the bed. The spec's fixed wall particles read
  // 1.930, the boundary integral 1.910 (the limit of q = 2, 4: 1.920, 1.913). Measured with q = 1:
  // lattice 1.940; blended (each segment's rows by the angle from its end) 1.975, the quadrant's
  // edge cells counted by two sets of rows; nearest 1.888. The bound, 1 %, is the spec lattice's
  // own distance from the integral; blended misses it.
  for (const char* corners : {"lattice", "blended"}) {
    INFO(corners);
    const double ratio = corner_to_bed_ratio(corners);
    WARN(corners << ": corner / bed " << ratio << " (spec walls 1.930)");
    if (std::string(corners) == "lattice")
      CHECK(ratio == Approx(1.930).epsilon(0.01));
    else
      CHECK(ratio > 1.950);
  }
}

TEST_CASE("distance function corners: blended reproduces the lattice number density at rest at every corner",
          "[walls]") {
  // On the initial lattice the rows of the segments that meet at a corner fall on the same
  // points; blended, their shares there add up to 1, so n_i equals the spec walls' value for every
  // fluid particle, to rounding: at the dam break's two tank corners, at the foot and the top of
  // its obstacle (dambreak_obstacle.json: buried face parts and the bed under it), and around the
  // box on the bed (hydrostatic_box.json: two convex, two concave corners; nearest misses by up to
  // 1.1 of n0 = 6.54 at 4 particles there, tested in tests/test_walls.cpp for the tank only).
  const MethodInfo& mps = *registries().methods.find("mps");
  for (const char* name : {"dambreak.json", "dambreak_obstacle.json", "hydrostatic_box.json"})
    for (const char* corners : {"blended", "lattice"}) {
      INFO(name << ", corners " << corners);
      const Scene reference_scene = load(name);
      const Scene distance_scene = load(name, {distance_function(corners)});
      const Simulation reference(reference_scene, mps);
      const Simulation distance(distance_scene, mps);
      REQUIRE(distance.particles().count(ParticleType::Fluid) == reference.particles().count(ParticleType::Fluid));
      double worst = 0.0;
      for (std::size_t i = 0; i < reference.particles().size(); ++i) {  // fluid comes first, in the same order
        if (reference.particles().type[i] != ParticleType::Fluid) continue;
        worst = std::max(worst, std::fabs(distance.particles().field("number_density")[i] -
                                          reference.particles().field("number_density")[i]));
      }
      CHECK(worst < 1e-12);
    }
}

TEST_CASE("distance function corners: blended, a sample stands for the solid that holds it", "[walls][loads]") {
  // The still-water obstacles (tests/still_water_obstacles.hpp): the plate's foot stands on the bed,
  // so the rows of its left face reach into the bed, where the bed's rows cover the same points.
  // Blended, those points count for both; each sample names the solid it lies in: the bed's (-1)
  // below the bed's surface y = 0.0125 m, the plate's (1) in [0.4375, 0.4875] x [0.0125, 0.5125] m.
  const WallTreatmentInfo& model = *registries().walls.find("distance_function");
  const SampleState state =
      sample_state(model, 2.1 * 0.025, {"methods.isph.wall_treatments.distance_function.corners=\"blended\""});
  std::size_t plate = 0, below_bed = 0;
  for (const WallSample& sample : state.samples.samples) {
    const Vec2& x = sample.position;
    INFO("sample at " << x.transpose() << " of obstacle " << sample.obstacle);
    if (x.y() < 0.0125 - 1e-9) {
      ++below_bed;
      CHECK(sample.obstacle == -1);
    }
    if (sample.obstacle == 1) {
      ++plate;
      CHECK((x.x() > 0.4375 && x.x() < 0.4875 && x.y() > 0.0125 && x.y() < 0.5125));
    }
  }
  CHECK(plate > 0);
  CHECK(below_bed > 0);
}

TEST_CASE("distance function corners: blended, MPS's still water over the slope has no velocity spike",
          "[walls][polygon][mps]") {
  // scenes/hydrostatic_slope.json to 1.5 s, four realisations (gravity scaled by 1 + k 1e-10).
  // Every particle must stay slower than sqrt(2 g D) = 2.43 m/s, the speed of a fall through the
  // whole water depth D = 0.3 m, at every step. Measured over 12 realisations: blended 1.54-1.83 m/s
  // (mean kinetic energy over [0.5, 1.5] s 6.9-9.1 J/m), nearest 4.9-228 m/s (13-181 J/m): the
  // points of the slope's rows crossing the line where the nearest segment changes beside the toe
  // kick a particle there (docs/walls.md, "Distance function at corners").
  const MethodInfo& mps = *registries().methods.find("mps");
  for (int k = 0; k < 4; ++k) {
    char gravity[64];
    std::snprintf(gravity, sizeof gravity, "physics.gravity=[0.0, %.17g]", -9.81 * (1.0 + k * 1e-10));
    const Scene scene =
        load("hydrostatic_slope.json", {distance_function("blended"), "time.end_time=1.5", std::string(gravity)});
    Simulation simulation(scene, mps);
    double fastest = 0.0;
    while (simulation.time() < 1.5 - 1e-9) {
      simulation.advance();
      const ParticleSet& p = simulation.particles();
      for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.type[i] == ParticleType::Fluid) fastest = std::max(fastest, p.velocity[i].norm());
      }
    }
    INFO("realisation " << k << ": fastest particle " << fastest << " m/s");
    CHECK(fastest < std::sqrt(2.0 * 9.81 * 0.3));
    CHECK(simulation.monitor().count("penetration") == 0);
  }
}
