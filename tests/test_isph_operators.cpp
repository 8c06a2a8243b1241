// ISPH operators (methods/isph/isph_operators.hpp) on fields with known derivatives, and the
// rows of the assembled pressure Poisson matrix.
#include <cmath>

#include <catch2/catch.hpp>

#include "core/search/neighbour_search.hpp"
#include "methods/isph/isph_operators.hpp"
#include "methods/isph/isph_pressure.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::isph;

namespace {

constexpr double kRestDensity = 1000.0;

// A (2 half_width + 1)^2 block of fluid on the lattice; particle `centre` has full support.
struct Block {
  ParticleSet particles;
  std::size_t centre = 0;
};

Block lattice_block(double l0, int half_width, int rows_above_centre) {
  Block block;
  for (int j = -half_width; j <= rows_above_centre; ++j) {
    for (int i = -half_width; i <= half_width; ++i) {
      if (i == 0 && j == 0) block.centre = block.particles.size();
      block.particles.add(Vec2(0.3 + i * l0, 0.2 + j * l0), Vec2::Zero(), ParticleType::Fluid);
    }
  }
  return block;
}

// The Cummins & Rudman Laplacian of p = a x^2 + b y^2 at a particle with full support, summed
// directly over the lattice offsets (no particles, no neighbour list): with rho_i = rho_j = rho0
// and m = rho0 / sum W, a_ij = (2 m / rho0^2) (-r W'(r)) / (r^2 + eta^2).
double lattice_laplacian_of_quadratic(const SphKernel& kernel, double l0, double eta2, double a, double b) {
  const double mass = kRestDensity / lattice_kernel_sum(kernel, l0);
  const int reach = static_cast<int>(std::ceil(kernel.support() / l0));
  double sum = 0.0;
  for (int j = -reach; j <= reach; ++j) {
    for (int i = -reach; i <= reach; ++i) {
      const double dx = i * l0, dy = j * l0, r = std::hypot(dx, dy);
      if (r == 0.0 || r >= kernel.support()) continue;
      sum += 2.0 * mass / (kRestDensity * kRestDensity) * (-r * kernel.derivative(r)) / (r * r + eta2) *
             (a * dx * dx + b * dy * dy);
    }
  }
  return sum;
}

}  // namespace

TEST_CASE("ISPH PPE Laplacian of a quadratic pressure on the lattice", "[isph]") {
  // p = x^2 + 3 y^2 (offset to the block's centre): div(grad p / rho0) = 8 / rho0 exactly.
  // The discrete operator sums (p_j - p_i) a_ij: the linear part of p cancels by the lattice's
  // symmetry, the quadratic part gives 8/rho0 times the lattice quadrature of the kernel's
  // second moment, 1/2 sum_j V_j (-W'(r_j)) r_j^3 / (r_j^2 + eta^2), instead of its integral 1.
  // Two sources of error, both computed here for the cubic spline (python, same sums):
  //   eta^2 = (0.1 h)^2 lowers each pair by eta^2/(r^2 + eta^2) <= 1.4 % (r = l0, h = 1.2 l0);
  //   the lattice quadrature of the moment is within 1.1 % of the integral for h = 1.2-1.5 l0.
  // Measured totals: 0.9809 (h = 1.2), 0.9999 (1.3), 0.9918 (1.5); Wendland C2 at h = 1.5:
  // 0.9798. Tolerance 2.5 %: the sum of the two bounds. (Wendland C2 at h = 1.2 l0 is 6 %
  // low: its support 2.4 l0 is too narrow for it, one reason the default is the cubic spline.)
  const double l0 = 0.025;
  struct Case {
    SphKernelKind kind;
    double h_over_l0;
  };
  for (const Case& c : {Case{SphKernelKind::CubicSpline, 1.2}, Case{SphKernelKind::CubicSpline, 1.3},
                        Case{SphKernelKind::CubicSpline, 1.5}, Case{SphKernelKind::WendlandC2, 1.5}}) {
    const SphKernel kernel(c.kind, 2.0 * c.h_over_l0 * l0);
    const double mass = kRestDensity / lattice_kernel_sum(kernel, l0);
    const double eta2 = std::pow(0.1 * c.h_over_l0 * l0, 2);
    Block block = lattice_block(l0, 6, 6);
    auto& p = block.particles;
    const Vec2 origin = p.position[block.centre];
    std::vector<double> field(p.size()), density(p.size(), kRestDensity), laplacian;
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Vec2 d = p.position[i] - origin;
      field[i] = 5.0 + 2.0 * d.x() - d.y() + d.x() * d.x() + 3.0 * d.y() * d.y();
    }
    const NeighbourList list = find_neighbours(p.position, p.type, kernel.support());
    ppe_laplacian(p, list, kernel, mass, density, eta2, field, laplacian);
    const double value = laplacian[block.centre];
    INFO("kernel " << static_cast<int>(c.kind) << ", h = " << c.h_over_l0 << " l0: lap = " << value * kRestDensity / 8.0
                   << " x 8/rho0");
    // The implementation sums exactly the lattice formula (neighbour list, ghosts, indices).
    CHECK(value == Approx(lattice_laplacian_of_quadratic(kernel, l0, eta2, 1.0, 3.0)).epsilon(1e-10));
    CHECK(value == Approx(8.0 / kRestDensity).epsilon(0.025));
    // A linear field has zero Laplacian (by the lattice's symmetry, to round-off).
    for (std::size_t i = 0; i < p.size(); ++i) field[i] = 7.0 + 3.0 * p.position[i].x() - 2.0 * p.position[i].y();
    ppe_laplacian(p, list, kernel, mass, density, eta2, field, laplacian);
    CHECK(std::fabs(laplacian[block.centre]) < 1e-9 * 8.0 / kRestDensity);
  }
}

