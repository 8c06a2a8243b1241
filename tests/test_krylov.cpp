// The Krylov solvers of core/linalg/krylov.hpp against Eigen: conjugate gradients on a symmetric
// positive definite system, BiCGSTAB on a non-symmetric one, each with the Jacobi and the
// block ILU(0) preconditioner; their stopping rule, iteration cap, warm start, and that the
// result does not depend on the number of threads.
#include <cmath>
#include <random>
#include <vector>

#include <omp.h>
#include <catch2/catch.hpp>

#include <Eigen/Dense>
#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>

#include "core/linalg/krylov.hpp"
#include "core/linalg/pressure_system.hpp"

using namespace mps_lab;

namespace {

// The 5-point operator on an m x m grid with Dirichlet boundaries, plus a first-order upwind
// convection term of strength `convection` (0: the symmetric positive definite Laplacian;
// > 0: non-symmetric, still diagonally dominant). Rows in grid order; columns unsorted on
// purpose (diagonal first), as the pressure assemblers store them.
CsrMatrix grid_operator(int m, double convection) {
  CsrMatrix matrix;
  matrix.rows = m * m;
  matrix.diagonal_first = true;
  matrix.row_start.assign(1, 0);
  for (int y = 0; y < m; ++y) {
    for (int x = 0; x < m; ++x) {
      const int row = y * m + x;
      matrix.column.push_back(row);
      matrix.value.push_back(4.0 + convection);
      const auto add = [&](int xx, int yy, double v) {
        if (xx < 0 || yy < 0 || xx >= m || yy >= m) return;
        matrix.column.push_back(yy * m + xx);
        matrix.value.push_back(v);
      };
      add(x + 1, y, -1.0);
      add(x - 1, y, -1.0 - convection);  // upwind: the flow comes from -x
      add(x, y + 1, -1.0);
      add(x, y - 1, -1.0);
      matrix.row_start.push_back(static_cast<int>(matrix.column.size()));
    }
  }
  return matrix;
}

std::vector<double> random_vector(int n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<double> v(static_cast<std::size_t>(n));
  for (double& x : v) x = uniform(rng);
  return v;
}

Eigen::Map<const Eigen::VectorXd> as_eigen(const std::vector<double>& v) {
  return {v.data(), static_cast<Eigen::Index>(v.size())};
}

// ||b - A x|| / ||b|| recomputed with Eigen. Evaluated in another order than the solver's, it
// differs from the solver's by round-off: per row about (row entries) eps sum_j |a_ij x_j|, so
// relatively about 5 eps cond(A) <= 1e-13 for these systems (cond <= 180); the checks allow
// kResidualRoundOff on top of a relative 1e-6.
constexpr double kResidualRoundOff = 1e-12;

double relative_residual(const CsrMatrix& matrix, const std::vector<double>& b, const std::vector<double>& x) {
  const Eigen::SparseMatrix<double, Eigen::RowMajor> a = to_eigen(matrix);
  return (as_eigen(b) - a * as_eigen(x)).norm() / as_eigen(b).norm();
}

// The 2-norm condition number from the singular values (small systems only).
double condition_number(const CsrMatrix& matrix) {
  const Eigen::MatrixXd dense = Eigen::MatrixXd(to_eigen(matrix));
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(dense);
  const auto& sigma = svd.singularValues();
  return sigma(0) / sigma(sigma.size() - 1);
}

}  // namespace

