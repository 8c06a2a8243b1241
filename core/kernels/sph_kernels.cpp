#include "core/kernels/sph_kernels.hpp"

#include <cmath>
#include <stdexcept>

namespace mps_lab {

namespace {
constexpr double kPi = 3.14159265358979323846;
}

SphKernelKind sph_kernel_from_name(const std::string& name) {
  if (name == "cubic_spline") return SphKernelKind::CubicSpline;
  if (name == "wendland_c2") return SphKernelKind::WendlandC2;
  throw std::invalid_argument("unknown SPH kernel '" + name + "' (expected cubic_spline or wendland_c2)");
}

SphKernel::SphKernel(SphKernelKind kind, double support) : kind_(kind), support_(support) {
  if (!(support > 0.0)) throw std::invalid_argument("SPH kernel support must be > 0");
  if (kind == SphKernelKind::CubicSpline) {
    const double h = 0.5 * support;
    scale_ = 1.0 / h;
    sigma_ = 10.0 / (7.0 * kPi * h * h);
  } else {
    scale_ = 1.0 / support;
    sigma_ = 7.0 / (kPi * support * support);
  }
}

double lattice_kernel_sum(const SphKernel& kernel, double spacing) {
  const int reach = static_cast<int>(std::ceil(kernel.support() / spacing));
  double sum = 0.0;
  for (int j = -reach; j <= reach; ++j) {
    for (int i = -reach; i <= reach; ++i) {
      sum += kernel.value(spacing * std::hypot(static_cast<double>(i), static_cast<double>(j)));
    }
  }
  return sum;
}

}  // namespace mps_lab
