// Particle shifting (a measure at after_correction, every method): each fluid particle moves a
// little down the gradient of the particle concentration, so that a disordered arrangement
// relaxes towards a uniform one (Fickian shifting, Lind et al. 2012, J. Comput. Phys. 231;
// the coefficient of Skillen et al. 2013, Comput. Methods Appl. Mech. Engrg. 265):
//   C_i      = V sum_j W_ij                     concentration (Lind 2012 eq. 11), j over fluid and
//                                               wall particles and wall samples (volume V_w / l0^2)
//   grad C_i = V sum_j grad_i W_ij              (Lind 2012 eq. 12)
//   div r_i  = -V sum_j r_ij . grad_i W_ij      r_ij = x_i - x_j; 2 inside a 2-D fluid, about 1 on
//                                               its free surface (Lee et al. 2008)
//   dr_i     = -D_i s_i grad C_i,  D_i = (A |u_i| dt + B h) h
//              A = `coefficient` (Skillen 2013: D = A h |u| dt, A in [1, 6], 2 their choice);
//              B = `fixed_coefficient` (0 by default): a part of D that does not vanish with the
//              flow, as Lind 2012's D fixed per step in units of h^2; it keeps ordering water at
//              rest. An explicit diffusion step is stable for D <= h^2 / 2 (B < 0.5)
//   s_i      = clamp((div r_i - t) / (d - t), 0, 1),  t = `free_surface_threshold`
//              (the free-surface correction of Mokos 2013 / DualSPHysics: no shifting on the
//               surface, where the truncated support would pull particles out of the water,
//               full shifting inside, a ramp between; d = div r of a particle inside the square
//               lattice, 1.899 for a support of 2.1 l0, 1.894 for 2.4 l0: the discrete sum's 2)
//   u_i     += (grad u)_i dr_i,  (grad u)_i = V sum_j (u_j - u_i) (x) grad_i W_ij
//              (`velocity_correction`, off by default: the velocity carried to the new position by
//               its Taylor expansion, Xu et al. 2009, Lind et al. 2012. It injects energy on the
//               dam break: kinetic energy at 2 s 32.7 J/m with it, 11.1 without, 11.7 unshifted for
//               dfsph; 10.7, 7.8 and 9.6 for mps (docs/walls.md, "Particle shifting"))
// with the Wendland C2 kernel of support the method's operator support (h = support / 2: the
// smoothing length of a cubic spline of the same support) and V = 1 / (the kernel's lattice sum),
// so that C = 1 and grad C = 0 on the square lattice at the scene's spacing. Every shift is computed
// from the positions before any shift of this step (a Jacobi sweep: independent of particle order
// and thread count). It acts at the end of the step, on the positions the step leaves (a method
// may rebuild its positions from the step's start after the search: isph's r^n + dt u^{n+1}, so
// a shift made there would be lost), with its own neighbour search at those positions: the
// method's list is from the step's search (dfsph's from its start, 0.6 l0 behind a splash at
// 3 m/s and 5e-3 s). The wall samples are the method's, from its search (a wall sample is a
// fixed wall point; those that came within the support since are missing). Runs before the
// position clamp (order 5 < 10), which puts back a particle shifted past a wall. Model only
// what a scene asks for: off by default.
#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#include "core/io/scene.hpp"
#include "core/kernels/sph_kernels.hpp"
#include "core/search/neighbour_search.hpp"
#include "core/walls/wall_treatment.hpp"

namespace mps_lab {
namespace {

// What the shift of one fluid particle is built from (the sums above).
struct ShiftingSums {
  Vec2 concentration_gradient = Vec2::Zero();  // grad C, 1/m
  double position_divergence = 0.0;            // div r
  Mat2 velocity_gradient = Mat2::Zero();       // (grad u)_ab = d u_a / d x_b, 1/s
};

class ParticleShifting final : public WallTreatment {
 public:
  explicit ParticleShifting(const WallTreatmentSetup& setup)
      : spacing_(setup.scene.particle_spacing),
        coefficient_(setup.parameters.number("coefficient")),
        fixed_coefficient_(setup.parameters.number("fixed_coefficient")),
        free_surface_threshold_(setup.parameters.number("free_surface_threshold")),
        velocity_correction_(setup.parameters.boolean("velocity_correction")) {}

  void after_correction(WallContext& context) override {
    set_kernel(context.support);
    cells_.build(context.particles.position, context.particles.type, kernel_->support());
    cells_.find_neighbours(context.particles.position, context.particles.type, kernel_->support(), neighbours_);
    const auto n = static_cast<std::ptrdiff_t>(context.particles.size());
    shifts_.assign(context.particles.size(), Vec2::Zero());
    velocity_changes_.assign(context.particles.size(), Vec2::Zero());
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      if (context.particles.type[i] != ParticleType::Fluid) continue;
      const ShiftingSums sums = shifting_sums(context, static_cast<std::size_t>(i));
      shifts_[i] = shift(sums, context.particles.velocity[i].norm(), context.dt);
      if (velocity_correction_) velocity_changes_[i] = sums.velocity_gradient * shifts_[i];
    }
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      context.particles.position[i] += shifts_[i];
      context.particles.velocity[i] += velocity_changes_[i];
    }
  }

