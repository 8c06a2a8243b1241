// The pressure a wall sample extends (core/walls/wall_sample_pressure.hpp; parameter
// wall_sample_pressure of isph and eisph): the linear MLS fit (FIT) about the source particle on
// the still-water lattice, and how isph's pressure gradient uses it.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstddef>
#include <string>
#include <vector>

#include "core/walls/wall_sample_pressure.hpp"
#include "isph_still_tank.hpp"
#include "methods/isph/isph_operators.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

namespace {

// The fluid particle nearest to `point`.
std::size_t fluid_nearest(const ParticleSet& particles, const Vec2& point) {
  std::size_t best = 0;
  double distance = 1e300;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] != ParticleType::Fluid) continue;
    const double d = (particles.position[i] - point).norm();
    if (d < distance) {
      distance = d;
      best = i;
    }
  }
  return best;
}

// The tank's three kinds of stencil: inside, in the column beside the left wall, on the top row.
struct Stencils {
  std::size_t inside, beside_wall, surface;
};

Stencils stencils(const Tank& tank) {
  return {fluid_nearest(tank.particles, Vec2(0.2375, 0.1375)), fluid_nearest(tank.particles, Vec2(0.0125, 0.1375)),
          fluid_nearest(tank.particles, Vec2(0.2375, tank.top))};
}

double weight(const Tank& tank, double r) { return tank.kernel.value(r); }

}  // namespace

TEST_CASE("wall sample pressure: (FIT) reproduces any linear field, whatever its gradient", "[unit][isph][walls]") {
  // a + b . x with a gradient 40 times the hydrostatic one and tilted (an impact's, not the rest
  // state's): the fit returns it at x_s to round-off inside, beside the wall and on the surface,
  // where the stencil is cut in half. The Shepard mean (a fit of order 0) would be off there by
  // b . (x_s - centroid), a third of a spacing times the gradient.
  const auto tank = still_tank("dummy_layers");
  std::vector<double> pressure(tank->particles.size());
  const Vec2 gradient(3.0e5, -4.0e5);  // Pa/m
  for (std::size_t i = 0; i < pressure.size(); ++i) pressure[i] = 2.0e4 + gradient.dot(tank->particles.position[i]);
  const auto w = [&](double r) { return weight(*tank, r); };
  const Stencils s = stencils(*tank);
  for (std::size_t i : {s.inside, s.beside_wall, s.surface}) {
    CAPTURE(i, tank->particles.position[i].transpose());
    CHECK(fitted_pressure(tank->particles, tank->neighbours, w, pressure, i) ==
          Approx(pressure[i]).epsilon(1e-12).margin(1e-7));
  }
}

TEST_CASE("wall sample pressure: (FIT) passes on a symmetric stencil W(0) / sum W of the particle's own deviation",
          "[unit][isph][walls]") {
  // Hydrostatic pressure with the inside particle's own value raised by dp: on the lattice's
  // symmetric stencil the moment matrix is diagonal, so the fit's constant is the weighted mean and
  // keeps W(0) / (W(0) + sum_j W_ij) of dp: 0.316 for the cubic spline at h = 1.2 l0 (the samples'
  // own pressure kept all of it). Beside the wall the stencil is cut and the fit's gradient takes up
  // part of dp: 0.552 of it stays (measured; the lattice fixes it to the digits given).
  const auto tank = still_tank("dummy_layers");
  std::vector<double> pressure = hydrostatic(tank->particles, tank->top, 0.5 * 0.025);
  const auto w = [&](double r) { return weight(*tank, r); };
  const Stencils s = stencils(*tank);
  const double dp = 50.0;  // Pa
  double weights = w(0.0);
  for (std::uint32_t k = tank->neighbours.begin(s.inside); k < tank->neighbours.end(s.inside); ++k) {
    const std::uint32_t j = tank->neighbours.indices[k];
    if (tank->particles.type[j] == ParticleType::Fluid) {
      weights += w((tank->particles.position[j] - tank->particles.position[s.inside]).norm());
    }
  }
  for (std::size_t i : {s.inside, s.beside_wall}) {
    std::vector<double> raised = pressure;
    raised[i] += dp;
    const double share = (fitted_pressure(tank->particles, tank->neighbours, w, raised, i) - pressure[i]) / dp;
    CAPTURE(i, share);
    if (i == s.inside) {
      CHECK(share == Approx(w(0.0) / weights).epsilon(1e-9));
      CHECK(share == Approx(0.316).margin(0.001));
    } else {
      CHECK(share == Approx(0.552).margin(0.001));
    }
  }
}

