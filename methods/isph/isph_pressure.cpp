#include "methods/isph/isph_pressure.hpp"

#include <cmath>

#include "core/linalg/pressure_system.hpp"
#include "core/search/for_each_neighbour.hpp"
#include "methods/isph/isph_operators.hpp"
#include "methods/isph/isph_surface.hpp"

namespace mps_lab::isph {

Eigen::SparseMatrix<double, Eigen::RowMajor> PressurePoissonSolver::matrix() const { return to_eigen(matrix_); }

MemoryBreakdown PressurePoissonSolver::memory_breakdown() const {
  return pressure_solve_breakdown(matrix_, assembler_.held_bytes(),
                                  held_bytes(row_of_, particle_of_, grounded_, reached_, rhs_, surface_factor_),
                                  solver_);
}

// The entries row_of_[i]'s row can have: the diagonal and one per neighbour (a wall row: per
// fluid neighbour) or wall sample that is an unknown, as fluid_row and wall_row visit them (they
// drop a pair whose coefficient is exactly 0: coincident particles; the assembler closes the gap).
int PressurePoissonSolver::row_count(const RowInputs& in, std::size_t i) const {
  const ParticleSet& particles = in.particles;
  int count = 1;
  if (particles.type[i] != ParticleType::Fluid || surface_factor_[i] > 0.0) {  // a wall or (SURF) row
    for_each_neighbour(in.neighbours, i, [&](std::uint32_t f) {
      count += particles.type[f] == ParticleType::Fluid && row_of_[f] >= 0 ? 1 : 0;
    });
    return count;
  }
  for_each_neighbour(in.neighbours, i, [&](std::uint32_t j) {
    count += particles.type[j] != ParticleType::Ghost && row_of_[j] >= 0 ? 1 : 0;
  });
  for_each_neighbour(in.samples, i, [&](const WallSample& wall) {
    const std::uint32_t s = wall.source;
    count += particles.type[s] != ParticleType::Ghost && s != i && row_of_[s] >= 0 ? 1 : 0;
  });
  return count;
}

// Fluid row `row` (particle i): Cummins & Rudman (1999) / Shao & Lo (2003), with the wall
// samples' terms; sets the diagonal and b_i. Returns whether it touches a Dirichlet particle.
bool PressurePoissonSolver::fluid_row(const RowInputs& in, int row, std::size_t i,
                                      CsrInPlaceAssembler::RowWriter& writer) {
  const ParticleSet& particles = in.particles;
  const SphKernel& kernel = in.kernel;
  const std::vector<double>& density = in.density;
  const PressureSolveSettings& settings = in.settings;
  const NeighbourList& neighbours = in.neighbours;
  const WallSampleList& samples = in.samples;
  const std::vector<double>& source = in.source;
  const double fluid_scale = in.fluid_scale;
  const bool with_samples = samples.has_samples();
  bool grounded = false;
  // Cummins & Rudman (1999) / Shao & Lo (2003) Laplacian: sum_j a_ij (p_i - p_j) = -S_i
  double diagonal = 0.0;
  for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
    if (particles.type[j] == ParticleType::Ghost) return;
    const double factor = laplacian_pair_factor(kernel, particles.position[i] - particles.position[j], settings.eta2);
    const double a = fluid_scale * ppe_pair_coefficient(settings.mass, density[i], density[j], factor);
    if (a == 0.0) return;
    diagonal += a;
    if (row_of_[j] >= 0) {
      writer.add(row_of_[j], -a);
    } else {
      grounded = true;  // a surface neighbour, p = 0
    }
  });
  // Wall samples: a_iw (p_i - p_s - rho0 g . (x_w - x_s)); the hydrostatic part is known.
  double wall_head = 0.0;  // sum_w a_iw rho0 g . (x_w - x_s), Pa
  for_each_neighbour(samples, i, [&](const WallSample& wall) {
    const std::uint32_t s = wall.source;
    if (particles.type[s] == ParticleType::Ghost) return;
    const double factor = laplacian_pair_factor(kernel, particles.position[i] - wall.position, settings.eta2);
    const double a =
        fluid_scale * ppe_pair_coefficient(settings.mass * wall.volume, density[i], settings.rest_density, factor);
    if (a == 0.0) return;
    wall_head += a * sample_pressure_offset(wall, particles.position, settings.rest_density, settings.gravity);
    if (s == i) return;  // p_w - p_i = the hydrostatic part alone
    diagonal += a;
    if (row_of_[s] >= 0) {
      writer.add(row_of_[s], -a);
    } else {
      grounded = true;  // the image of a surface particle, p_s = 0
    }
  });
  if (diagonal == 0.0) {  // no neighbour within the support: p = 0
    diagonal = 1.0;
    grounded = true;
    rhs_[static_cast<std::size_t>(row)] = 0.0;
  } else {
    rhs_[static_cast<std::size_t>(row)] = -fluid_scale * source[i] + (with_samples ? wall_head : 0.0);
  }
  writer.value(0) = diagonal;
  return grounded;
}

