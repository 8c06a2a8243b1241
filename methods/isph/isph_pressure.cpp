#include "methods/isph/isph_pressure.hpp"

#include <cmath>
#include <stdexcept>

#include <Eigen/IterativeLinearSolvers>

#include "core/pressure_system.hpp"
#include "methods/isph/isph_operators.hpp"

namespace mps_lab::isph {

namespace {

using RowMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor>;

// A group of unknowns with no Dirichlet row (core/pressure_system.hpp) has a singular block:
// fluid rows sum to zero and wall rows are weighted averages. As in the mps method (and the
// public MPS-Basic code) the diagonal of such a group's fluid rows is doubled, which pins its
// pressure level near zero. Returns the number of groups fixed.
std::size_t regularise_ungrounded_groups(RowMatrix& matrix, const std::vector<char>& grounded,
                                         const std::vector<char>& is_fluid_row) {
  const auto groups = ungrounded_groups(matrix, grounded);
  for (const auto& members : groups) {
    for (int row : members) {
      if (is_fluid_row[static_cast<std::size_t>(row)]) matrix.coeffRef(row, row) *= 2.0;
    }
  }
  return groups.size();
}

// BiCGSTAB until the *recomputed* residual ||b - A x|| / ||b|| is below the tolerance or the
// iteration budget is spent. Eigen's BiCGSTAB stops on its recurrence residual, which can
// drift from the true one; when it does, the solve is resumed from the current iterate with
// the iterations left. (Eigen resets its own counter once, on its first internal breakdown
// restart; the count reported is Eigen's.)
template <typename Solver>
void run_bicgstab(Solver& solver, const RowMatrix& matrix, const Eigen::VectorXd& rhs, const Eigen::VectorXd& guess,
                  const PressureSolveSettings& settings, Eigen::VectorXd& solution, PressureSolveResult& result) {
  solver.compute(matrix);
  if (solver.info() != Eigen::Success) throw std::runtime_error("ISPH pressure solve: preconditioner set-up failed");
  solver.setTolerance(settings.tolerance);
  const double rhs_norm = rhs.norm();
  solution = guess;
  result.iterations = 0;
  if (rhs_norm == 0.0) {
    solution.setZero();
    result.residual = 0.0;
    result.converged = true;
    return;
  }
  for (;;) {
    solver.setMaxIterations(static_cast<Eigen::Index>(settings.max_iterations - result.iterations));
    solution = solver.solveWithGuess(rhs, solution);
    result.iterations += static_cast<long long>(solver.iterations());
    result.residual = (rhs - matrix * solution).norm() / rhs_norm;
    if (!std::isfinite(result.residual)) {
      throw std::runtime_error("ISPH pressure solve: BiCGSTAB produced a non-finite pressure");
    }
    result.converged = result.residual <= settings.tolerance;
    if (result.converged || result.iterations >= settings.max_iterations || solver.iterations() == 0) return;
  }
}

}  // namespace

Preconditioner preconditioner_from_name(const std::string& name) {
  if (name == "diagonal") return Preconditioner::Diagonal;
  if (name == "incomplete_lut") return Preconditioner::IncompleteLut;
  throw std::invalid_argument("unknown preconditioner '" + name + "' (expected diagonal or incomplete_lut)");
}

void PressurePoissonSolver::assemble(const ParticleSet& particles, const NeighbourList& neighbours,
                                     const WallSampleList& samples, const SphKernel& kernel,
                                     const std::vector<double>& density, const std::vector<double>& source,
                                     const PressureSolveSettings& settings, std::vector<char>& grounded) {
  const auto unknowns = static_cast<Eigen::Index>(particle_of_.size());
  const double fluid_scale = settings.rest_density * settings.spacing * settings.spacing;  // kg/m: rows in Pa
  triplets_.clear();
  rhs_.resize(unknowns);
  guess_.resize(unknowns);
  grounded.assign(static_cast<std::size_t>(unknowns), 0);
  const bool with_samples = samples.has_samples();
  for (Eigen::Index row = 0; row < unknowns; ++row) {
    const auto i = static_cast<std::size_t>(particle_of_[static_cast<std::size_t>(row)]);
    const auto row_index = static_cast<int>(row);
    guess_[row] = settings.warm_start ? particles.pressure[i] : 0.0;
    if (particles.type[i] == ParticleType::Fluid) {
      // Cummins & Rudman (1999) / Shao & Lo (2003) Laplacian: sum_j a_ij (p_i - p_j) = -S_i
      double diagonal = 0.0;
      for (std::uint32_t k = neighbours.begin(i); k < neighbours.end(i); ++k) {
        const std::uint32_t j = neighbours.indices[k];
        if (particles.type[j] == ParticleType::Ghost) continue;
        const double factor =
            laplacian_pair_factor(kernel, particles.position[i] - particles.position[j], settings.eta2);
        const double a = fluid_scale * ppe_pair_coefficient(settings.mass, density[i], density[j], factor);
        if (a == 0.0) continue;
        diagonal += a;
        if (row_of_[j] >= 0) {
          triplets_.emplace_back(row_index, row_of_[j], -a);
        } else {
          grounded[static_cast<std::size_t>(row)] = 1;  // a surface neighbour, p = 0
        }
      }
      // Wall samples: a_iw (p_i - p_s - rho0 g . (x_w - x_s)); the hydrostatic part is known.
      double wall_head = 0.0;  // sum_w a_iw rho0 g . (x_w - x_s), Pa
      if (with_samples) {
        for (std::uint32_t k = samples.begin(i); k < samples.end(i); ++k) {
          const WallSample& wall = samples.samples[k];
          const std::uint32_t s = wall.source;
          if (particles.type[s] == ParticleType::Ghost) continue;
          const double factor = laplacian_pair_factor(kernel, particles.position[i] - wall.position, settings.eta2);
          const double a = fluid_scale * ppe_pair_coefficient(settings.mass * wall.volume, density[i],
                                                              settings.rest_density, factor);
          if (a == 0.0) continue;
          wall_head +=
              a * sample_pressure_offset(wall, particles.position, settings.rest_density, settings.gravity);
          if (s == i) continue;  // p_w - p_i = the hydrostatic part alone
          diagonal += a;
          if (row_of_[s] >= 0) {
            triplets_.emplace_back(row_index, row_of_[s], -a);
          } else {
            grounded[static_cast<std::size_t>(row)] = 1;  // the image of a surface particle, p_s = 0
          }
        }
      }
      if (diagonal == 0.0) {  // no neighbour within the support: p = 0
        diagonal = 1.0;
        grounded[static_cast<std::size_t>(row)] = 1;
        rhs_[row] = 0.0;
      } else {
        rhs_[row] = -fluid_scale * source[i];
        if (with_samples) rhs_[row] += wall_head;
      }
      triplets_.emplace_back(row_index, row_index, diagonal);
    } else {
      // Adami, Hu & Adams (2012), eq. 27 with a_w = 0:
      //   p_w = (sum_f p_f W_wf + g . sum_f rho_f (x_w - x_f) W_wf) / sum_f W_wf
      double weight_sum = 0.0;
      Vec2 head = Vec2::Zero();
      for (std::uint32_t k = neighbours.begin(i); k < neighbours.end(i); ++k) {
        const std::uint32_t f = neighbours.indices[k];
        if (particles.type[f] != ParticleType::Fluid) continue;
        weight_sum += kernel.value((particles.position[i] - particles.position[f]).norm());
      }
      for (std::uint32_t k = neighbours.begin(i); k < neighbours.end(i); ++k) {
        const std::uint32_t f = neighbours.indices[k];
        if (particles.type[f] != ParticleType::Fluid) continue;
        const Vec2 between = particles.position[i] - particles.position[f];
        const double w = kernel.value(between.norm()) / weight_sum;
        if (w == 0.0) continue;
        head += density[f] * w * between;
        if (row_of_[f] >= 0) {
          triplets_.emplace_back(row_index, row_of_[f], -w);
        } else {
          grounded[static_cast<std::size_t>(row)] = 1;  // a surface fluid neighbour, p = 0
        }
      }
      triplets_.emplace_back(row_index, row_index, 1.0);
      rhs_[row] = settings.gravity.dot(head);
    }
  }
  matrix_.resize(unknowns, unknowns);
  matrix_.setFromTriplets(triplets_.begin(), triplets_.end());
}

PressureSolveResult PressurePoissonSolver::solve(ParticleSet& particles, const NeighbourList& neighbours,
                                                 const WallSampleList& samples, const SphKernel& kernel,
                                                 const std::vector<double>& density,
                                                 const std::vector<double>& free_surface,
                                                 const std::vector<double>& source,
                                                 const PressureSolveSettings& settings) {
  PressureSolveResult result;
  const std::size_t n = particles.size();
  row_of_.assign(n, -1);
  particle_of_.clear();

  // Fluid unknowns first, then the wall particles that see fluid within the support.
  for (std::size_t i = 0; i < n; ++i) {
    if (particles.type[i] != ParticleType::Fluid) continue;
    if (free_surface[i] != 0.0) {
      ++result.surface;
      continue;
    }
    row_of_[i] = static_cast<int>(particle_of_.size());
    particle_of_.push_back(static_cast<int>(i));
  }
  result.fluid_unknowns = particle_of_.size();
  for (std::size_t i = 0; i < n; ++i) {
    if (particles.type[i] != ParticleType::Wall) continue;
    bool sees_fluid = false;
    for (std::uint32_t k = neighbours.begin(i); k < neighbours.end(i) && !sees_fluid; ++k) {
      const std::uint32_t f = neighbours.indices[k];
      sees_fluid = particles.type[f] == ParticleType::Fluid &&
                   kernel.value((particles.position[i] - particles.position[f]).norm()) > 0.0;
    }
    if (!sees_fluid) continue;
    row_of_[i] = static_cast<int>(particle_of_.size());
    particle_of_.push_back(static_cast<int>(i));
  }
  result.wall_unknowns = particle_of_.size() - result.fluid_unknowns;

  for (std::size_t i = 0; i < n; ++i) {
    if (row_of_[i] < 0) particles.pressure[i] = 0.0;
  }
  if (particle_of_.empty()) return result;

  std::vector<char> grounded;
  assemble(particles, neighbours, samples, kernel, density, source, settings, grounded);
  std::vector<char> is_fluid_row(particle_of_.size(), 0);
  for (std::size_t row = 0; row < result.fluid_unknowns; ++row) is_fluid_row[row] = 1;
  result.ungrounded_groups = regularise_ungrounded_groups(matrix_, grounded, is_fluid_row);

  if (settings.preconditioner == Preconditioner::IncompleteLut) {
    Eigen::BiCGSTAB<RowMatrix, Eigen::IncompleteLUT<double>> solver;
    run_bicgstab(solver, matrix_, rhs_, guess_, settings, solution_, result);
  } else {
    Eigen::BiCGSTAB<RowMatrix, Eigen::DiagonalPreconditioner<double>> solver;
    run_bicgstab(solver, matrix_, rhs_, guess_, settings, solution_, result);
  }

  for (std::size_t row = 0; row < particle_of_.size(); ++row) {
    particles.pressure[static_cast<std::size_t>(particle_of_[row])] = solution_[static_cast<Eigen::Index>(row)];
  }
  return result;
}

}  // namespace mps_lab::isph