TEST_CASE("wall sample pressure: where the fit is singular the particle keeps its own pressure",
          "[unit][isph][walls]") {
  // A horizontal row of five particles: every neighbour lies on the line y = 0, the moment matrix's
  // y row is zero (its diagonal's product 0): p_s itself, exactly.
  ParticleSet row;
  for (int k = 0; k < 5; ++k) row.add(Vec2(0.025 * k, 0.0), Vec2::Zero(), ParticleType::Fluid);
  const SphKernel kernel(SphKernelKind::CubicSpline, 2.4 * 0.025);
  const NeighbourList neighbours = find_neighbours(row.position, row.type, kernel.support());
  const std::vector<double> pressure = {100.0, 250.0, 90.0, 310.0, 120.0};
  const auto w = [&](double r) { return kernel.value(r); };
  CHECK(fitted_pressure(row, neighbours, w, pressure, 2) == pressure[2]);
  std::vector<double> fitted;
  fit_source_pressures(row, neighbours, w, pressure, fitted);
  CHECK(fitted == pressure);
  // The same row along the diagonal: no zero row in the moment matrix now (M11 = M22 > 0), but its
  // determinant is round-off (the neighbours are collinear): the threshold, not the diagonal, keeps p_s.
  ParticleSet diagonal;
  for (int k = 0; k < 5; ++k) diagonal.add(Vec2(0.018 * k, 0.018 * k), Vec2::Zero(), ParticleType::Fluid);
  const NeighbourList diagonal_neighbours = find_neighbours(diagonal.position, diagonal.type, kernel.support());
  CHECK(fitted_pressure(diagonal, diagonal_neighbours, w, pressure, 2) == pressure[2]);
  CHECK(fitted_pressure(diagonal, diagonal_neighbours, w, pressure, 1) == pressure[1]);
}

TEST_CASE("wall sample pressure: the normalised determinant of the lattice's stencils", "[unit][isph][walls]") {
  // What kMinimumFitDeterminant (0.01) is set against: det M / (M00 M11 M22) is 1 inside the fluid
  // (M diagonal), and the cut stencils beside the wall and under the surface (measured 0.730 each)
  // and in the corner (0.526) stay far above the threshold, so the fit holds wherever the water is
  // more than a sheet.
  const auto tank = still_tank("dummy_layers");
  const Stencils s = stencils(*tank);
  const std::size_t corner = fluid_nearest(tank->particles, Vec2(0.0125, tank->top));
  auto normalised_determinant = [&](std::size_t i) {
    Eigen::Matrix3d moment = Eigen::Matrix3d::Zero();
    moment(0, 0) = weight(*tank, 0.0);
    for (std::uint32_t k = tank->neighbours.begin(i); k < tank->neighbours.end(i); ++k) {
      const std::uint32_t j = tank->neighbours.indices[k];
      if (tank->particles.type[j] != ParticleType::Fluid) continue;
      const Vec2 d = tank->particles.position[j] - tank->particles.position[i];
      const Eigen::Vector3d b(1.0, d.x(), d.y());
      moment += weight(*tank, d.norm()) * b * b.transpose();
    }
    return moment.determinant() / (moment(0, 0) * moment(1, 1) * moment(2, 2));
  };
  CHECK(normalised_determinant(s.inside) == Approx(1.0).epsilon(1e-9));
  for (std::size_t i : {s.beside_wall, s.surface, corner}) {
    CAPTURE(i, normalised_determinant(i));
    CHECK(normalised_determinant(i) > 10.0 * kMinimumFitDeterminant);
    CHECK(normalised_determinant(i) < 1.0);
  }
}

