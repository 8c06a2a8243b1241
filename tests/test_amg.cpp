// The smoothed-aggregation AMG preconditioner (core/linalg/amg.hpp): iteration counts of
// preconditioned CG that stay flat while Jacobi-CG's grow like sqrt(N), on the 5-point
// Poisson matrix and on a particle-like (MPS kernel) matrix; a symmetric operator; the same
// bits for 1 and 2 threads; BiCGSTAB on mildly nonsymmetric rows (ISPH). The Krylov solvers
// here are small test-only ones (the project's own are separate).
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <random>
#include <vector>

#include <catch2/catch.hpp>

#include "core/linalg/amg.hpp"
#include "core/linalg/krylov.hpp"

using namespace mps_lab;

namespace {

double dot(const std::vector<double>& a, const std::vector<double>& b) {
  return deterministic_dot(a.data(), b.data(), a.size());
}

// Rows of triplets (diagonal first) to CSR.
struct RowBuilder {
  CsrMatrix matrix;
  explicit RowBuilder(int rows) {
    matrix.clear_rows(rows);
    matrix.diagonal_first = true;
  }
  void add(int row, int column, double value) {  // rows in increasing order
    matrix.column.push_back(column);
    matrix.value.push_back(value);
    matrix.row_start[static_cast<std::size_t>(row) + 1] = static_cast<int>(matrix.column.size());
  }
};

// 5-point Laplacian on an n x n grid, Dirichlet boundary (the boundary values eliminated).
CsrMatrix poisson_5_point(int n) {
  RowBuilder builder(n * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int row = j * n + i;
      builder.add(row, row, 4.0);
      if (i > 0) builder.add(row, row - 1, -1.0);
      if (i + 1 < n) builder.add(row, row + 1, -1.0);
      if (j > 0) builder.add(row, row - n, -1.0);
      if (j + 1 < n) builder.add(row, row + n, -1.0);
    }
  return builder.matrix;
}

struct ParticleMatrixOptions {
  double jitter = 0.0;         // random displacement of each point, in l0
  bool shuffle = false;        // unknowns in a random order (particles are not sorted)
  double row_asymmetry = 0.0;  // rows scaled by 1 + U(-a, a): mildly nonsymmetric (ISPH-like)
};

// The MPS pressure matrix on an nx x (ny + 1) lattice with spacing l0 = 1: weights
// w(r) = re / r - 1 for r < re = 2.1; row i: diagonal sum_j w_ij over every neighbour,
// -w_ij for each unknown neighbour. The top lattice row is the free surface (P = 0,
// Dirichlet): not an unknown, its columns dropped. The other sides have no neighbours
// beyond them (a wall-less Neumann-like edge).
CsrMatrix particle_matrix(int nx, int ny, const ParticleMatrixOptions& options = {}) {
  constexpr double re = 2.1;
  std::mt19937_64 random(12345);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const int columns_of_points = nx, rows_of_points = ny + 1;
  std::vector<double> x(static_cast<std::size_t>(columns_of_points * rows_of_points));
  std::vector<double> y(x.size());
  for (int j = 0; j < rows_of_points; ++j)
    for (int i = 0; i < columns_of_points; ++i) {
      const auto p = static_cast<std::size_t>(j * columns_of_points + i);
      x[p] = i + options.jitter * uniform(random);
      y[p] = j + options.jitter * uniform(random);
    }
  const int unknowns = nx * ny;  // points with j < ny
  std::vector<int> order(static_cast<std::size_t>(unknowns));
  for (int k = 0; k < unknowns; ++k) order[static_cast<std::size_t>(k)] = k;
  if (options.shuffle) std::shuffle(order.begin(), order.end(), random);
  std::vector<int> unknown_of_point(static_cast<std::size_t>(unknowns));
  for (int k = 0; k < unknowns; ++k) unknown_of_point[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])] = k;
  RowBuilder builder(unknowns);
  for (int row = 0; row < unknowns; ++row) {
    const int point = order[static_cast<std::size_t>(row)];
    const int pi = point % columns_of_points, pj = point / columns_of_points;
    const double scale = 1.0 + options.row_asymmetry * uniform(random);
    double diagonal = 0.0;
    std::vector<std::pair<int, double>> off_diagonal;
    for (int dj = -3; dj <= 3; ++dj)
      for (int di = -3; di <= 3; ++di) {
        const int qi = pi + di, qj = pj + dj;
        if ((di == 0 && dj == 0) || qi < 0 || qi >= columns_of_points || qj < 0 || qj >= rows_of_points) continue;
        const int q = qj * columns_of_points + qi;
        const double r = std::hypot(x[static_cast<std::size_t>(q)] - x[static_cast<std::size_t>(point)],
                                    y[static_cast<std::size_t>(q)] - y[static_cast<std::size_t>(point)]);
        if (r >= re) continue;
        const double w = re / r - 1.0;
        diagonal += w;
        if (qj < ny) off_diagonal.emplace_back(unknown_of_point[static_cast<std::size_t>(q)], -w);
      }
    builder.add(row, row, scale * diagonal);
    for (const auto& [column, value] : off_diagonal) builder.add(row, column, scale * value);
  }
  return builder.matrix;
}