TEST_CASE("conjugate gradients: Jacobi and block ILU(0) reach the tolerance and Eigen's solution", "[krylov]") {
  const CsrMatrix matrix = grid_operator(20, 0.0);  // 400 unknowns, SPD
  const std::vector<double> b = random_vector(matrix.rows, 1);
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> direct(Eigen::SparseMatrix<double>(to_eigen(matrix)));
  REQUIRE(direct.info() == Eigen::Success);
  const Eigen::VectorXd exact = direct.solve(as_eigen(b));
  // ||x - x*|| / ||x*|| <= cond(A) ||b - A x|| / ||b|| (cond = 178 for this grid).
  const double cond = condition_number(matrix);
  INFO("cond(A) = " << cond);
  CHECK(cond == Approx(178.1).epsilon(0.01));

  const double tolerance = 1e-10;
  KrylovSettings settings;
  settings.tolerance = tolerance;
  settings.max_iterations = 1000;
  KrylovWorkspace workspace;

  JacobiPreconditioner jacobi;
  IncompleteLuPreconditioner ilu_one(1), ilu_three(3);
  long long jacobi_iterations = 0;
  for (Preconditioner* preconditioner : std::vector<Preconditioner*>{&jacobi, &ilu_one, &ilu_three}) {
    preconditioner->setup(matrix);
    std::vector<double> x(static_cast<std::size_t>(matrix.rows), 0.0);
    const KrylovResult result = conjugate_gradient(matrix, b.data(), x.data(), *preconditioner, settings, workspace);
    INFO(result.iterations << " iterations, residual " << result.residual);
    CHECK(result.converged);
    CHECK(result.residual < tolerance);
    CHECK(result.residual == Approx(relative_residual(matrix, b, x)).epsilon(1e-6).margin(kResidualRoundOff));
    CHECK((as_eigen(x) - exact).norm() <= cond * tolerance * exact.norm());
    if (preconditioner == &jacobi) {
      jacobi_iterations = result.iterations;
      // Eigen's Jacobi CG does the same iterations (it does not count the last one).
      Eigen::ConjugateGradient<Eigen::SparseMatrix<double, Eigen::RowMajor>, Eigen::Lower | Eigen::Upper> eigen_cg;
      eigen_cg.setTolerance(tolerance);
      const Eigen::SparseMatrix<double, Eigen::RowMajor> a = to_eigen(matrix);
      eigen_cg.compute(a);
      const Eigen::VectorXd eigen_x = eigen_cg.solve(as_eigen(b));
      CHECK(std::llabs(result.iterations - (eigen_cg.iterations() + 1)) <= 1);
    } else {
      CHECK(result.iterations < jacobi_iterations);
    }
  }
}

TEST_CASE("ILU(0) of a tridiagonal matrix is its exact LU: CG converges in one iteration", "[krylov]") {
  CsrMatrix matrix;  // the 1-D Laplacian, 50 unknowns
  matrix.rows = 50;
  matrix.row_start.assign(1, 0);
  for (int r = 0; r < matrix.rows; ++r) {
    for (int c : {r + 1, r, r - 1}) {  // unsorted columns
      if (c < 0 || c >= matrix.rows) continue;
      matrix.column.push_back(c);
      matrix.value.push_back(c == r ? 2.0 : -1.0);
    }
    matrix.row_start.push_back(static_cast<int>(matrix.column.size()));
  }
  IncompleteLuPreconditioner ilu(1);
  ilu.setup(matrix);
  const std::vector<double> b = random_vector(matrix.rows, 2);
  std::vector<double> x(50, 0.0);
  KrylovWorkspace workspace;
  const KrylovResult result =
      conjugate_gradient(matrix, b.data(), x.data(), ilu, KrylovSettings{1e-12, 100}, workspace);
  CHECK(result.converged);
  CHECK(result.iterations == 1);
  CHECK(result.residual < 1e-12);
}

TEST_CASE("BiCGSTAB: Jacobi and block ILU(0) on a non-symmetric system", "[krylov]") {
  const CsrMatrix matrix = grid_operator(20, 2.0);
  const std::vector<double> b = random_vector(matrix.rows, 3);
  const Eigen::SparseMatrix<double> a(to_eigen(matrix));
  CHECK((a - Eigen::SparseMatrix<double>(a.transpose())).norm() > 1.0);  // really non-symmetric
  Eigen::SparseLU<Eigen::SparseMatrix<double>> direct(a);
  REQUIRE(direct.info() == Eigen::Success);
  const Eigen::VectorXd exact = direct.solve(as_eigen(b));
  const double cond = condition_number(matrix);
  INFO("cond(A) = " << cond);
  CHECK(cond < 100.0);

  const double tolerance = 1e-10;
  KrylovWorkspace workspace;
  JacobiPreconditioner jacobi;
  IncompleteLuPreconditioner ilu(2);
  long long jacobi_iterations = 0;
  for (Preconditioner* preconditioner : std::vector<Preconditioner*>{&jacobi, &ilu}) {
    preconditioner->setup(matrix);
    std::vector<double> x(static_cast<std::size_t>(matrix.rows), 0.0);
    const KrylovResult result =
        bicgstab(matrix, b.data(), x.data(), *preconditioner, KrylovSettings{tolerance, 1000}, workspace);
    INFO(result.iterations << " iterations, residual " << result.residual);
    CHECK(result.converged);
    CHECK(result.residual <= tolerance);
    CHECK(result.residual == Approx(relative_residual(matrix, b, x)).epsilon(1e-6).margin(kResidualRoundOff));
    CHECK((as_eigen(x) - exact).norm() <= cond * tolerance * exact.norm());
    if (preconditioner == &jacobi) {
      jacobi_iterations = result.iterations;
    } else {
      CHECK(result.iterations < jacobi_iterations);
    }
  }
}

