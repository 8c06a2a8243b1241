#include "methods/dfsph/dfsph_global_density.hpp"

#include <algorithm>
#include <cstddef>

#include "core/linalg/pressure_system.hpp"

namespace mps_lab::dfsph {
namespace {

// The pair coefficients of one step: c_ij = m_j grad W_ij of neighbour pair k (kg/m^4).
struct Pairs {
  const std::uint32_t* offsets;
  const std::uint32_t* neighbour;
  const Vec2* gradient;
  const double* mass;
  Vec2 c(std::uint32_t k) const { return mass[neighbour[k]] * gradient[k]; }
};

Pairs pairs_of(const ParticleSet& particles, const SphSystem& system, GlobalDensityWorkspace& w) {
  const std::size_t n = particles.size();
  const double* mass = system.kernel.neighbour_mass.data();
  if (system.kernel.neighbour_mass.size() != n) {  // as compute_kernel_cache with the masses
    w.neighbour_mass.resize(n);
    for (std::size_t j = 0; j < n; ++j) {
      w.neighbour_mass[j] = neighbour_mass_of(particles, system.particle_mass, system.boundary_mass, j);
    }
    mass = w.neighbour_mass.data();
  }
  return Pairs{system.neighbours.offsets.data(), system.neighbours.indices.data(), system.kernel.gradient.data(), mass};
}

// The unknowns: fluid particles with at least min_neighbours fluid + boundary neighbours.
void select_unknowns(const ParticleSet& particles, const std::vector<double>& counts, std::uint32_t min_neighbours,
                     GlobalDensityWorkspace& w) {
  const std::size_t n = particles.size();
  w.row_of.assign(n, -1);
  w.particle_of.clear();
  for (std::size_t i = 0; i < n; ++i) {
    if (particles.type[i] == ParticleType::Fluid && counts[i] >= static_cast<double>(min_neighbours)) {
      w.row_of[i] = static_cast<int>(w.particle_of.size());
      w.particle_of.push_back(static_cast<int>(i));
    }
  }
}

// The right-hand side of every unknown, from the velocities before the correction (boundary
// particles at their prescribed velocity): the predicted excess of every fluid particle,
//   e_i = rho_i + dt D_i(v) - rho0,  D_i(v) = sum_j c_ij . (v_i - v_j)  ([BK17] eq. (9)),
// averaged over the fluid in the kernel's support (Shepard weights W_ij, i itself included)
// and only then clamped at 0:
//   b_i = max(sum_j W_ij e_j / sum_j W_ij, 0) / dt^2.
// Compression only, as [BK17]'s clamp, but the clamp comes after the average: a mode that
// compresses and expands neighbours in turn averages to about 0 and is left to the Jacobi
// iteration, which resolves it locally. Clamped first (b_i = max(e_i, 0) / dt^2), it would be a
// net source, which the global solve spreads over the whole column as a smooth pressure that
// cannot undo it: at a million particles such a mode grew at the column's corner until the run
// diverged at step 59 (with 2 Jacobi iterations per step) or 103 (with 10).
void right_hand_side(const ParticleSet& particles, const SphSystem& system, const Pairs& pairs,
                     const std::vector<double>& density, double dt, GlobalDensityWorkspace& w) {
  const auto rows = static_cast<std::ptrdiff_t>(w.particle_of.size());
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
  w.rhs.resize(w.particle_of.size());
  w.excess.resize(particles.size());
  const auto velocity = [&](std::uint32_t j) {
    return particles.type[j] == ParticleType::Fluid ? particles.velocity[j] : particles.prescribed_wall_velocity(j);
  };
  const double rho0 = system.rest_density;
#pragma omp parallel
  {
#pragma omp for schedule(static)
    for (std::ptrdiff_t i = 0; i < n; ++i) {
      if (particles.type[i] != ParticleType::Fluid) continue;
      const Vec2 vi = particles.velocity[i];
      double rate = 0.0;  // kg/(m^3 s)
      for (std::uint32_t k = pairs.offsets[i]; k < pairs.offsets[i + 1]; ++k) {
        rate += pairs.c(k).dot(vi - velocity(pairs.neighbour[k]));
      }
      w.excess[i] = density[i] + dt * rate - rho0;
    }
#pragma omp for schedule(static)
    for (std::ptrdiff_t r = 0; r < rows; ++r) {
      const auto i = static_cast<std::uint32_t>(w.particle_of[static_cast<std::size_t>(r)]);
      double sum = system.kernel.self_value * w.excess[i], weight = system.kernel.self_value;
      for (std::uint32_t k = pairs.offsets[i]; k < pairs.offsets[i + 1]; ++k) {
        const std::uint32_t j = pairs.neighbour[k];
        if (j == i || particles.type[j] != ParticleType::Fluid) continue;
        sum += system.kernel.value[k] * w.excess[j];
        weight += system.kernel.value[k];
      }
      w.rhs[static_cast<std::size_t>(r)] = std::max(sum / weight, 0.0) / (dt * dt);
    }
  }
}

// The pair coefficient of the surrogate (header), kg^2/m^8:
//   a_ij = 2 rho0 m (-r_ij . grad W_ij) / (|r_ij|^2 + eta^2),  r_ij = x_i - x_j,
// the Laplacian of Cummins & Rudman (1999) for a uniform density rho0, times rho0^2 (A ~ -rho0^2 lap).
inline double pair_coefficient(const ParticleSet& particles, const Pairs& pairs, std::uint32_t i, std::uint32_t k,
                               double mass_times_2rho0, double eta2) {
  const Vec2 r = particles.position[i] - particles.position[pairs.neighbour[k]];
  return mass_times_2rho0 * (-r.dot(pairs.gradient[k])) / (r.squaredNorm() + eta2);
}

// Rows in parallel (CsrInPlaceAssembler): the diagonal sum_j a_ij over every fluid neighbour
// (an unknown or not: a fluid neighbour that is not an unknown is at s = 0, Dirichlet), first,
// then -a_ij for each unknown neighbour; a boundary neighbour adds nothing (Neumann: the
// mirrored wall pressure, p_b = p_i). A row with a Dirichlet neighbour is grounded.
void assemble_rows(const ParticleSet& particles, const SphSystem& system, const Pairs& pairs,
                   GlobalDensityWorkspace& w) {
  const int rows = static_cast<int>(w.particle_of.size());
  const double mass_times_2rho0 = 2.0 * system.rest_density * system.particle_mass;
  const double eta2 = 0.01 * system.particle_mass / system.rest_density;  // (0.1 l0)^2, m^2
  w.grounded.assign(static_cast<std::size_t>(rows), 0);
  CsrInPlaceAssembler assembler;
  assembler.start(w.matrix, rows);
  const bool threaded = rows >= static_cast<int>(kThreadedLoopMinimum);
#pragma omp parallel if (threaded)
  {
#pragma omp for schedule(static)
    for (int r = 0; r < rows; ++r) {
      const auto i = static_cast<std::uint32_t>(w.particle_of[static_cast<std::size_t>(r)]);
      int length = 1;
      for (std::uint32_t k = pairs.offsets[i]; k < pairs.offsets[i + 1]; ++k) {
        const std::uint32_t j = pairs.neighbour[k];
        if (j != i && w.row_of[j] >= 0) ++length;
      }
      assembler.count(r, length);
    }
#pragma omp single
    assembler.place(w.matrix);
#pragma omp for schedule(static)
    for (int r = 0; r < rows; ++r) {
      const auto i = static_cast<std::uint32_t>(w.particle_of[static_cast<std::size_t>(r)]);
      auto writer = assembler.row(r);
      writer.add(r, 0.0);
      double diagonal = 0.0;
      for (std::uint32_t k = pairs.offsets[i]; k < pairs.offsets[i + 1]; ++k) {
        const std::uint32_t j = pairs.neighbour[k];
        if (j == i || particles.type[j] != ParticleType::Fluid) continue;
        const double a = pair_coefficient(particles, pairs, i, k, mass_times_2rho0, eta2);
        diagonal += a;
        if (w.row_of[j] >= 0) {
          writer.add(w.row_of[j], -a);
        } else {
          w.grounded[static_cast<std::size_t>(r)] = 1;
        }
      }
      writer.value(0) = diagonal;
      writer.close();
    }
  }
  assembler.finish(w.matrix, /*diagonal_first=*/true);
}

}  // namespace

std::size_t assemble_density_system(const ParticleSet& particles, const SphSystem& system,
                                    const std::vector<double>& counts, const GlobalDensitySettings& settings,
                                    GlobalDensityWorkspace& workspace) {
  GlobalDensityWorkspace& w = workspace;
  const Pairs pairs = pairs_of(particles, system, w);
  select_unknowns(particles, counts, settings.min_neighbours, w);
  assemble_rows(particles, system, pairs, w);
  // A group of unknowns without a Dirichlet neighbour (water filling a closed tank) is
  // singular: its level is pinned as mps's and isph's are (core/linalg/pressure_system.hpp).
  w.ungrounded_groups = pin_ungrounded_groups(w.matrix, w.grounded, w.particle_of.size(), w.reached);
  if (!w.preconditioner) w.preconditioner = make_preconditioner(PreconditionerKind::Amg);
  if (w.matrix.rows > 0) w.preconditioner->setup(w.matrix);
  return w.particle_of.size();
}

void density_right_hand_side(const ParticleSet& particles, const SphSystem& system, const std::vector<double>& density,
                             double dt, GlobalDensityWorkspace& workspace) {
  right_hand_side(particles, system, pairs_of(particles, system, workspace), density, dt, workspace);
}

GlobalDensityOutcome add_density_increment(const ParticleSet& particles, const SphSystem& system,
                                           const std::vector<double>& density, double dt,
                                           const GlobalDensitySettings& settings, std::vector<double>& stiffness,
                                           GlobalDensityWorkspace& workspace) {
  GlobalDensityWorkspace& w = workspace;
  GlobalDensityOutcome outcome;
  outcome.unknowns = w.particle_of.size();
  density_right_hand_side(particles, system, density, dt, w);
  if (std::none_of(w.rhs.begin(), w.rhs.end(), [](double b) { return b > 0.0; })) return outcome;
  w.solution.assign(w.rhs.size(), 0.0);
  KrylovSettings krylov;
  krylov.tolerance = settings.tolerance;
  krylov.max_iterations = settings.max_iterations;
  const KrylovResult solved =
      conjugate_gradient(w.matrix, w.rhs.data(), w.solution.data(), *w.preconditioner, krylov, w.krylov);
  outcome.iterations = solved.iterations;
  outcome.residual = solved.residual;
  outcome.converged = solved.converged;
  outcome.solved = true;
  const auto rows = static_cast<std::ptrdiff_t>(w.particle_of.size());
#pragma omp parallel for schedule(static) if (rows >= kThreadedLoopMinimum)
  for (std::ptrdiff_t r = 0; r < rows; ++r) {  // kappa += rho ds, kept >= 0 ([BK17]: only compression)
    const auto i = static_cast<std::size_t>(w.particle_of[static_cast<std::size_t>(r)]);
    stiffness[i] = std::max(stiffness[i] + density[i] * w.solution[static_cast<std::size_t>(r)], 0.0);
  }
  return outcome;
}

}  // namespace mps_lab::dfsph
