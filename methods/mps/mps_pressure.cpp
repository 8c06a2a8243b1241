#include "methods/mps/mps_pressure.hpp"

#include <stdexcept>

#include <Eigen/IterativeLinearSolvers>

#include "core/pressure_system.hpp"

namespace mps_lab::mps {

namespace {

// A group of unknowns with no Dirichlet row (core/pressure_system.hpp) makes A singular
// (pressure defined up to a constant). The remedy of the public MPS-Basic code (Kondo lab) is
// kept: double the diagonal of such a group's rows, which pins its mean pressure near zero.
// Returns the number of groups fixed.
std::size_t regularise_ungrounded_groups(Eigen::SparseMatrix<double, Eigen::RowMajor>& matrix,
                                         const std::vector<char>& grounded) {
  const auto groups = ungrounded_groups(matrix, grounded);
  for (const auto& members : groups) {
    for (int row : members) matrix.coeffRef(row, row) *= 2.0;
  }
  return groups.size();
}

template <typename Solver>
void run_cg(Solver& solver, const Eigen::SparseMatrix<double, Eigen::RowMajor>& matrix, const Eigen::VectorXd& rhs,
            const Eigen::VectorXd& guess, const PressureSolveSettings& settings, Eigen::VectorXd& solution,
            PressureSolveResult& result) {
  solver.setTolerance(settings.tolerance);
  solver.setMaxIterations(static_cast<Eigen::Index>(settings.max_iterations));
  solver.compute(matrix);
  if (solver.info() != Eigen::Success) throw std::runtime_error("MPS pressure solve: preconditioner setup failed");
  if (settings.warm_start) {
    solution = solver.solveWithGuess(rhs, guess);
  } else {
    solution = solver.solve(rhs);
  }
  result.iterations = static_cast<long long>(solver.iterations());
  result.residual = solver.error();
  result.converged = solver.info() == Eigen::Success;
}

}  // namespace

PressureSolveResult PressurePoissonSolver::solve(ParticleSet& particles, const NeighbourList& neighbours,
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

  // Free-surface detection (spec §3, §7): n*_i / n0 < beta -> surface, P = 0.
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
  const auto unknowns = static_cast<Eigen::Index>(particle_of_.size());
  result.unknowns = particle_of_.size();
  if (unknowns == 0) return result;

  // Assembly: a_ij = (2d / (n0_L lambda_L)) w_L(r_ij).
  const double coefficient = 2.0 * kDimension / (laplacian.n0 * laplacian.lambda);  // 1/m^2
  const double source = settings.relaxation * settings.density / (dt * dt);        // kg/(m^3 s^2)
  triplets_.clear();
  rhs_.resize(unknowns);
  guess_.resize(unknowns);
  std::vector<char> grounded(static_cast<std::size_t>(unknowns), 0);
  for (Eigen::Index row = 0; row < unknowns; ++row) {
    const auto i = static_cast<std::size_t>(particle_of_[static_cast<std::size_t>(row)]);
    double diagonal = 0.0;
    for (std::uint32_t k = neighbours.begin(i); k < neighbours.end(i); ++k) {
      const std::uint32_t j = neighbours.indices[k];
      if (!carries_pressure[j] || particles.type[j] == ParticleType::Ghost) continue;
      const double a = coefficient *
                       mps_weight((particles.position[j] - particles.position[i]).norm(), laplacian.re, laplacian.r_min);
      if (a == 0.0) continue;
      diagonal += a;
      if (row_of_[j] >= 0) {
        triplets_.emplace_back(static_cast<int>(row), row_of_[j], -a);
      } else {
        grounded[static_cast<std::size_t>(row)] = 1;  // a Dirichlet (P = 0) neighbour
      }
    }
    double wall_part = 0.0;  // known part of the wall samples' Laplacian terms, moved to b_i
    if (samples.has_samples()) {
      for (std::uint32_t k = samples.begin(i); k < samples.end(i); ++k) {
        const WallSample& wall = samples.samples[k];
        const double a = coefficient * wall.volume *
                         mps_weight((wall.position - particles.position[i]).norm(), laplacian.re, laplacian.r_min);
        if (a == 0.0) continue;
        wall_part += a * sample_pressure_offset(wall, particles.position, settings.density, settings.gravity);
        if (wall.source == i) continue;  // p_i - p_i
        diagonal += a;
        if (row_of_[wall.source] >= 0) {
          triplets_.emplace_back(static_cast<int>(row), row_of_[wall.source], -a);
        } else {
          grounded[static_cast<std::size_t>(row)] = 1;  // the image of a Dirichlet particle
        }
      }
    }
    if (diagonal == 0.0) {  // isolated: no pressure-carrying neighbour at all
      diagonal = 1.0;
      grounded[static_cast<std::size_t>(row)] = 1;
    }
    triplets_.emplace_back(static_cast<int>(row), static_cast<int>(row), diagonal);
    // b_i = relaxation (rho/dt^2) (n*_i - n0)/n0   [sign: A = -<lap>]
    rhs_[row] = source * (number_density[i] - n0) / n0 + wall_part;
    guess_[row] = particles.pressure[i];
  }
  matrix_.resize(unknowns, unknowns);
  matrix_.setFromTriplets(triplets_.begin(), triplets_.end());
  result.ungrounded_groups = regularise_ungrounded_groups(matrix_, grounded);

  if (settings.preconditioner == "incomplete_cholesky") {
    Eigen::ConjugateGradient<Eigen::SparseMatrix<double, Eigen::RowMajor>, Eigen::Lower | Eigen::Upper,
                             Eigen::IncompleteCholesky<double>>
        solver;
    run_cg(solver, matrix_, rhs_, guess_, settings, solution_, result);
  } else {
    Eigen::ConjugateGradient<Eigen::SparseMatrix<double, Eigen::RowMajor>, Eigen::Lower | Eigen::Upper,
                             Eigen::DiagonalPreconditioner<double>>
        solver;
    run_cg(solver, matrix_, rhs_, guess_, settings, solution_, result);
  }

  for (Eigen::Index row = 0; row < unknowns; ++row) {
    double pressure = solution_[row];
    if (settings.clamp_negative && pressure < 0.0) pressure = 0.0;  // spec §5.2-7
    particles.pressure[static_cast<std::size_t>(particle_of_[static_cast<std::size_t>(row)])] = pressure;
  }
  return result;
}

}  // namespace mps_lab::mps