// A right-hand side with every frequency: uniform random in [-1, 1].
std::vector<double> random_vector(int n, unsigned seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<double> v(static_cast<std::size_t>(n));
  for (double& value : v) value = uniform(random);
  return v;
}

// Preconditioned CG from x = 0 to ||r|| <= tolerance ||b||; returns the iteration count.
template <class Preconditioner>
int pcg_iterations(const CsrMatrix& a, const std::vector<double>& b, const Preconditioner& preconditioner,
                   double tolerance = 1e-8, int max_iterations = 20000) {
  const auto n = b.size();
  std::vector<double> x(n, 0.0), r = b, z(n), p(n), q(n);
  const double target = tolerance * std::sqrt(dot(b, b));
  preconditioner(r.data(), z.data());
  p = z;
  double rz = dot(r, z);
  for (int iteration = 1; iteration <= max_iterations; ++iteration) {
    multiply(a, p.data(), q.data());
    const double alpha = rz / dot(p, q);
    for (std::size_t i = 0; i < n; ++i) {
      x[i] += alpha * p[i];
      r[i] -= alpha * q[i];
    }
    if (std::sqrt(dot(r, r)) <= target) return iteration;
    preconditioner(r.data(), z.data());
    const double rz_new = dot(r, z);
    const double beta = rz_new / rz;
    rz = rz_new;
    for (std::size_t i = 0; i < n; ++i) p[i] = z[i] + beta * p[i];
  }
  return max_iterations + 1;
}

// Right-preconditioned BiCGSTAB (van der Vorst 1992) from x = 0; returns the iteration count.
int bicgstab_iterations(const CsrMatrix& a, const std::vector<double>& b, const AmgPreconditioner& amg,
                        double tolerance = 1e-8, int max_iterations = 2000) {
  const auto n = b.size();
  std::vector<double> x(n, 0.0), r = b, r0 = b, p(n, 0.0), v(n, 0.0), s(n), t(n), p_hat(n), s_hat(n);
  const double target = tolerance * std::sqrt(dot(b, b));
  double rho = 1.0, alpha = 1.0, omega = 1.0;
  for (int iteration = 1; iteration <= max_iterations; ++iteration) {
    const double rho_new = dot(r0, r);
    const double beta = (rho_new / rho) * (alpha / omega);
    rho = rho_new;
    for (std::size_t i = 0; i < n; ++i) p[i] = r[i] + beta * (p[i] - omega * v[i]);
    amg.apply(p.data(), p_hat.data());
    multiply(a, p_hat.data(), v.data());
    alpha = rho / dot(r0, v);
    for (std::size_t i = 0; i < n; ++i) s[i] = r[i] - alpha * v[i];
    amg.apply(s.data(), s_hat.data());
    multiply(a, s_hat.data(), t.data());
    omega = dot(t, s) / dot(t, t);
    for (std::size_t i = 0; i < n; ++i) {
      x[i] += alpha * p_hat[i] + omega * s_hat[i];
      r[i] = s[i] - omega * t[i];
    }
    if (std::sqrt(dot(r, r)) <= target) return iteration;
  }
  return max_iterations + 1;
}