TEST_CASE("wall sample pressure: isph's symmetric wall pairs extend the fit, its difference pairs the own pressure",
          "[unit][isph][walls]") {
  // The particle beside the wall with its own pressure raised by dp over the hydrostatic field. With
  // "fitted" the samples of its symmetric pairs carry p~_s + rho0 g . (x_w - x_s) instead of
  // p_s + rho0 g . (x_w - x_s): the acceleration changes by exactly
  //   -sum_w m V_w (p~_s - p_s) / rho0^2 grad W_iw
  // over its wet samples (nothing else: the pair's p_i and every fluid pair are unchanged). A
  // difference-form pair (m/rho^2)(p_w - p_i) grad W has no term in p_i's own deviation to filter
  // and keeps the own pressure: with "difference" the two accelerations are equal.
  const auto tank = still_tank("dummy_layers");
  ParticleSet& particles = tank->particles;
  particles.pressure = hydrostatic(particles, tank->top, 0.5 * 0.025);
  const std::size_t i = stencils(*tank).beside_wall;
  particles.pressure[i] += 50.0;  // Pa
  const double mass = kRho / lattice_kernel_sum(tank->kernel, 0.025);
  const std::vector<double> density(particles.size(), kRho);
  const std::vector<double> surface = top_row(particles, tank->top);
  std::vector<double> fitted;
  const isph::SamplePressure own{kRho, Vec2(0.0, -kG), true, true};
  const isph::SamplePressure fit =
      isph::with_source_pressure(own, particles, tank->neighbours, tank->samples, tank->kernel, true, fitted);
  REQUIRE(fit.source_pressure == &fitted);
  auto acceleration = [&](const isph::SamplePressure& rule, isph::PressureGradientForm form) {
    std::vector<Vec2> a;
    isph::pressure_acceleration(particles, tank->neighbours, tank->samples, rule, tank->kernel, mass, density, surface,
                                form, a);
    return a[i];
  };
  const auto symmetric = isph::PressureGradientForm::Symmetric;
  Vec2 expected = Vec2::Zero();
  for (std::uint32_t k = tank->samples.begin(i); k < tank->samples.end(i); ++k) {
    const WallSample& wall = tank->samples.samples[k];
    expected -= mass * wall.volume * (fitted[i] - particles.pressure[i]) / (kRho * kRho) *
                tank->kernel.gradient(particles.position[i] - wall.position);
  }
  REQUIRE(std::fabs(fitted[i] - particles.pressure[i]) > 10.0);  // the fit filters most of the 50 Pa
  REQUIRE(expected.norm() > 0.01);                               // m/s^2: a wall push worth testing
  const Vec2 change = acceleration(fit, symmetric) - acceleration(own, symmetric);
  CHECK(change.x() == Approx(expected.x()).epsilon(1e-9));
  CHECK(change.y() == Approx(expected.y()).margin(1e-9 * expected.norm()));
  const auto difference = isph::PressureGradientForm::Difference;
  CHECK((acceleration(fit, difference) - acceleration(own, difference)).norm() < 1e-12);
  // Without wall samples (wall particles) the rule is left as it was.
  std::vector<double> unused;
  CHECK(isph::with_source_pressure(own, particles, tank->neighbours, WallSampleList{}, tank->kernel, true, unused)
            .source_pressure == nullptr);
  CHECK(isph::with_source_pressure(own, particles, tank->neighbours, tank->samples, tank->kernel, false, unused)
            .source_pressure == nullptr);
}

TEST_CASE("wall sample pressure: the dry-wall test reads the same fitted p_w as the pair", "[unit][isph][walls]") {
  // The top-row particle beside the wall on a hydrostatic field whose zero lies 1.5 l0 above the
  // row (368 Pa at the row), its own pressure lowered to 240 Pa, below the head of one spacing,
  // rho g l0 = 245 Pa. The wall points a spacing above it then have p_w = 240 - 245 < 0 with the own
  // pressure (dry), and with the fit, p_w > 0 (wet): the test follows the pressure the pair uses. (At
  // this corner of the water the stencil is cut on two sides and the fit keeps 0.92 of the
  // particle's deviation: measured 200 Pa -> 213.8 Pa.)
  const auto tank = still_tank("dummy_layers");
  ParticleSet& particles = tank->particles;
  particles.pressure = hydrostatic(particles, tank->top, 1.5 * 0.025);
  const std::size_t i = fluid_nearest(particles, Vec2(0.0125, tank->top));
  particles.pressure[i] = 240.0;  // Pa
  std::vector<double> fitted;
  const isph::SamplePressure own{kRho, Vec2(0.0, -kG), true, true};
  const isph::SamplePressure fit =
      isph::with_source_pressure(own, particles, tank->neighbours, tank->samples, tank->kernel, true, fitted);
  REQUIRE(fitted[i] > 0.0);
  int changed = 0;
  for (std::uint32_t k = tank->samples.begin(i); k < tank->samples.end(i); ++k) {
    const WallSample& wall = tank->samples.samples[k];
    if (wall.position.y() <= particles.position[i].y() + 0.5 * 0.025) continue;  // a spacing above i and more
    CHECK(own.excludes_sample(particles, i, wall));
    const bool wet = fit.wall_pressure(particles, wall) > 0.0;
    CHECK(fit.excludes_sample(particles, i, wall) == !wet);
    if (wet) ++changed;
  }
  CHECK(changed > 0);  // the points a spacing above i are wet with the fit
}
