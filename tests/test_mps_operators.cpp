// MPS operators (spec §2) on fields with known derivatives, and the PPE solver.
#include <random>

#include <Eigen/SparseCholesky>
#include <catch2/catch.hpp>

#include "core/io/geometry.hpp"
#include "methods/mps/mps_operators.hpp"
#include "methods/mps/mps_pressure.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::mps;

namespace {

// A 21 x 21 block of fluid on the lattice; particle `centre` has full support.
struct Block {
  ParticleSet particles;
  std::size_t centre = 0;
};

Block lattice_block(double l0, int half_width) {
  Block block;
  for (int j = -half_width; j <= half_width; ++j) {
    for (int i = -half_width; i <= half_width; ++i) {
      if (i == 0 && j == 0) block.centre = block.particles.size();
      block.particles.add(Vec2(0.3 + i * l0, 0.2 + j * l0), Vec2::Zero(), ParticleType::Fluid);
    }
  }
  return block;
}

}  // namespace

TEST_CASE("MPS Laplacian is exact for quadratic fields on the lattice", "[mps][operators]") {
  // Sum_j (u_j - u_i) w_ij = grad u . Sum r w + 1/2 Sum (r.H.r) w. On the square lattice the
  // first sum vanishes by symmetry and the second is (lap u / 2) lambda n0 for an isotropic
  // part; with lambda = Sum r^2 w / Sum w the model returns lap u exactly (Koshizuka & Oka
  // 1996, eq. 9): only round-off remains.
  const double l0 = 0.025;
  for (double re_over_l0 : {2.1, 3.1, 4.0}) {
    Block block = lattice_block(l0, 10);
    auto& p = block.particles;
    // u = (x^2 + 3 y^2, 2 x y - y^2): lap u = (2 + 6, 0 - 2) = (8, -2).
    for (std::size_t i = 0; i < p.size(); ++i) {
      const Vec2 x = p.position[i];
      p.velocity[i] = Vec2(x.x() * x.x() + 3 * x.y() * x.y(), 2 * x.x() * x.y() - x.y() * x.y());
    }
    const OperatorRadius radius = make_operator_radius(l0, re_over_l0 * l0, 0.01 * l0);
    const NeighbourList list = find_neighbours(p.position, p.type, radius.re);
    std::vector<Vec2> acceleration(p.size(), Vec2::Zero());
    add_viscous_acceleration(p, list, WallSampleList{}, radius, 1.0, acceleration);  // nu = 1: acceleration = lap u
    INFO("re = " << re_over_l0 << " l0");
    CHECK(acceleration[block.centre].x() == Approx(8.0).epsilon(1e-9));
    CHECK(acceleration[block.centre].y() == Approx(-2.0).epsilon(1e-9));
    // A linear field has zero Laplacian.
    for (std::size_t i = 0; i < p.size(); ++i) p.velocity[i] = Vec2(2 * p.position[i].x() - p.position[i].y(), 1.0);
    std::fill(acceleration.begin(), acceleration.end(), Vec2::Zero());
    add_viscous_acceleration(p, list, WallSampleList{}, radius, 1.0, acceleration);
    CHECK(acceleration[block.centre].norm() == Approx(0.0).margin(1e-9));
  }
}

TEST_CASE("MPS gradient is exact for linear and quadratic fields on the lattice", "[mps][operators]") {
  // (d/n0) Sum_j (P_j - P_i) r_ij r_ij^T / r^2 w: on the lattice Sum (r r^T / r^2) w = (n0/2) I,
  // so a linear P gives grad P exactly; the quadratic part r^T H r r / r^2 is odd in r and
  // cancels. The P_min shift adds (P_i - P_min) (d/n0) Sum r/r^2 w = 0 by symmetry.
  const double l0 = 0.025, rho = 1000.0;
  Block block = lattice_block(l0, 6);
  auto& p = block.particles;
  const OperatorRadius radius = make_operator_radius(l0, 2.1 * l0, 0.01 * l0);
  const NeighbourList list = find_neighbours(p.position, p.type, radius.re);
  std::vector<char> carries(p.size(), 1);
  std::vector<Vec2> acceleration(p.size(), Vec2::Zero());

  for (std::size_t i = 0; i < p.size(); ++i)
    p.pressure[i] = 5000.0 + 3000.0 * p.position[i].x() - 9810.0 * p.position[i].y();
  for (bool include_self : {true, false}) {
    pressure_acceleration(p, list, WallSampleList{}, radius, carries, rho, Vec2(0.0, -9.81), include_self, acceleration,
                          DryWallRule{});
    // a = -grad P / rho = (-3, 9.81)
    CHECK(acceleration[block.centre].x() == Approx(-3.0).epsilon(1e-10));
    CHECK(acceleration[block.centre].y() == Approx(9.81).epsilon(1e-10));
  }
  const Vec2 centre = p.position[block.centre];
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Vec2 x = p.position[i];
    p.pressure[i] = 1.0e4 * (x.x() * x.x() + x.x() * x.y() + 2.0 * x.y() * x.y());
  }
  pressure_acceleration(p, list, WallSampleList{}, radius, carries, rho, Vec2(0.0, -9.81), true, acceleration,
                        DryWallRule{});
  const Vec2 exact = -1.0e4 / rho * Vec2(2 * centre.x() + centre.y(), centre.x() + 4 * centre.y());
  CHECK(acceleration[block.centre].x() == Approx(exact.x()).epsilon(1e-10));
  CHECK(acceleration[block.centre].y() == Approx(exact.y()).epsilon(1e-10));
}