// Wall row `row` (wall particle i): the kernel-weighted average of the fluid pressure around
// it plus the hydrostatic head; sets the diagonal and b_w. Returns whether it touches a
// Dirichlet particle.
bool PressurePoissonSolver::wall_row(const RowInputs& in, int row, std::size_t i,
                                     CsrInPlaceAssembler::RowWriter& writer) {
  const ParticleSet& particles = in.particles;
  const SphKernel& kernel = in.kernel;
  const std::vector<double>& density = in.density;
  bool grounded = false;
  // Adami, Hu & Adams (2012), eq. 27, a_w the wall's acceleration (0 unless its obstacle moves):
  //   p_w = (sum_f p_f W_wf + (g - a_w) . sum_f rho_f (x_w - x_f) W_wf) / sum_f W_wf
  double weight_sum = 0.0;
  Vec2 head = Vec2::Zero();
  for_each_neighbour(in.neighbours, i, [&](std::uint32_t f) {
    if (particles.type[f] != ParticleType::Fluid) return;
    weight_sum += kernel.value((particles.position[i] - particles.position[f]).norm());
  });
  for_each_neighbour(in.neighbours, i, [&](std::uint32_t f) {
    if (particles.type[f] != ParticleType::Fluid) return;
    const Vec2 between = particles.position[i] - particles.position[f];
    const double w = kernel.value(between.norm()) / weight_sum;
    if (w == 0.0) return;
    head += density[f] * w * between;
    if (row_of_[f] >= 0) {
      writer.add(row_of_[f], -w);
      // a row (SURF), grounded itself, which does not reach back to the walls
      grounded = grounded || surface_factor_[f] > 0.0;
    } else {
      grounded = true;  // a surface fluid neighbour, p = 0
    }
  });
  writer.value(0) = 1.0;
  rhs_[static_cast<std::size_t>(row)] = (in.settings.gravity - particles.prescribed_wall_acceleration(i)).dot(head);
  return grounded;
}

// Surface row `row` (free-surface particle i with a surface offset): (SURF) of isph_surface.hpp,
//   p_i - factor_i sum_j W_ij p_j = 0 over the non-ghost fluid neighbours, in Pa. Always grounded:
// the zero pressure at the water surface is its Dirichlet condition.
void PressurePoissonSolver::surface_row(const RowInputs& in, int row, std::size_t i,
                                        CsrInPlaceAssembler::RowWriter& writer) {
  const ParticleSet& particles = in.particles;
  const double factor = surface_factor_[i];
  for_each_neighbour(in.neighbours, i, [&](std::uint32_t j) {
    if (particles.type[j] != ParticleType::Fluid || row_of_[j] < 0) return;  // p_j = 0 at a held particle
    const double w = factor * in.kernel.value((particles.position[i] - particles.position[j]).norm());
    if (w != 0.0) writer.add(row_of_[j], -w);
  });
  writer.value(0) = 1.0;
  rhs_[static_cast<std::size_t>(row)] = 0.0;
}

void PressurePoissonSolver::assemble_rows(const ParticleSet& particles, const NeighbourList& neighbours,
                                          const WallSampleList& samples, const SphKernel& kernel,
                                          const std::vector<double>& density, const std::vector<double>& source,
                                          const PressureSolveSettings& settings) {
  const auto unknowns = static_cast<int>(particle_of_.size());
  const double fluid_scale = settings.rest_density * settings.spacing * settings.spacing;  // kg/m: rows in Pa
  rhs_.resize(static_cast<std::size_t>(unknowns));
  grounded_.assign(static_cast<std::size_t>(unknowns), 0);
  const RowInputs in{particles, neighbours, samples, kernel, density, source, settings, fluid_scale};
  // The entries of every row, counted (in parallel), then placed: the rows' storage in matrix_.
  assembler_.start(matrix_, unknowns);
#pragma omp parallel for schedule(static)
  for (int row = 0; row < unknowns; ++row) {
    assembler_.count(row, row_count(in, static_cast<std::size_t>(particle_of_[static_cast<std::size_t>(row)])));
  }
  assembler_.place(matrix_);
  // Rows in parallel; every row stores its diagonal first.
#pragma omp parallel for schedule(static)
  for (int row = 0; row < unknowns; ++row) {
    const auto i = static_cast<std::size_t>(particle_of_[static_cast<std::size_t>(row)]);
    auto writer = assembler_.row(row);
    writer.add(row, 0.0);  // the diagonal, set below
    bool grounded = true;
    if (surface_factor_[i] > 0.0) {
      surface_row(in, row, i, writer);
    } else {
      grounded =
          particles.type[i] == ParticleType::Fluid ? fluid_row(in, row, i, writer) : wall_row(in, row, i, writer);
    }
    writer.close();
    grounded_[static_cast<std::size_t>(row)] = grounded ? 1 : 0;
  }
  assembler_.finish(matrix_, /*diagonal_first=*/true);
}