TEST_CASE("ISPH PPE matrix rows are the Laplacian scaled to pascals - a ghost is no neighbour", "[isph]") {
  // Fluid row i of A p = b reads rho0 l0^2 sum_j a_ij (p_i - p_j) = -rho0 l0^2 S_i: applied to
  // the unknowns' values of a quadratic field, a row whose neighbours are all unknowns must
  // give -rho0 l0^2 <lap p>_i (to round-off), and b_i = -rho0 l0^2 S_i.
  const double l0 = 0.025;
  const SphKernel kernel(SphKernelKind::CubicSpline, 2.4 * l0);
  const double mass = kRestDensity / lattice_kernel_sum(kernel, l0);
  const double eta2 = std::pow(0.12 * l0, 2);
  Block block = lattice_block(l0, 6, 6);
  auto& p = block.particles;
  const Vec2 origin = p.position[block.centre];
  std::vector<double> surface(p.size(), 0.0), source(p.size(), 0.0), field(p.size()), density(p.size(), kRestDensity);
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec2 d = (p.position[i] - origin) / l0;
    if (std::max(std::fabs(d.x()), std::fabs(d.y())) > 5.5) surface[i] = 1.0;  // outer ring: Dirichlet
    field[i] = 1000.0 * (d.x() * d.x() + 3.0 * d.y() * d.y());
    source[i] = 123.0 + static_cast<double>(i);
  }
  const NeighbourList list = find_neighbours(p.position, p.type, kernel.support());
  PressureSolveSettings settings;
  settings.rest_density = kRestDensity;
  settings.spacing = l0;
  settings.mass = mass;
  settings.eta2 = eta2;
  PressurePoissonSolver solver;
  const PressureSolveResult result = solver.solve(p, list, kernel, density, surface, source, settings);
  CHECK(result.fluid_unknowns == 11u * 11u);
  CHECK(result.surface == p.size() - 11u * 11u);
  CHECK(result.wall_unknowns == 0u);
  CHECK(result.converged);

  std::vector<double> laplacian;
  ppe_laplacian(p, list, kernel, mass, density, eta2, field, laplacian);
  Eigen::VectorXd unknowns(static_cast<Eigen::Index>(solver.particle_of_row().size()));
  for (std::size_t row = 0; row < solver.particle_of_row().size(); ++row) {
    unknowns[static_cast<Eigen::Index>(row)] = field[static_cast<std::size_t>(solver.particle_of_row()[row])];
  }
  const Eigen::VectorXd product = solver.matrix() * unknowns;
  const double scale = kRestDensity * l0 * l0;
  const int row = solver.row_of_particle()[block.centre];
  REQUIRE(row >= 0);
  CHECK(product[row] == Approx(-scale * laplacian[block.centre]).epsilon(1e-12));
  CHECK(solver.rhs()[row] == Approx(-scale * source[block.centre]).epsilon(1e-12));

  // A neighbour that has become a ghost since the list was built does not enter the row.
  const std::size_t next = block.centre + 1;
  p.type[next] = ParticleType::Ghost;
  solver.solve(p, list, kernel, density, surface, source, settings);
  const int row_after = solver.row_of_particle()[block.centre];
  REQUIRE(row_after >= 0);
  CHECK(solver.row_of_particle()[next] == -1);
  double diagonal_before = 0.0, diagonal_after = solver.matrix().coeff(row_after, row_after);
  const auto pair = [&](std::size_t j) {
    const double factor = laplacian_pair_factor(kernel, p.position[block.centre] - p.position[j], eta2);
    return scale * ppe_pair_coefficient(mass, kRestDensity, kRestDensity, factor);
  };
  for (std::uint32_t k = list.begin(block.centre); k < list.end(block.centre); ++k)
    diagonal_before += pair(list.indices[k]);
  CHECK(diagonal_after == Approx(diagonal_before - pair(next)).epsilon(1e-12));
}

