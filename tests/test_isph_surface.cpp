// The water surface beyond the free-surface particles (methods/isph/isph_surface.hpp, parameter
// free_surface_offset of isph): (SURF) on the still-water lattice with every boundary model, the
// rows it adds to the PPE, and the hydrostatic pressure it gives at the wall sensors.
#include <catch2/catch.hpp>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "core/io/geometry.hpp"
#include "core/walls/wall_treatment.hpp"
#include "isph_still_tank.hpp"
#include "methods/isph/isph_operators.hpp"
#include "methods/isph/isph_pressure.hpp"
#include "methods/isph/isph_surface.hpp"
#include "still_water_sensors.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

const std::vector<std::string> kModels = {"adami_wall_particles", "dummy_layers", "mirror_particles",
                                          "distance_function"};

TEST_CASE("isph water surface: (SURF) is exact under the flat surface of the lattice - every boundary model",
          "[unit][isph][surface]") {
  // On the still-water lattice every top-row particle gets a factor, and (SURF) of the hydrostatic
  // field under a surface delta = l0/2 above the row returns rho g delta to round-off (1e-9): the
  // field is linear along the vertical normal. At the contact line (the columns next to the side
  // walls) the normal is vertical only if the wall points above the particle are left out: with
  // them the particle read 1.19 rho g delta (measured). d_i = 0.57 l0 in the open (factor
  // 6.9e-4 m^2), more next to a wall (fewer fluid neighbours beside it).
  for (const std::string& model : kModels) {
    INFO("boundary model " << model);
    const auto t = still_tank(model);
    const double l0 = 0.025, delta = 0.5 * l0;
    const std::vector<double> surface = top_row(t->particles, t->top);
    std::vector<double> factor;
    isph::water_surface_factors(t->particles, t->neighbours, t->samples, t->kernel, t->scene.physics.gravity, surface,
                                delta, l0, factor);
    const std::vector<double> p = hydrostatic(t->particles, t->top, delta);
    std::size_t rows = 0;
    for (std::size_t i = 0; i < p.size(); ++i) {
      if (surface[i] == 0.0) {
        CHECK(factor[i] == 0.0);
        continue;
      }
      ++rows;
      INFO("x = " << t->particles.position[i].x() << " m");
      REQUIRE(factor[i] > 0.0);
      const double got = isph::water_surface_pressure(t->particles, t->neighbours, t->kernel, factor[i], i, p);
      CHECK(got == Approx(kRho * kG * delta).epsilon(1e-9));
    }
    CHECK(rows == 19);
    // Offset 0 is Shao & Lo's condition: no factor anywhere.
    isph::water_surface_factors(t->particles, t->neighbours, t->samples, t->kernel, t->scene.physics.gravity, surface,
                                0.0, l0, factor);
    for (const double f : factor) CHECK(f == 0.0);
  }
}

TEST_CASE("isph water surface: the contact line's factor does not jump as the particle crosses the wall row's level",
          "[unit][isph][surface]") {
  // The top row of still water stands level with a row of wall points, and jitters about it by
  // ~1e-5 m. The top-row particle next to the left wall, moved by -1e-6 and +1e-6 m along y: its
  // factor of (SURF) must change by the derivative times the move, not jump. A cut at "level"
  // (a point counted when level or below, else dry) switched that row in and out of the normal:
  // the factor jumped by 19.7 % with every model (measured; in a run the pressure near the wall
  // jumped with it by 10-25 Pa from one step to the next). With the wet share (1 - Delta/l0 for a
  // point Delta above) the change is the share's slope times the move: 0.82-0.86e-4 measured,
  // about 2e-6 m / l0 = 0.8e-4 of one row's weight; the bound 1e-3 is ten times that.
  const double l0 = 0.025, delta = 0.5 * l0, move = 1e-6;
  for (const std::string& model : kModels) {
    INFO("boundary model " << model);
    const auto t = still_tank(model);
    std::size_t corner = t->particles.size();
    for (std::size_t i = 0; i < t->particles.size(); ++i) {
      const Vec2& x = t->particles.position[i];
      if (t->particles.type[i] != ParticleType::Fluid || x.y() < t->top - 1e-9) continue;
      if (corner == t->particles.size() || x.x() < t->particles.position[corner].x()) corner = i;
    }
    REQUIRE(corner < t->particles.size());
    const std::vector<double> surface = top_row(t->particles, t->top);
    std::vector<double> factors;
    for (const double dy : {-move, move}) {
      ParticleSet moved = t->particles;
      moved.position[corner].y() += dy;
      std::vector<double> factor;
      isph::water_surface_factors(moved, t->neighbours, t->samples, t->kernel, t->scene.physics.gravity, surface, delta,
                                  l0, factor);
      factors.push_back(factor[corner]);
    }
    REQUIRE(factors[0] > 0.0);
    CHECK(std::fabs(factors[1] / factors[0] - 1.0) < 1e-3);
  }
}