PressureSolveResult PressurePoissonSolver::assemble(ParticleSet& particles, const NeighbourList& neighbours,
                                                    const WallSampleList& samples, const SphKernel& kernel,
                                                    const std::vector<double>& density,
                                                    const std::vector<double>& free_surface,
                                                    const std::vector<double>& source,
                                                    const PressureSolveSettings& settings) {
  PressureSolveResult result;
  const std::size_t n = particles.size();
  row_of_.assign(n, -1);
  particle_of_.clear();

  // Fluid unknowns first (with the surface rows (SURF) when there is an offset), then the wall
  // particles that see fluid within the support.
  water_surface_factors(particles, neighbours, samples, kernel, settings.gravity, free_surface, settings.surface_offset,
                        settings.spacing, surface_factor_);
  for (std::size_t i = 0; i < n; ++i) {
    if (particles.type[i] != ParticleType::Fluid) continue;
    if (free_surface[i] != 0.0) {
      ++result.surface;
      if (surface_factor_[i] <= 0.0) continue;
      ++result.surface_unknowns;
    }
    row_of_[i] = static_cast<int>(particle_of_.size());
    particle_of_.push_back(static_cast<int>(i));
  }
  result.fluid_unknowns = particle_of_.size();
  fluid_rows_ = result.fluid_unknowns;
  for (std::size_t i = 0; i < n; ++i) {
    if (particles.type[i] != ParticleType::Wall) continue;
    const bool sees_fluid =
        any_neighbour(neighbours, i, [&](std::uint32_t f) { return particles.type[f] == ParticleType::Fluid; });
    if (!sees_fluid) continue;
    row_of_[i] = static_cast<int>(particle_of_.size());
    particle_of_.push_back(static_cast<int>(i));
  }
  result.wall_unknowns = particle_of_.size() - result.fluid_unknowns;

  for (std::size_t i = 0; i < n; ++i) {
    if (row_of_[i] < 0) particles.pressure[i] = 0.0;
  }
  matrix_.rows = 0;
  if (particle_of_.empty()) return result;

  assemble_rows(particles, neighbours, samples, kernel, density, source, settings);
  // A group of unknowns with no Dirichlet row (core/linalg/pressure_system.hpp) has a singular block:
  // fluid rows sum to zero and wall rows are weighted averages. As in the mps method (and the
  // public MPS-Basic code) the diagonal of such a group's fluid rows is doubled, which pins its
  // pressure level near zero.
  result.ungrounded_groups = pin_ungrounded_groups(matrix_, grounded_, fluid_rows_, reached_);
  return result;
}

void PressurePoissonSolver::solve_assembled(ParticleSet& particles, const PressureSolveSettings& settings,
                                            PressureSolveResult& result) {
  // BiCGSTAB until the recomputed residual ||b - A x|| / ||b|| is below the tolerance or the
  // iteration budget is spent (core/linalg/krylov.hpp restarts when the recurrence residual drifts).
  ProjectionSolverSettings solver;
  solver.method = KrylovMethod::Bicgstab;  // the wall rows make A non-symmetric
  solver.preconditioner = settings.preconditioner;
  solver.amg_reuse_budget = settings.amg_reuse_budget;
  solver.tolerance = settings.tolerance;
  solver.max_iterations = settings.max_iterations;
  solver.warm_start = settings.warm_start;
  solver.clamp_negative = false;  // clamped by the method
  solver.non_finite_error = "ISPH pressure solve: BiCGSTAB produced a non-finite pressure";
  const ProjectionSolveStatistics solved = solver_.solve(matrix_, rhs_, particle_of_, solver, particles.pressure);
  result.iterations = solved.iterations;
  result.residual = solved.residual;
  result.converged = solved.converged;
}

PressureSolveResult PressurePoissonSolver::solve(ParticleSet& particles, const NeighbourList& neighbours,
                                                 const WallSampleList& samples, const SphKernel& kernel,
                                                 const std::vector<double>& density,
                                                 const std::vector<double>& free_surface,
                                                 const std::vector<double>& source,
                                                 const PressureSolveSettings& settings) {
  PressureSolveResult result =
      assemble(particles, neighbours, samples, kernel, density, free_surface, source, settings);
  solve_assembled(particles, settings, result);
  return result;
}

}  // namespace mps_lab::isph