TEST_CASE("Krylov solvers: iteration cap - warm start - zero right-hand side", "[krylov]") {
  const CsrMatrix matrix = grid_operator(20, 0.0);
  const std::vector<double> b = random_vector(matrix.rows, 4);
  JacobiPreconditioner jacobi;
  jacobi.setup(matrix);
  KrylovWorkspace workspace;
  for (const bool symmetric_solver : {true, false}) {
    const auto solve = [&](std::vector<double>& x, KrylovSettings settings) {
      return symmetric_solver ? conjugate_gradient(matrix, b.data(), x.data(), jacobi, settings, workspace)
                              : bicgstab(matrix, b.data(), x.data(), jacobi, settings, workspace);
    };
    std::vector<double> x(static_cast<std::size_t>(matrix.rows), 0.0);
    const KrylovResult capped = solve(x, KrylovSettings{1e-12, 3});
    CHECK(capped.iterations == 3);
    CHECK_FALSE(capped.converged);
    CHECK(capped.residual == Approx(relative_residual(matrix, b, x)).epsilon(1e-9).margin(kResidualRoundOff));
    const KrylovResult done = solve(x, KrylovSettings{1e-12, 1000});  // warm start from the capped x
    CHECK(done.converged);
    const KrylovResult again = solve(x, KrylovSettings{1e-12, 1000});  // from the solution: nothing to do
    CHECK(again.iterations == 0);
    CHECK(again.converged);
    std::vector<double> zero_rhs(b.size(), 0.0), y(b.size(), 1.0);
    const KrylovResult zero = symmetric_solver
                                  ? conjugate_gradient(matrix, zero_rhs.data(), y.data(), jacobi, {1e-8, 10}, workspace)
                                  : bicgstab(matrix, zero_rhs.data(), y.data(), jacobi, {1e-8, 10}, workspace);
    CHECK(zero.converged);
    CHECK(zero.iterations == 0);
    CHECK(as_eigen(y).norm() == 0.0);
  }
}

TEST_CASE("Krylov solvers give the same bits on 1 and 2 threads", "[krylov]") {
  const CsrMatrix matrix = grid_operator(60, 0.5);  // 3600 rows: several reduction blocks
  const CsrMatrix spd = grid_operator(60, 0.0);
  const std::vector<double> b = random_vector(matrix.rows, 5);
  const int threads_before = omp_get_max_threads();
  std::vector<std::vector<double>> solutions;
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    KrylovWorkspace workspace;
    IncompleteLuPreconditioner ilu(2);
    JacobiPreconditioner jacobi;
    std::vector<double> x(b.size(), 0.0), y(b.size(), 0.0);
    jacobi.setup(spd);
    conjugate_gradient(spd, b.data(), x.data(), jacobi, {1e-10, 1000}, workspace);
    ilu.setup(matrix);
    bicgstab(matrix, b.data(), y.data(), ilu, {1e-10, 1000}, workspace);
    x.insert(x.end(), y.begin(), y.end());
    solutions.push_back(x);
  }
  omp_set_num_threads(threads_before);
  CHECK(solutions[0] == solutions[1]);
}

namespace {

// A preconditioner written as a user would, with apply() alone (a serial loop): conjugate
// gradients run their iterations in one parallel region and reach it through the default
// apply_in_team, which lets one thread of the team call apply().
class SerialDiagonal final : public Preconditioner {
 public:
  void setup(const CsrMatrix& matrix) override {
    inverse_.assign(static_cast<std::size_t>(matrix.rows), 0.0);
    for (int r = 0; r < matrix.rows; ++r)
      inverse_[static_cast<std::size_t>(r)] = 1.0 / matrix.value[matrix.row_start[r]];
  }
  void apply(const double* residual, double* result) const override {
    for (std::size_t r = 0; r < inverse_.size(); ++r) result[r] = inverse_[r] * residual[r];
  }

 private:
  std::vector<double> inverse_;  // 1 / a_rr (the grid operators store the diagonal first)
};

}  // namespace