TEST_CASE("isph water surface: a sheet one particle thick keeps p = 0 at its centres", "[unit][isph][surface]") {
  // A row of 12 fluid particles, all on the surface, nothing beneath: d_i = 0 < 0.25 l0 (its
  // neighbours lie beside it, not beneath), so no particle but the two tips gets a factor (a tip's
  // normal points along the row, its neighbours lie behind it; it then extrapolates from held
  // particles, p = 0). Two rows: each row has the other beneath it (d_i > 0.25 l0).
  const double l0 = 0.025;
  const SphKernel kernel(SphKernelKind::CubicSpline, 2.4 * l0);
  for (const int rows : {1, 2}) {
    ParticleSet sheet;
    for (int r = 0; r < rows; ++r) {
      for (int k = 0; k < 12; ++k) sheet.add(Vec2(k * l0, r * l0), Vec2::Zero(), ParticleType::Fluid);
    }
    const NeighbourList neighbours = find_neighbours(sheet.position, sheet.type, kernel.support());
    const std::vector<double> surface(sheet.size(), 1.0);
    std::vector<double> factor;
    isph::water_surface_factors(sheet, neighbours, isph::no_wall_samples(), kernel, Vec2(0.0, -9.81), surface, 0.5 * l0,
                                l0, factor);
    for (std::size_t i = 0; i < sheet.size(); ++i) {
      INFO(rows << " rows, particle " << i);
      const bool tip = i % 12 == 0 || i % 12 == 11;
      CHECK((factor[i] > 0.0) == (rows == 2 || tip));
    }
  }
}

TEST_CASE("isph water surface: the PPE's surface rows - hydrostatic residual 0, diagonally dominant",
          "[unit][isph][surface]") {
  // scenes/hydrostatic.json's lattice with the top row on the surface and surface_offset = l0/2:
  // each top-row particle is an unknown (19 more than with p = 0 at the centres), its row
  // (SURF) is satisfied by the hydrostatic field to round-off, its diagonal is 1 and its other
  // entries are negative and sum to -delta/(delta + d_i), in (-2/3, 0) (d_i >= l0/4).
  for (const std::string& model : kModels) {
    INFO("boundary model " << model);
    const auto t = still_tank(model);
    const double l0 = 0.025, delta = 0.5 * l0;
    ParticleSet particles = t->particles;
    const std::vector<double> surface = top_row(particles, t->top);
    const std::vector<double> rest(particles.size(), kRho), source(particles.size(), 0.0);
    isph::PressureSolveSettings settings;
    settings.spacing = l0;
    settings.mass = kRho / lattice_kernel_sum(t->kernel, l0);
    settings.surface_offset = delta;
    isph::PressurePoissonSolver solver;
    const auto result =
        solver.assemble(particles, t->neighbours, t->samples, t->kernel, rest, surface, source, settings);
    CHECK(result.surface == 19);
    CHECK(result.surface_unknowns == 19);
    CHECK(result.fluid_unknowns == 19 * 11);
    CHECK(result.ungrounded_groups == 0);
    const std::vector<double> p = hydrostatic(particles, t->top, delta);
    const auto matrix = solver.matrix();
    std::size_t checked = 0;
    for (std::size_t row = 0; row < solver.particle_of_row().size(); ++row) {
      const auto i = static_cast<std::size_t>(solver.particle_of_row()[row]);
      if (surface[i] == 0.0) continue;
      double product = 0.0, off_diagonal = 0.0, diagonal = 0.0;
      for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(matrix, static_cast<Eigen::Index>(row)); it;
           ++it) {
        const auto j = static_cast<std::size_t>(solver.particle_of_row()[static_cast<std::size_t>(it.col())]);
        product += it.value() * p[j];
        if (j == i) {
          diagonal += it.value();
        } else {
          CHECK(it.value() < 0.0);
          off_diagonal += it.value();
        }
      }
      CHECK(diagonal == 1.0);
      CHECK(off_diagonal > -2.0 / 3.0);
      CHECK(off_diagonal < 0.0);
      CHECK(std::fabs(product - solver.rhs()[static_cast<Eigen::Index>(row)]) < 1e-9 * kRho * kG * delta);
      ++checked;
    }
    CHECK(checked == 19);
  }
}