struct Counts {
  int jacobi = 0, amg = 0;
};

// Iteration counts of Jacobi-PCG and AMG-PCG on `a` for a random right-hand side.
Counts count_iterations(const CsrMatrix& a, bool with_jacobi, const char* label, const AmgOptions& options = {}) {
  const std::vector<double> b = random_vector(a.rows, 7);
  Counts counts;
  if (with_jacobi) {
    std::vector<double> inverse_diagonal(static_cast<std::size_t>(a.rows));
    for (int r = 0; r < a.rows; ++r) inverse_diagonal[static_cast<std::size_t>(r)] = 1.0 / a.value[a.row_start[r]];
    counts.jacobi = pcg_iterations(a, b, [&](const double* in, double* out) {
      for (std::size_t i = 0; i < inverse_diagonal.size(); ++i) out[i] = inverse_diagonal[i] * in[i];
    });
  }
  AmgPreconditioner amg(options);
  amg.setup(a);
  counts.amg = pcg_iterations(a, b, [&](const double* in, double* out) { amg.apply(in, out); });
  std::printf("[amg] %-24s rows %8d  levels %zu  operator complexity %.2f  iterations: jacobi %5d  amg %3d\n", label,
              a.rows, amg.levels().size(), amg.operator_complexity(), counts.jacobi, counts.amg);
  return counts;
}

// AMG-PCG iterations to 1e-8 from zero with the default options (degree-1 smoother, W-cycle),
// measured (the counts do not depend on the thread count): Poisson n = 32 .. 512: 19; particle
// lattice 1e3 .. 2.5e5 unknowns: 10-11; jittered and shuffled: 15-16. Bounds: measured maximum
// + about 30 %. (The V-cycle: 19-20, 11-18, 18-26; degree 2 with the V-cycle: 14-15, 15-18, 15-21.)
constexpr int kPoissonAmgBound = 26;
constexpr int kParticleAmgBound = 21;
// Growth of the AMG count over a 100-fold size increase: at most 2x (measured 0.91x on the
// particle lattice and 1.0x on Poisson with the W-cycle, 1.64x and 1.05x with the V-cycle), where
// Jacobi-CG grows like sqrt(N): 10x.
constexpr int kAmgGrowthFactor = 2;

}  // namespace

TEST_CASE("AMG-PCG iterations stay flat on the 5-point Poisson matrix", "[amg]") {
  std::vector<Counts> counts;
  for (const int n : {32, 64, 128}) {
    char label[64];
    std::snprintf(label, sizeof label, "poisson %dx%d", n, n);
    counts.push_back(count_iterations(poisson_5_point(n), true, label));
  }
  for (const Counts& c : counts) CHECK(c.amg <= kPoissonAmgBound);
  // Jacobi-CG grows like n (= sqrt(N)): x4 in n, at least x3 in iterations; AMG far less.
  CHECK(counts.back().jacobi >= 3 * counts.front().jacobi);
  CHECK(counts.back().amg <= kAmgGrowthFactor * counts.front().amg);
}

TEST_CASE("AMG-PCG iterations stay flat on the 5-point Poisson matrix - large grids", "[amg][long]") {
  for (const int n : {256, 512}) {
    char label[64];
    std::snprintf(label, sizeof label, "poisson %dx%d", n, n);
    const Counts c = count_iterations(poisson_5_point(n), n <= 256, label);
    CHECK(c.amg <= kPoissonAmgBound);
  }
}

