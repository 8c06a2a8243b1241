// SPH kernels (core/kernels/sph_kernels.hpp): normalisation, odd gradients, partition of unity.
#include <catch2/catch.hpp>

#include "core/kernels/sph_kernels.hpp"

using namespace mps_lab;

namespace {
constexpr double kPi = 3.14159265358979323846;
}

TEST_CASE("SPH kernels integrate to one over their support", "[kernels][sph]") {
  // 2-D integral 2 pi int_0^R W(r) r dr by composite Simpson with 20000 intervals: the
  // kernels are piecewise polynomials (C1 at the cubic spline's q = 1 knot), so the
  // quadrature error is below 1e-10; the tolerance 1e-8 leaves room for round-off.
  for (auto kind : {SphKernelKind::CubicSpline, SphKernelKind::WendlandC2}) {
    for (double support : {0.05, 0.06, 1.0}) {
      const SphKernel kernel(kind, support);
      const int intervals = 20000;
      const double h = support / intervals;
      double sum = 0.0;
      for (int k = 0; k <= intervals; ++k) {
        const double r = k * h;
        const double weight = (k == 0 || k == intervals) ? 1.0 : (k % 2 == 1 ? 4.0 : 2.0);
        sum += weight * kernel.value(r) * r;
      }
      const double integral = 2.0 * kPi * sum * h / 3.0;
      CHECK(integral == Approx(1.0).epsilon(1e-8));
      CHECK(kernel.value(support) == 0.0);
      CHECK(kernel.value(1.5 * support) == 0.0);
      CHECK(kernel.derivative(support) == Approx(0.0).margin(1e-12));
    }
  }
}

TEST_CASE("SPH kernel gradients are odd and match the derivative of W", "[kernels][sph]") {
  for (auto kind : {SphKernelKind::CubicSpline, SphKernelKind::WendlandC2}) {
    const SphKernel kernel(kind, 0.06);
    for (const Vec2& r : {Vec2(0.01, 0.0), Vec2(0.013, -0.021), Vec2(-0.03, 0.035), Vec2(0.0, 0.0299)}) {
      const Vec2 plus = kernel.gradient(r), minus = kernel.gradient(-r);
      CHECK((plus + minus).norm() == Approx(0.0).margin(1e-12 * plus.norm() + 1e-300));
      // Central difference of W along each axis: error O(h^2 W''') ~ 1e-9 relative here.
      const double step = 1e-7;
      for (int axis = 0; axis < 2; ++axis) {
        Vec2 e = Vec2::Zero();
        e[axis] = step;
        const double numeric = (kernel.value((r + e).norm()) - kernel.value((r - e).norm())) / (2 * step);
        CHECK(plus[axis] == Approx(numeric).epsilon(1e-5).margin(1e-6 * kernel.value(0.0) / 0.06));
      }
    }
    CHECK(kernel.gradient(Vec2::Zero()).norm() == 0.0);
    CHECK(kernel.derivative(0.0) == Approx(0.0).margin(1e-12));  // smooth at the origin
  }
}

TEST_CASE("discrete partition of unity on a lattice", "[kernels][sph]") {
  // sum_j W(x - x_j) l0^2 approximates int W = 1; the lattice quadrature error depends on
  // the support in spacings and on where x sits in the cell. Measured at x = lattice point,
  // (0.3, 0.1) l0 and cell centre: cubic spline |error| <= 3.7e-3 (support 2.4 l0) and
  // 3.8e-3 (3.0 l0); Wendland C2 <= 1.8e-2 (2.4 l0) and 5.1e-3 (3.0 l0), its flatter top
  // being sampled worse at small support. Tolerances 5e-3 (cubic) and 2e-2 (Wendland) sit
  // just above these. The gradient sums to zero at a lattice point (symmetry).
  const double l0 = 0.025;
  const struct {
    SphKernelKind kind;
    double support_over_l0;
    double tolerance;
  } cases[] = {{SphKernelKind::CubicSpline, 2.4, 5e-3},
               {SphKernelKind::CubicSpline, 3.0, 5e-3},
               {SphKernelKind::WendlandC2, 2.4, 2e-2},
               {SphKernelKind::WendlandC2, 3.0, 2e-2}};
  for (const auto& c : cases) {
    const SphKernel kernel(c.kind, c.support_over_l0 * l0);
    for (const Vec2& x : {Vec2(0.0, 0.0), Vec2(0.3 * l0, 0.1 * l0), Vec2(0.5 * l0, 0.5 * l0)}) {
      double sum = 0.0;
      Vec2 gradient_sum = Vec2::Zero();
      for (int i = -5; i <= 5; ++i) {
        for (int j = -5; j <= 5; ++j) {
          const Vec2 xj(i * l0, j * l0);
          sum += kernel.value((x - xj).norm()) * l0 * l0;
          gradient_sum += kernel.gradient(x - xj) * l0 * l0;
        }
      }
      INFO("kind " << static_cast<int>(c.kind) << " support " << c.support_over_l0 << " l0 at " << x.transpose());
      CHECK(sum == Approx(1.0).margin(c.tolerance));
      if (x.isZero()) CHECK(gradient_sum.norm() == Approx(0.0).margin(1e-9));
    }
  }
}