TEST_CASE("number density of a full-support particle is n0", "[mps][operators]") {
  const double l0 = 0.0125;
  Block block = lattice_block(l0, 5);
  const OperatorRadius radius = make_operator_radius(l0, 2.1 * l0, 0.01 * l0);
  const NeighbourList list = find_neighbours(block.particles.position, block.particles.type, radius.re);
  std::vector<double> n;
  number_density(block.particles, list, WallSampleList{}, radius, n);
  CHECK(n[block.centre] == Approx(radius.n0).epsilon(1e-12));
  // A corner particle of the block sees a quarter of the support plus the two half-axes.
  CHECK(n[0] < 0.5 * radius.n0);
}

TEST_CASE("PPE: CG agrees with a direct solve - and the system is symmetric positive definite", "[mps][pressure]") {
  // The dam-break particles with a compressed state: CG with relative tolerance 1e-12 must
  // match a sparse Cholesky solve. Bound: ||x - x*|| / ||x*|| <= cond(A) * tol; cond(A) of
  // this system is ~1e3 (measured), so 1e-8 is a safe tolerance on the relative difference.
  using namespace mps_lab::testing;
  const Scene scene = load("dambreak.json");
  ParticleSet particles = build_particles(scene);
  std::mt19937 rng(3);
  std::normal_distribution<double> jitter(0.0, 0.05 * scene.particle_spacing);
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] == ParticleType::Fluid) particles.position[i] += Vec2(jitter(rng), jitter(rng));
  }
  const double l0 = scene.particle_spacing;
  const OperatorRadius radius = make_operator_radius(l0, 2.1 * l0, 0.01 * l0);
  const NeighbourList list = find_neighbours(particles.position, particles.type, radius.re);
  std::vector<double> n;
  number_density(particles, list, WallSampleList{}, radius, n);
  std::vector<char> carries(particles.size());
  for (std::size_t i = 0; i < particles.size(); ++i) {
    carries[i] = particles.type[i] == ParticleType::Fluid || particles.wall_layer[i] == 1;
  }
  PressureSolveSettings settings;
  settings.tolerance = 1e-12;
  settings.clamp_negative = false;
  settings.warm_start = false;
  std::vector<double> surface;
  PressurePoissonSolver solver;
  const auto result =
      solver.solve(particles, list, WallSampleList{}, n, carries, radius, radius.n0, 5e-4, settings, surface);
  REQUIRE(result.converged);
  REQUIRE(result.unknowns > 100);
  CHECK(result.ungrounded_groups == 0);

  const Eigen::SparseMatrix<double> A = solver.matrix();
  const Eigen::SparseMatrix<double> At = A.transpose();
  CHECK((A - At).norm() <= 1e-12 * A.norm());
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> direct(A);
  REQUIRE(direct.info() == Eigen::Success);
  CHECK(direct.vectorD().minCoeff() > 0.0);  // positive definite
  const Eigen::VectorXd exact = direct.solve(solver.rhs());
  Eigen::VectorXd cg(exact.size());
  std::size_t row = 0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (carries[i] && surface[i] == 0.0 && particles.type[i] != ParticleType::Ghost)
      cg[static_cast<Eigen::Index>(row++)] = particles.pressure[i];
  }
  REQUIRE(row == static_cast<std::size_t>(exact.size()));
  CHECK((cg - exact).norm() <= 1e-8 * exact.norm());

  // Incomplete Cholesky preconditioning converges to the same solution in fewer iterations.
  settings.preconditioner = PreconditionerKind::IncompleteFactorisation;
  PressurePoissonSolver ic_solver;
  const auto ic =
      ic_solver.solve(particles, list, WallSampleList{}, n, carries, radius, radius.n0, 5e-4, settings, surface);
  CHECK(ic.converged);
  CHECK(ic.iterations < result.iterations);
}