TEST_CASE("AMG-PCG iterations stay flat on a particle-like (MPS kernel) matrix", "[amg]") {
  std::vector<Counts> counts;
  for (const int n : {32, 100, 317}) {
    char label[64];
    std::snprintf(label, sizeof label, "particles %dx%d", n, n);
    counts.push_back(count_iterations(particle_matrix(n, n), n <= 100, label));
  }
  for (const Counts& c : counts) CHECK(c.amg <= kParticleAmgBound);
  CHECK(counts[1].jacobi >= 2 * counts[0].jacobi);
  CHECK(counts.back().amg <= kAmgGrowthFactor * counts.front().amg);
  // Irregular points in an unsorted order (particles after some steps).
  const Counts shuffled =
      count_iterations(particle_matrix(100, 100, {0.2, true, 0.0}), false, "particles 100 jitter+shuffle");
  CHECK(shuffled.amg <= kParticleAmgBound);
}

TEST_CASE("AMG-PCG iterations stay flat on a particle-like matrix - 2.5e5 unknowns", "[amg][long]") {
  const Counts c = count_iterations(particle_matrix(500, 500), true, "particles 500x500");
  CHECK(c.amg <= kParticleAmgBound);
  const Counts shuffled =
      count_iterations(particle_matrix(500, 500, {0.2, true, 0.0}), false, "particles 500 jitter+shuffle");
  CHECK(shuffled.amg <= kParticleAmgBound);
}

TEST_CASE("AMG W-cycle: the particle lattice's iterations stay flat where the V-cycle's grow", "[amg]") {
  // The default cycle (coarse_cycles 2, levels from 256 rows) against the V-cycle on the MPS
  // kernel lattice at 1e3 and 1e5 unknowns (3 and 5 levels; at 1e3 the second level has fewer than 256
  // rows, so both cycles are the same there). Measured: W 11 and 10, V 18 at 1e5.
  AmgOptions v_cycle;
  v_cycle.coarse_cycles = 1;
  const CsrMatrix small = particle_matrix(32, 32), large = particle_matrix(317, 317);
  const int w_small = count_iterations(small, false, "particles 32x32, W").amg;
  const int w_large = count_iterations(large, false, "particles 317x317, W").amg;
  const int v_large = count_iterations(large, false, "particles 317x317, V", v_cycle).amg;
  CHECK(w_large <= w_small + 1);  // flat: one iteration of slack for the random right-hand side
  CHECK(v_large >= w_large + 4);  // the V-cycle's growth, which the W-cycle removes
}

TEST_CASE("AMG apply is a symmetric positive definite operator", "[amg]") {
  // With each smoother: the default degree-1 Chebyshev step, whose V-cycle fuses it with the
  // residual and the prolongation (AmgPreconditioner::cycle), and the unfused degree 2 and
  // damped Jacobi. A fused loop that read a neighbour's value before it was written, or a
  // post-smoothing step from the wrong vector, breaks the symmetry by far more than 1e-12.
  AmgOptions degree_two;
  degree_two.smoother_sweeps = 2;
  AmgOptions jacobi;
  jacobi.smoother = AmgSmoother::damped_jacobi;
  jacobi.smoother_sweeps = 2;
  // The W-cycle: each coarse level but the coarsest cycled twice (repeat_cycle), 2B - BAB.
  AmgOptions w_cycle;
  w_cycle.coarse_cycles = 2;
  for (const AmgOptions& options : {AmgOptions{}, degree_two, jacobi, w_cycle}) {
    for (const CsrMatrix& a : {poisson_5_point(64), particle_matrix(60, 50, {0.2, true, 0.0})}) {
      INFO("smoother sweeps " << options.smoother_sweeps
                              << (options.smoother == AmgSmoother::chebyshev ? " chebyshev" : " jacobi")
                              << ", coarse cycles " << options.coarse_cycles);
      AmgPreconditioner amg(options);
      amg.setup(a);
      REQUIRE(amg.levels().size() >= 3);
      for (unsigned seed = 1; seed <= 3; ++seed) {
        const std::vector<double> r1 = random_vector(a.rows, seed), r2 = random_vector(a.rows, seed + 100);
        std::vector<double> z1(r1.size()), z2(r2.size());
        amg.apply(r1.data(), z1.data());
        amg.apply(r2.data(), z2.data());
        const double left = dot(z1, r2), right = dot(r1, z2);
        const double scale = std::sqrt(dot(z1, z1) * dot(r2, r2));
        CHECK(std::abs(left - right) <= 1e-12 * scale);
        CHECK(dot(z1, r1) > 0.0);
        CHECK(dot(z2, r2) > 0.0);
      }
    }
  }
}

