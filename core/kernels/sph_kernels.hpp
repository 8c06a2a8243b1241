#pragma once
// Standard SPH kernels in 2-D, for the SPH-family methods (ISPH, DFSPH).
//
// Both kernels are written with the support radius `support` (= where W becomes zero),
// not the smoothing length h, so a method states its choice once: e.g. the cubic spline
// with h = 1.2 l0 has support 2h = 2.4 l0.
//   cubic spline (Monaghan 1992; Monaghan & Lattanzio 1985), q = r/h, h = support/2:
//     W = sigma [1 - 3/2 q^2 + 3/4 q^3]   0 <= q < 1
//         sigma [1/4 (2 - q)^3]           1 <= q < 2,     sigma = 10 / (7 pi h^2)
//   Wendland C2 (Wendland 1995; Dehnen & Aly 2012), q = r/H, H = support:
//     W = sigma (1 - q)^4 (1 + 4 q)       0 <= q < 1,     sigma = 7 / (pi H^2)
// Gradients: grad_i W(x_i - x_j) = dW/dr * (x_i - x_j) / r (odd in x_i - x_j, zero at r = 0).
#include <string>

#include "core/base/types.hpp"

namespace mps_lab {

enum class SphKernelKind { CubicSpline, WendlandC2 };

SphKernelKind sph_kernel_from_name(const std::string& name);  // "cubic_spline" | "wendland_c2"

class SphKernel {
 public:
  SphKernel(SphKernelKind kind, double support);

  double support() const { return support_; }  // m
  SphKernelKind kind() const { return kind_; }
  double value(double r) const;       // 1/m^2
  double derivative(double r) const;  // dW/dr, 1/m^3
  // grad W with respect to x_i of W(|x_i - x_j|); `r_ij` = x_i - x_j.
  Vec2 gradient(const Vec2& r_ij) const {
    const double r = r_ij.norm();
    if (r <= 0.0 || r >= support_) return Vec2::Zero();
    return derivative(r) / r * r_ij;
  }

 private:
  SphKernelKind kind_;
  double support_;
  double sigma_;  // normalisation, 1/m^2
  double scale_;  // 1/h (cubic) or 1/H (Wendland), 1/m
};

// Sum of W over the square lattice of the given spacing for a particle at a lattice point,
// the particle itself included (1/m^2). m = rho0 / this sum makes the summation density of a
// particle with full support exactly rho0; sum * spacing^2 is the lattice partition of unity.
double lattice_kernel_sum(const SphKernel& kernel, double spacing);

// Inline: the operators call these once per neighbour pair. Both pieces of the cubic spline
// are computed and one is selected (no branch on q, which neighbours straddle at random;
// docs/performance.md), with the same expressions as a branch would evaluate, so the values
// are bit for bit those of the branching form.
inline double SphKernel::value(double r) const {
  const double q = r * scale_;
  if (kind_ == SphKernelKind::CubicSpline) {
    const double s = 2.0 - q;
    const double inner = sigma_ * (1.0 - 1.5 * q * q + 0.75 * q * q * q);
    const double outer = sigma_ * 0.25 * s * s * s;
    const double tail = q < 2.0 ? outer : 0.0;
    return q < 1.0 ? inner : tail;
  }
  const double s = 1.0 - q;
  const double inside = sigma_ * s * s * s * s * (1.0 + 4.0 * q);
  return q >= 1.0 ? 0.0 : inside;
}

inline double SphKernel::derivative(double r) const {
  const double q = r * scale_;
  if (kind_ == SphKernelKind::CubicSpline) {
    const double s = 2.0 - q;
    const double inner = sigma_ * scale_ * (-3.0 * q + 2.25 * q * q);
    const double outer = -sigma_ * scale_ * 0.75 * s * s;
    const double tail = q < 2.0 ? outer : 0.0;
    return q < 1.0 ? inner : tail;
  }
  const double s = 1.0 - q;
  const double inside = -20.0 * sigma_ * scale_ * q * s * s * s;  // d/dq [(1-q)^4 (1+4q)] = -20 q (1-q)^3
  return q >= 1.0 ? 0.0 : inside;
}

}  // namespace mps_lab