TEST_CASE("ISPH pressure gradient on a free surface: renormalised exact - symmetric form half", "[isph]") {
  // Hydrostatic p = rho0 g (y_top - y) on a block whose top row is the free surface (p = 0).
  // At a surface particle the support is cut in half. The renormalised gradient (Bonet & Lok
  // 1999) is exact for a linear p whatever the support: a = -grad p / rho0 = (0, g) to
  // round-off. The symmetric form sum_j m p_j / rho0^2 grad W_ij sees half the kernel and gives
  // about g/2 (the lattice's half-plane moment, 0.5 +- 0.05): why surface particles use the
  // renormalised form by default (symmetric_corrected_surface). Inside, with full support, all
  // forms agree with g to the lattice quadrature of the first moment (1 %, computed).
  const double l0 = 0.025, g = 9.81;
  const SphKernel kernel(SphKernelKind::CubicSpline, 2.4 * l0);
  const double mass = kRestDensity / lattice_kernel_sum(kernel, l0);
  Block block = lattice_block(l0, 6, 0);  // the centre's row is the top row
  auto& p = block.particles;
  const double top = p.position[block.centre].y();
  std::vector<double> surface(p.size(), 0.0), density(p.size(), kRestDensity);
  for (std::size_t i = 0; i < p.size(); ++i) {
    p.pressure[i] = kRestDensity * g * (top - p.position[i].y());
    if (p.position[i].y() > top - 0.5 * l0) surface[i] = 1.0;
  }
  const NeighbourList list = find_neighbours(p.position, p.type, kernel.support());
  std::vector<Vec2> corrected, symmetric, hybrid;
  pressure_acceleration(p, list, kernel, mass, density, surface, PressureGradientForm::Corrected, corrected);
  pressure_acceleration(p, list, kernel, mass, density, surface, PressureGradientForm::Symmetric, symmetric);
  pressure_acceleration(p, list, kernel, mass, density, surface, PressureGradientForm::SymmetricCorrectedSurface,
                        hybrid);
  const std::size_t c = block.centre;
  CHECK(corrected[c].x() == Approx(0.0).margin(1e-9));
  CHECK(corrected[c].y() == Approx(g).epsilon(1e-9));
  CHECK(hybrid[c].y() == Approx(g).epsilon(1e-9));
  INFO("symmetric form at the surface: " << symmetric[c].y() / g << " g");
  CHECK(symmetric[c].y() / g == Approx(0.5).margin(0.05));
  // Three rows down the support is complete: symmetric and renormalised agree with g.
  const std::size_t inside = c - 3 * 13;
  REQUIRE(surface[inside] == 0.0);
  CHECK(symmetric[inside].y() == Approx(g).epsilon(0.01));
  CHECK(hybrid[inside].y() == Approx(symmetric[inside].y()).epsilon(1e-12));
  CHECK(corrected[inside].y() == Approx(g).epsilon(1e-9));
}