// Tagged [determinism] too: it sets its own thread count, so CTest runs it alone (tests/CMakeLists.txt).
TEST_CASE("AMG setup and apply give the same bits for 1 and 2 threads", "[amg][determinism]") {
  // Above the size at which the loops use threads (4096 rows), on several levels; the V-cycle
  // and the W-cycle (coarse_cycles 2).
  const CsrMatrix a = particle_matrix(200, 150, {0.2, true, 0.0});
  const CsrMatrix other = particle_matrix(180, 190, {0.1, false, 0.0});
  const std::vector<double> r = random_vector(a.rows, 3);
  const int previous = omp_get_max_threads();
  for (const int cycles : {1, 2}) {
    INFO("coarse cycles " << cycles);
    AmgOptions options;
    options.coarse_cycles = cycles;
    std::vector<std::vector<double>> results;
    for (const int threads : {1, 2}) {
      omp_set_num_threads(threads);
      AmgPreconditioner amg(options);
      amg.setup(a);
      std::vector<double> z(r.size());
      amg.apply(r.data(), z.data());
      results.push_back(z);
      // Storage reused from a setup on another matrix leaves no trace.
      AmgPreconditioner reused(options);
      reused.setup(other);
      reused.setup(a);
      reused.setup(other);
      reused.setup(a);
      reused.apply(r.data(), z.data());
      results.push_back(z);
    }
    omp_set_num_threads(previous);
    const std::size_t bytes = results[0].size() * sizeof(double);
    for (std::size_t k = 1; k < results.size(); ++k)
      CHECK(std::memcmp(results[0].data(), results[k].data(), bytes) == 0);
  }
}

TEST_CASE("AMG preconditions BiCGSTAB on mildly nonsymmetric rows (ISPH-like)", "[amg]") {
  std::vector<int> iterations;
  for (const int n : {40, 160}) {
    const CsrMatrix a = particle_matrix(n, n, {0.2, true, 0.1});
    AmgPreconditioner amg;
    amg.setup(a);
    iterations.push_back(bicgstab_iterations(a, random_vector(a.rows, 5), amg));
    std::printf("[amg] bicgstab nonsymmetric %dx%d: %d iterations\n", n, n, iterations.back());
  }
  // Measured: 9 and 13 iterations.
  CHECK(iterations[0] <= 20);
  CHECK(iterations[1] <= 20);
}

TEST_CASE("AMG through the Preconditioner interface of the project's Krylov solvers", "[amg]") {
  const CsrMatrix symmetric = particle_matrix(100, 100, {0.2, true, 0.0});
  const CsrMatrix nonsymmetric = particle_matrix(100, 100, {0.2, true, 0.1});
  AmgPreconditioner amg;
  const Preconditioner& interface = amg;
  KrylovSettings settings;
  settings.tolerance = 1e-8;
  KrylovWorkspace workspace;
  const std::vector<double> b = random_vector(symmetric.rows, 11);
  std::vector<double> x(b.size(), 0.0);
  amg.setup(symmetric);
  const KrylovResult cg = conjugate_gradient(symmetric, b.data(), x.data(), interface, settings, workspace);
  CHECK(cg.converged);
  CHECK(cg.iterations <= kParticleAmgBound);
  std::fill(x.begin(), x.end(), 0.0);
  amg.setup(nonsymmetric);
  const KrylovResult bicg = bicgstab(nonsymmetric, b.data(), x.data(), interface, settings, workspace);
  CHECK(bicg.converged);
  CHECK(bicg.iterations <= 20);
}