TEST_CASE("isph water surface: still water reads rho g h at the wall - every boundary model",
          "[isph][validation][sensor]") {
  // scenes/hydrostatic.json with free_surface_offset = 0.5, the sensors' mean over [0.5, 1.5] s
  // (still_water_sensors.hpp). Measured, h = 0.225 / 0.15 / 0.075 m: adami_wall_particles
  // 1.0022 / 0.9982 / 0.9849, dummy_layers 1.0033 / 0.9974 / 0.9844, mirror_particles 1.0055 /
  // 1.0038 / 0.9980, distance_function 1.0008 / 0.9935 / 0.9762 (9 of 12 within 1 %). With p = 0
  // at the centres (offset 0) every sensor reads rho g (h - l0/2): 0.95 / 0.92 / 0.83, which this
  // fails. The three misses are the shallow sensor, 3 l0 beneath the surface, with the no-slip
  // models: the walls' negative pressure above the water (the hydrostatic extension) is clamped
  // to 0, so the water at the contact line sinks and stirs (without that clamp all 12 are within
  // 1 %, but the dam breaks diverge: docs/methods/isph.md, "The water surface"); there the
  // half-second means scatter by 1-1.5 % (distance_function 0.981 over [0.5, 1] s, 0.971 over
  // [1, 1.5] s). Bound: 3 %, the largest measured deviation (2.4 %) with room for that scatter;
  // the 1 % target is reported.
  const auto within = [](const std::string& model, double depth, double ratio) {
    INFO("boundary model " << model << ", h = " << depth << " m: mean / rho g h = " << ratio);
    CHECK(std::fabs(ratio - 1.0) < 0.03);
    CHECK_NOFAIL(std::fabs(ratio - 1.0) < 0.01);  // the target, reported
  };
  still_water_wall_sensors("isph", {"methods.isph.free_surface_offset=0.5"}, 1.5, within);
  // The tank accelerating upward at a = g/2 (tests/test_pressure_sensors.cpp): p = rho (g + a) h.
  // Measured: 1.001 / 0.995 / 0.977, 1.003 / 0.997 / 0.984, 1.006 / 1.004 / 0.998, 1.000 / 0.993 /
  // 0.977 (the models in the order above; 9 of 12 within 1 %).
  still_water_wall_sensors("isph", {"methods.isph.free_surface_offset=0.5"}, 1.5, within, 1.5 * 9.81);
}

TEST_CASE("isph dry wall points: which wall points dry_wall_points \"excluded\" leaves out", "[unit][isph][surface]") {
  // A wall point is dry for fluid particle i when it lies above i (against gravity) and its pressure
  // is not above 0: the air above the water. Beside or below i, or with a positive pressure, it is
  // wet; without gravity nothing is above; with the rule off nothing is left out.
  const Vec2 x_i(0.1, 0.2);
  const isph::SamplePressure excluded{kRho, Vec2(0.0, -kG), true, true};
  const isph::SamplePressure clamped{kRho, Vec2(0.0, -kG), true, false};
  const isph::SamplePressure weightless{kRho, Vec2::Zero(), true, true};
  const Vec2 above = x_i + Vec2(0.01, 0.02), beside = x_i + Vec2(0.025, 0.0), below = x_i + Vec2(0.0, -0.025);
  CHECK(excluded.dry_rule().excludes(x_i, above, 0.0));
  CHECK(excluded.dry_rule().excludes(x_i, above, -50.0));
  CHECK_FALSE(excluded.dry_rule().excludes(x_i, above, 1.0));
  CHECK_FALSE(excluded.dry_rule().excludes(x_i, beside, -50.0));
  CHECK_FALSE(excluded.dry_rule().excludes(x_i, below, -50.0));
  CHECK_FALSE(clamped.dry_rule().excludes(x_i, above, -50.0));
  CHECK_FALSE(weightless.dry_rule().excludes(x_i, above, -50.0));
}