 private:
  // The kernel follows the method's operator support (known at the first hook).
  void set_kernel(double support) {
    if (kernel_ != nullptr && kernel_->support() == support) return;
    if (support <= 0.0)
      throw std::logic_error("particle_shifting: the method set no operator support in its WallContext");
    kernel_ = std::make_unique<SphKernel>(SphKernelKind::WendlandC2, support);
    volume_ = 1.0 / lattice_kernel_sum(*kernel_, spacing_);
    inside_divergence_ = lattice_position_divergence();
    if (inside_divergence_ <= free_surface_threshold_) {
      throw std::logic_error("particle_shifting: free_surface_threshold is not below the lattice's div r");
    }
  }

  // div r of a particle inside the square lattice of spacing l0 (the ramp's full-shifting end).
  double lattice_position_divergence() const {
    const int reach = static_cast<int>(std::ceil(kernel_->support() / spacing_));
    double divergence = 0.0;
    for (int a = -reach; a <= reach; ++a) {
      for (int b = -reach; b <= reach; ++b) {
        const Vec2 r_ij = -spacing_ * Vec2(a, b);
        divergence -= volume_ * r_ij.dot(kernel_->gradient(r_ij));
      }
    }
    return divergence;
  }

  // The sums of particle i over its neighbours and wall samples (the header's equations).
  ShiftingSums shifting_sums(const WallContext& context, std::size_t i) const {
    const ParticleSet& particles = context.particles;
    const NeighbourList& neighbours = neighbours_;
    ShiftingSums sums;
    auto add = [&](const Vec2& x_j, const Vec2& u_j, double volume) {
      const Vec2 r_ij = particles.position[i] - x_j;
      const Vec2 grad_w = kernel_->gradient(r_ij);
      sums.concentration_gradient += volume * grad_w;
      sums.position_divergence -= volume * r_ij.dot(grad_w);
      sums.velocity_gradient += volume * (u_j - particles.velocity[i]) * grad_w.transpose();
    };
    for (std::uint32_t k = neighbours.begin(i); k < neighbours.end(i); ++k) {
      const std::uint32_t j = neighbours.indices[k];
      if (j == i || particles.type[j] == ParticleType::Ghost) continue;
      const bool wall = particles.type[j] == ParticleType::Wall;  // a wall moves as prescribed
      add(particles.position[j], wall ? particles.prescribed_wall_velocity(j) : particles.velocity[j], volume_);
    }
    if (context.samples != nullptr && context.samples->has_samples()) {
      for (std::uint32_t k = context.samples->begin(i); k < context.samples->end(i); ++k) {
        const WallSample& sample = context.samples->samples[k];
        add(sample.position, sample_velocity(sample, particles.velocity), volume_ * sample.volume);
      }
    }
    return sums;
  }

  // dr_i = -D_i s_i grad C_i, D_i = (A |u_i| dt + B h) h (Skillen et al. 2013 and a fixed part,
  // with the free-surface ramp s_i), m.
  Vec2 shift(const ShiftingSums& sums, double speed, double dt) const {
    const double smoothing_length = 0.5 * kernel_->support();
    const double ramp = std::clamp(
        (sums.position_divergence - free_surface_threshold_) / (inside_divergence_ - free_surface_threshold_), 0.0,
        1.0);
    const double diffusion = (coefficient_ * speed * dt + fixed_coefficient_ * smoothing_length) * smoothing_length;
    return -diffusion * ramp * sums.concentration_gradient;
  }

  double spacing_;            // l0, m
  double coefficient_;        // A
  double fixed_coefficient_;  // B
  double free_surface_threshold_;
  bool velocity_correction_;
  std::unique_ptr<SphKernel> kernel_;
  double volume_ = 0.0;             // V, m^2
  double inside_divergence_ = 2.0;  // d, div r inside the lattice
  CellList cells_;                  // the search at the step's end positions (reused storage)
  NeighbourList neighbours_;
  std::vector<Vec2> shifts_;            // this step's dr (reused storage)
  std::vector<Vec2> velocity_changes_;  // this step's (grad u) dr (reused storage)
};

}  // namespace
}  // namespace mps_lab

void mps_lab_register_wall_treatment_particle_shifting(mps_lab::WallTreatmentRegistry& registry) {
  using namespace mps_lab;
  WallTreatmentInfo info{
      "particle_shifting",
      "Fickian particle shifting down the concentration gradient, D = (A |u| dt + B h) h, none on the free "
      "surface (Lind et al. 2012; Skillen et al. 2013)",
      {number_parameter("coefficient", 2.0, "",
                        "A of the shifting coefficient D = (A |u| dt + B h) h (Skillen et al. 2013: A in 1-6)")
           .at_least(0.0)
           .at_most(6.0),
       number_parameter("fixed_coefficient", 0.0, "",
                        "B of D = (A |u| dt + B h) h: a part that does not vanish with the flow (Lind et al. 2012's "
                        "fixed D); orders water at rest; D <= h^2/2 keeps the explicit step stable")
           .at_least(0.0)
           .below(0.5),
       number_parameter("free_surface_threshold", 1.5, "",
                        "div r below which a particle is on the free surface and is not shifted; full shifting "
                        "from the lattice's div r (about 1.9) in, a ramp between (Mokos 2013)")
           .above(0.0)
           .below(1.85),
       boolean_parameter("velocity_correction", false,
                         "carry the velocity to the shifted position by its Taylor expansion (Lind et al. 2012; "
                         "off: it adds kinetic energy on the dam break, docs/walls.md)")},
      5,
      [](const WallTreatmentSetup& setup) { return std::make_unique<ParticleShifting>(setup); }};
  info.hooks = {WallHook::AfterCorrection};
  registry.add(std::move(info));
}