TEST_CASE("AMG on tiny and degenerate matrices", "[amg]") {
  // A single level (coarsest size not reached): the dense solve is exact.
  const CsrMatrix small = poisson_5_point(5);
  AmgPreconditioner amg;
  amg.setup(small);
  CHECK(amg.levels().size() == 1);
  const std::vector<double> b = random_vector(small.rows, 9);
  std::vector<double> x(b.size()), check(b.size());
  amg.apply(b.data(), x.data());
  multiply(small, x.data(), check.data());
  for (std::size_t i = 0; i < b.size(); ++i) CHECK(check[i] == Approx(b[i]).margin(1e-12));
  // A diagonal matrix: no strong connection, nothing to aggregate.
  RowBuilder diagonal(5000);
  for (int r = 0; r < 5000; ++r) diagonal.add(r, r, 2.0);
  AmgPreconditioner amg_diagonal;
  amg_diagonal.setup(diagonal.matrix);
  std::vector<double> ones(5000, 1.0), result(5000);
  amg_diagonal.apply(ones.data(), result.data());
  CHECK(result[0] > 0.0);
  CHECK(std::isfinite(result[4999]));
  // An empty matrix.
  CsrMatrix empty;
  empty.clear_rows(0);
  AmgPreconditioner amg_empty;
  amg_empty.setup(empty);
  amg_empty.apply(nullptr, nullptr);
  CHECK(amg_empty.levels().size() == 1);
}

// A reused hierarchy (AmgPreconditioner::refresh; docs/performance.md, "A reused hierarchy").
namespace {

std::vector<int> identity_rows(int rows, int base_rows) {
  std::vector<int> base(static_cast<std::size_t>(rows));
  for (int r = 0; r < rows; ++r) base[static_cast<std::size_t>(r)] = r < base_rows ? r : -1;
  return base;
}

// Q A Q^T for the permutation that puts row r at new_row[r] (the same unknowns in another order,
// as after particles are reordered or unknowns renumbered between steps).
CsrMatrix permuted(const CsrMatrix& a, const std::vector<int>& new_row) {
  std::vector<int> old_row(new_row.size());
  for (std::size_t r = 0; r < new_row.size(); ++r) old_row[static_cast<std::size_t>(new_row[r])] = static_cast<int>(r);
  RowBuilder builder(a.rows);
  for (int row = 0; row < a.rows; ++row) {
    const int source = old_row[static_cast<std::size_t>(row)];
    for (int k = a.row_start[source]; k < a.row_start[source + 1]; ++k)
      builder.add(row, new_row[static_cast<std::size_t>(a.column[k])], a.value[k]);
  }
  return builder.matrix;
}

// CG iterations from zero to 1e-8 on `a` with `amg` (through the project's CG).
long long project_cg_iterations(const CsrMatrix& a, const AmgPreconditioner& amg) {
  KrylovSettings settings;
  settings.tolerance = 1e-8;
  KrylovWorkspace workspace;
  const std::vector<double> b = random_vector(a.rows, 21);
  std::vector<double> x(b.size(), 0.0);
  const KrylovResult solved = conjugate_gradient(a, b.data(), x.data(), amg, settings, workspace);
  CHECK(solved.converged);
  return solved.iterations;
}

}  // namespace

