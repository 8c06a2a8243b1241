// Corners of the walls (issue 15, item 1; docs/walls.md "Polygon walls", "Corners"): mirror
// particles at a box's convex corners (the box's top corners, fluid around them) and at its
// concave corners with the bed (scenes/hydrostatic_box.json). Before the fix in
// core/walls/mirror_particles.cpp the images of the fluid above the box's top face and of the
// fluid beside its side faces both filled the solid near each top corner (twice the wall's
// number density there), and nothing filled the bed under the box's side faces; ISPH with
// mirror particles then stirred still water up to 0.75 m/s (docs/walls.md).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/run/driver.hpp"
#include "core/walls/wall_geometry.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

namespace {

const std::string kMirror = "methods.mps.wall_treatments={\"mirror_particles\":{}}";

std::vector<double> fluid_number_density(const Simulation& simulation) {
  std::vector<double> n;
  const ParticleSet& particles = simulation.particles();
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] == ParticleType::Fluid) n.push_back(particles.field("number_density")[i]);
  }
  return n;
}

}  // namespace

TEST_CASE("mirror particles at a box's convex and concave corners give the lattice number density",
          "[walls][mirror][corners]") {
  // On the initial lattice the mirror image of every fluid lattice point across a wall surface
  // half a spacing from it is a wall lattice point, so n_i must equal the spec walls' value
  // (every lattice point of the box and of the tank's layers) for every fluid particle, to
  // rounding, with two exceptions that are no corner: mirror particles exist only where there
  // is water to mirror, and the two top-row particles beside the side walls miss the wall
  // points above the free surface, 0.4849242405 of n0 = 6.54 each (the value of
  // tests/test_walls.cpp's dam break). Before the fix (doubled images at the top corners, none
  // in the bed under the box's foot) the worst particle was off by 1.1 (measured).
  const MethodInfo& mps = *registries().methods.find("mps");
  const Scene box_scene = load("hydrostatic_box.json");
  const std::vector<double> expected = fluid_number_density(Simulation(box_scene, mps));
  const Scene mirror_scene = load("hydrostatic_box.json", {kMirror});  // the Simulation keeps a reference
  const Simulation mirrored(mirror_scene, mps);
  CHECK(mirrored.particles().count(ParticleType::Wall) == 0);
  const std::vector<double> n = fluid_number_density(mirrored);
  REQUIRE(n.size() == expected.size());
  double worst = 0.0;
  std::size_t above_surface = 0;
  for (std::size_t i = 0; i < n.size(); ++i) {  // fluid comes first, in the same order
    const double difference = n[i] - expected[i];
    if (std::fabs(difference + 0.4849242405) < 1e-9) {
      ++above_surface;
      continue;
    }
    worst = std::max(worst, std::fabs(difference));
  }
  CHECK(worst < 1e-12);
  CHECK(above_surface == 2u);
}

TEST_CASE("ISPH with mirror particles keeps still water still around a box's corners",
          "[walls][mirror][corners][hydrostatic]") {
  // scenes/hydrostatic_box.json to t = 1 s with isph and mirror_particles: no penetration, no
  // lost particle, and
  //  - the fastest fluid particle over every step below sqrt(2 g l0/2) = 0.495 m/s, the speed of
  //    a fall through half a spacing: water that settles on the lattice moves a fraction of
  //    that (measured 0.307 m/s, in the start-up; 0.06-0.11 m/s in series.csv after 0.3 s).
  //    Before the fix: 0.789 m/s (kinetic energy 1.8 against 0.03 J/m at 1 s).
  //  - each sensor's mean over [0.5, 1] s against rho g h (h below the lattice's top edge, the
  //    top row + l0/2, as tests/test_pressure_sensors.cpp) within [0.88, 1.0]: measured 0.953
  //    (left wall, h = 0.225 m), 0.927 (box top, 0.175 m), 0.946 (box's left face, 0.225 m).
  //    ISPH reads 4-5 % low on the flat tank with every boundary model (0.961 there, the p = 0
  //    of the top particle centres; docs/data/wall_study.md); the envelope is that reading
  //    with 8 points below and none above (an excess at a corner is what the doubled images
  //    produced: 1.0 would be a new error, not the target). Before the fix the box top read
  //    1.055, with swings of +-50 % between series rows.
  const MethodInfo& isph = *registries().methods.find("isph");
  const Scene scene = load("hydrostatic_box.json", {"methods.isph.wall_treatments={\"mirror_particles\":{}}",
                                                    "time.end_time=1.0", "stability.on_divergence=continue"});
  Simulation simulation(scene, isph);
  const double surface = fluid_top(simulation.particles()) + 0.5 * scene.particle_spacing;
  double fastest = 0.0;
  const auto advance_to = [&](double end) {
    while (simulation.time() < end - 1e-9) {
      simulation.advance();
      const ParticleSet& p = simulation.particles();
      for (std::size_t i = 0; i < p.size(); ++i) {
        if (p.type[i] == ParticleType::Fluid) fastest = std::max(fastest, p.velocity[i].norm());
      }
    }
  };
  advance_to(0.5);
  simulation.pressure_sensors().take_row(simulation.particles());
  advance_to(1.0);
  const std::vector<double> row = simulation.pressure_sensors().take_row(simulation.particles());
  const auto& sensors = scene.diagnostics.pressure_sensors;
  REQUIRE(sensors.size() == 3);
  for (std::size_t k = 0; k < sensors.size(); ++k) {
    const double ratio = row[2 * k] / (scene.physics.density * 9.81 * (surface - sensors[k].position.y()));
    INFO("sensor " << sensors[k].name);
    WARN("isph / mirror_particles on the box: sensor " << sensors[k].name << " mean / rho g h = " << ratio);
    CHECK(ratio > 0.88);
    CHECK(ratio < 1.0);
  }
  WARN("isph / mirror_particles on the box: fastest particle " << fastest << " m/s");
  CHECK(fastest < std::sqrt(9.81 * scene.particle_spacing));  // sqrt(2 g l0/2), m/s
  CHECK(simulation.monitor().count("penetration") == 0);
  CHECK(simulation.particles().count(ParticleType::Ghost) == 0);
}