TEST_CASE("conjugate gradients in one parallel region: a preconditioner with apply() alone, and ILU(0) in the team",
          "[krylov]") {
  // The serial diagonal is the Jacobi preconditioner computed by other code: the same z = D^-1 r
  // and, through the team's dot product, the same r.z block sums as Jacobi's fused update, so
  // the bits must be Jacobi's. ILU(0) shares its blocks among the team (apply_in_team): the bits
  // must not depend on the thread count.
  const CsrMatrix spd = grid_operator(60, 0.0);
  const std::vector<double> b = random_vector(spd.rows, 11);
  const int threads_before = omp_get_max_threads();
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    KrylovWorkspace workspace;
    JacobiPreconditioner jacobi;
    SerialDiagonal serial;
    jacobi.setup(spd);
    serial.setup(spd);
    std::vector<double> x_jacobi(b.size(), 0.0), x_serial(b.size(), 0.0);
    const KrylovResult with_jacobi =
        conjugate_gradient(spd, b.data(), x_jacobi.data(), jacobi, {1e-10, 1000}, workspace);
    const KrylovResult with_serial =
        conjugate_gradient(spd, b.data(), x_serial.data(), serial, {1e-10, 1000}, workspace);
    INFO(threads << " threads: " << with_jacobi.iterations << " and " << with_serial.iterations << " iterations");
    CHECK(with_serial.converged);
    CHECK(with_serial.iterations == with_jacobi.iterations);
    CHECK(x_serial == x_jacobi);
  }
  std::vector<std::vector<double>> ilu_solutions;
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    KrylovWorkspace workspace;
    IncompleteLuPreconditioner ilu(4);
    ilu.setup(spd);
    std::vector<double> x(b.size(), 0.0);
    CHECK(conjugate_gradient(spd, b.data(), x.data(), ilu, {1e-10, 1000}, workspace).converged);
    CHECK(relative_residual(spd, b, x) < 1e-10 + kResidualRoundOff);
    ilu_solutions.push_back(x);
  }
  omp_set_num_threads(threads_before);
  CHECK(ilu_solutions[0] == ilu_solutions[1]);
}

TEST_CASE(
    "BiCGSTAB in one parallel region: a preconditioner with apply() alone gives Jacobi's bits, on 1 and 2 threads",
    "[krylov]") {
  // BiCGSTAB's iterations share one region (core/linalg/krylov.cpp, bicgstab_iterations), with
  // its two preconditioner applications in the team. The serial diagonal (apply() by one thread
  // of the team) computes Jacobi's z = D^-1 r, so the iterations and the solution must be
  // Jacobi's to the bit; and neither may depend on the thread count. The system is the
  // non-symmetric convection operator of the test above, at 60 x 60 (3,600 rows, 15 blocks: the
  // team splits every loop), solved to 1e-10.
  const CsrMatrix matrix = grid_operator(60, 2.0);
  const std::vector<double> b = random_vector(matrix.rows, 17);
  const int threads_before = omp_get_max_threads();
  std::vector<std::vector<double>> solutions;
  std::vector<long long> iterations;
  for (int threads : {1, 2}) {
    omp_set_num_threads(threads);
    KrylovWorkspace workspace;
    JacobiPreconditioner jacobi;
    SerialDiagonal serial;
    jacobi.setup(matrix);
    serial.setup(matrix);
    std::vector<double> x_jacobi(b.size(), 0.0), x_serial(b.size(), 0.0);
    const KrylovResult with_jacobi = bicgstab(matrix, b.data(), x_jacobi.data(), jacobi, {1e-10, 1000}, workspace);
    const KrylovResult with_serial = bicgstab(matrix, b.data(), x_serial.data(), serial, {1e-10, 1000}, workspace);
    INFO(threads << " threads: " << with_jacobi.iterations << " and " << with_serial.iterations << " iterations");
    CHECK(with_jacobi.converged);
    CHECK(relative_residual(matrix, b, x_jacobi) < 1e-10 + kResidualRoundOff);
    CHECK(with_serial.iterations == with_jacobi.iterations);
    CHECK(x_serial == x_jacobi);
    solutions.push_back(x_jacobi);
    iterations.push_back(with_jacobi.iterations);
  }
  omp_set_num_threads(threads_before);
  CHECK(iterations[0] == iterations[1]);
  CHECK(solutions[0] == solutions[1]);
}