TEST_CASE("AMG refreshed with its own matrix and rows gives the bits of its set-up", "[amg]") {
  // The remapped transfers (every row its own base row) must be the set-up's transfers.
  const CsrMatrix a = particle_matrix(80, 60, {0.2, true, 0.0});
  const std::vector<double> r = random_vector(a.rows, 4);
  AmgPreconditioner amg;
  amg.setup(a);
  REQUIRE(amg.levels().size() >= 3);
  std::vector<double> set_up(r.size()), refreshed(r.size());
  amg.apply(r.data(), set_up.data());
  std::vector<int> own_rows = identity_rows(a.rows, a.rows);
  amg.refresh(a, own_rows);
  amg.apply(r.data(), refreshed.data());
  CHECK(std::memcmp(set_up.data(), refreshed.data(), r.size() * sizeof(double)) == 0);
}

TEST_CASE("AMG refreshed for moved points and changed unknowns stays SPD and converges", "[amg]") {
  // The base: a jittered lattice of 60 x 50 unknowns. The new systems: every point moved by
  // up to 0.05 l0 more (one step's motion at a Courant number of 0.05), and the top row of
  // unknowns gone to the free surface (base rows without a current row) or one row of unknowns
  // added (current rows without a base row: the smoother alone treats them).
  const CsrMatrix base = particle_matrix(60, 50, {0.20, false, 0.0});
  struct Case {
    const char* name;
    CsrMatrix matrix;
  };
  const std::vector<Case> cases = {{"moved", particle_matrix(60, 50, {0.25, false, 0.0})},
                                   {"top row dry", particle_matrix(60, 49, {0.25, false, 0.0})},
                                   {"a row more", particle_matrix(60, 51, {0.25, false, 0.0})}};
  for (const Case& test : cases) {
    INFO(test.name);
    // The new system's unknowns in a shuffled order: row new_row[r] stands for the lattice's
    // unknown r, which is base row r when the base has it.
    std::vector<int> new_row(static_cast<std::size_t>(test.matrix.rows));
    for (int r = 0; r < test.matrix.rows; ++r) new_row[static_cast<std::size_t>(r)] = r;
    std::shuffle(new_row.begin(), new_row.end(), std::mt19937_64(99));
    const CsrMatrix a = permuted(test.matrix, new_row);
    const std::vector<int> lattice_rows = identity_rows(test.matrix.rows, base.rows);
    std::vector<int> base_row_of_row(lattice_rows.size());
    for (std::size_t r = 0; r < lattice_rows.size(); ++r)
      base_row_of_row[static_cast<std::size_t>(new_row[r])] = lattice_rows[r];
    AmgPreconditioner fresh;
    fresh.setup(a);
    AmgPreconditioner reused;
    reused.setup(base);
    reused.refresh(a, base_row_of_row);
    for (unsigned seed = 1; seed <= 3; ++seed) {
      const std::vector<double> r1 = random_vector(a.rows, seed), r2 = random_vector(a.rows, seed + 100);
      std::vector<double> z1(r1.size()), z2(r2.size());
      reused.apply(r1.data(), z1.data());
      reused.apply(r2.data(), z2.data());
      CHECK(std::abs(dot(z1, r2) - dot(r1, z2)) <= 1e-12 * std::sqrt(dot(z1, z1) * dot(r2, r2)));
      CHECK(dot(z1, r1) > 0.0);
    }
    const long long with_fresh = project_cg_iterations(a, fresh);
    const long long with_reused = project_cg_iterations(a, reused);
    std::printf("[amg] refreshed hierarchy, %-12s CG iterations: set-up %lld, reused %lld\n", test.name, with_fresh,
                with_reused);
    // Measured: reused as many as set up (16, 17, 16: the set-up on the shuffled order
    // aggregates worse than the lattice-ordered base). Rows matched to the wrong base rows
    // (identity instead of new_row) cost 257-263, more than Jacobi.
    CHECK(with_reused <= with_fresh + 4);
  }
}
