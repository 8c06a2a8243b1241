#include "methods/mps/mps_pressure.hpp"

#include <stdexcept>

#include "core/linalg/amg.hpp"
#include "core/linalg/pressure_system.hpp"

namespace mps_lab::mps {

namespace {

// The row blocks of the incomplete Cholesky preconditioner: fixed (not the thread count), so
// that the result does not depend on it; two blocks let two threads factor and solve at once.
constexpr int kIncompleteCholeskyBlocks = 2;

}  // namespace

std::unique_ptr<Preconditioner> make_preconditioner(const std::string& name) {
  if (name == "jacobi") return std::make_unique<JacobiPreconditioner>();
  if (name == "incomplete_cholesky") return std::make_unique<IncompleteLuPreconditioner>(kIncompleteCholeskyBlocks);
  if (name == "amg") return std::make_unique<AmgPreconditioner>();  // core/linalg/amg.hpp, smoothed aggregation
  throw std::invalid_argument("unknown preconditioner '" + name + "' (expected jacobi, incomplete_cholesky or amg)");
}

Eigen::SparseMatrix<double, Eigen::RowMajor> PressurePoissonSolver::matrix() const { return to_eigen(matrix_); }

PressureSolveResult PressurePoissonSolver::assemble(ParticleSet& particles, const NeighbourList& neighbours,
                                                    const WallSampleList& samples,
                                                    const std::vector<double>& number_density,
                                                    const std::vector<char>& carries_pressure,
                                                    const OperatorRadius& laplacian, double n0, double dt,
                                                    const PressureSolveSettings& settings,
                                                    std::vector<double>& free_surface) {
  PressureSolveResult result;
  const std::size_t n = particles.size();
  row_of_.assign(n, -1);
  particle_of_.clear();
  free_surface.assign(n, 0.0);

  // Free-surface detection (spec §3, §7): n*_i / n0 < beta -> surface, P = 0. Unknowns are
  // numbered in particle order.
  for (std::size_t i = 0; i < n; ++i) {
    if (!carries_pressure[i] || particles.type[i] == ParticleType::Ghost) continue;
    if (number_density[i] < settings.free_surface_threshold * n0) {
      free_surface[i] = 1.0;
      particles.pressure[i] = 0.0;
      ++result.surface;
    } else {
      row_of_[i] = static_cast<int>(particle_of_.size());
      particle_of_.push_back(static_cast<int>(i));
    }
  }
  const auto unknowns = static_cast<int>(particle_of_.size());
  result.unknowns = particle_of_.size();
  matrix_.rows = 0;
  if (unknowns == 0) return result;

  // Assembly: a_ij = (2d / (n0_L lambda_L)) w_L(r_ij) (spec §2 Laplacian), A_ii = sum_j a_ij,
  // A_ij = -a_ij; the diagonal is stored first in its row. Rows in parallel: row i reads only.
  const double coefficient = 2.0 * kDimension / (laplacian.n0 * laplacian.lambda);  // 1/m^2
  const double source = settings.relaxation * settings.density / (dt * dt);        // kg/(m^3 s^2)
  const bool with_samples = samples.has_samples();
  rhs_.resize(static_cast<std::size_t>(unknowns));
  grounded_.assign(static_cast<std::size_t>(unknowns), 0);
  assembler_.start(unknowns, [&](int row) {
    const auto i = static_cast<std::size_t>(particle_of_[static_cast<std::size_t>(row)]);
    return static_cast<int>(1 + neighbours.count(i) + (with_samples ? samples.end(i) - samples.begin(i) : 0));
  });
#pragma omp parallel for schedule(static)
  for (int row = 0; row < unknowns; ++row) {
    const auto i = static_cast<std::size_t>(particle_of_[static_cast<std::size_t>(row)]);
    auto writer = assembler_.row(row);
    writer.add(row, 0.0);  // the diagonal, summed below
    double diagonal = 0.0;
    bool grounded = false;
    for (std::uint32_t k = neighbours.begin(i); k < neighbours.end(i); ++k) {
      const std::uint32_t j = neighbours.indices[k];
      if (!carries_pressure[j] || particles.type[j] == ParticleType::Ghost) continue;
      const double a = coefficient *
                       mps_weight((particles.position[j] - particles.position[i]).norm(), laplacian.re, laplacian.r_min);
      if (a == 0.0) continue;
      diagonal += a;
      if (row_of_[j] >= 0) {
        writer.add(row_of_[j], -a);
      } else {
        grounded = true;  // a Dirichlet (P = 0) neighbour
      }
    }
    double wall_part = 0.0;  // known part of the wall samples' Laplacian terms, moved to b_i
    if (with_samples) {
      for (std::uint32_t k = samples.begin(i); k < samples.end(i); ++k) {
        const WallSample& wall = samples.samples[k];
        const double a = coefficient * wall.volume *
                         mps_weight((wall.position - particles.position[i]).norm(), laplacian.re, laplacian.r_min);
        if (a == 0.0) continue;
        wall_part += a * sample_pressure_offset(wall, particles.position, settings.density, settings.gravity);
        if (wall.source == i) continue;  // p_i - p_i
        diagonal += a;
        if (row_of_[wall.source] >= 0) {
          writer.add(row_of_[wall.source], -a);
        } else {
          grounded = true;  // the image of a Dirichlet particle
        }
      }
    }
    if (diagonal == 0.0) {  // isolated: no pressure-carrying neighbour at all
      diagonal = 1.0;
      grounded = true;
    }
    writer.value(0) = diagonal;
    writer.close();
    grounded_[static_cast<std::size_t>(row)] = grounded ? 1 : 0;
    // b_i = relaxation (rho/dt^2) (n*_i - n0)/n0   [sign: A = -<lap>]
    rhs_[static_cast<std::size_t>(row)] = source * (number_density[i] - n0) / n0 + wall_part;
  }
  assembler_.finish(matrix_, /*diagonal_first=*/true);

  // A group of unknowns with no Dirichlet row (core/linalg/pressure_system.hpp) makes A singular
  // (pressure defined up to a constant). The remedy of the public MPS-Basic code (Kondo lab)
  // is kept: double the diagonal of such a group's rows, which pins its mean pressure near zero.
  result.ungrounded_groups = pin_ungrounded_groups(matrix_, grounded_, particle_of_.size());
  return result;
}

void PressurePoissonSolver::solve_assembled(ParticleSet& particles, const PressureSolveSettings& settings,
                                            PressureSolveResult& result) {
  const int unknowns = matrix_.rows;
  if (unknowns == 0) return;
  if (!preconditioner_ || preconditioner_name_ != settings.preconditioner) {
    preconditioner_ = make_preconditioner(settings.preconditioner);
    preconditioner_name_ = settings.preconditioner;
  }
  preconditioner_->setup(matrix_);

  gather_unknowns(particles.pressure, particle_of_, settings.warm_start, solution_);

  KrylovSettings krylov;
  krylov.tolerance = settings.tolerance;
  krylov.max_iterations = settings.max_iterations;
  const KrylovResult solved = conjugate_gradient(matrix_, rhs_.data(), solution_.data(), *preconditioner_, krylov, workspace_);
  result.iterations = solved.iterations;
  result.residual = solved.residual;
  result.converged = solved.converged;

  scatter_unknowns(solution_, particle_of_, settings.clamp_negative, particles.pressure);  // spec §5.2-7
}

}  // namespace mps_lab::mps
