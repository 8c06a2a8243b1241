#include "methods/mps/mps_pressure.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/base/memory_bytes.hpp"

#include "core/linalg/pressure_system.hpp"
#include "core/search/for_each_neighbour.hpp"

namespace mps_lab::mps {

Eigen::SparseMatrix<double, Eigen::RowMajor> PressurePoissonSolver::matrix() const { return to_eigen(matrix_); }

MemoryBreakdown PressurePoissonSolver::memory_breakdown() const {
  return pressure_solve_breakdown(matrix_, assembler_.held_bytes(),
                                  held_bytes(row_of_, particle_of_, grounded_, reached_, rhs_), solver_);
}

// An upper bound of row i's entries (the assembler closes up what assemble_row leaves unused):
// the diagonal and every pressure-carrying neighbour and wall sample that is an unknown. The
// neighbour list holds the pairs within the search radius, re of the Laplacian or more, so the
// bound is the count itself unless another operator's radius is larger; no distances here.
int PressurePoissonSolver::row_count(const RowInputs& in, std::size_t i) const {
  const ParticleSet& particles = in.particles;
  int count = 1;
  for_each_neighbour(in.neighbours, i, [&](std::uint32_t j) {
    count += in.carries_pressure[j] && particles.type[j] != ParticleType::Ghost && row_of_[j] >= 0 ? 1 : 0;
  });
  for_each_neighbour(in.samples, i,
                     [&](const WallSample& wall) { count += wall.source != i && row_of_[wall.source] >= 0 ? 1 : 0; });
  return count;
}

// Row `row` of A and b (spec §2 Laplacian, §8 source): the neighbours' and the wall samples'
// terms, the diagonal first, the right-hand side, and whether the row touches a Dirichlet
// particle. Reads only: rows are assembled in parallel.
void PressurePoissonSolver::assemble_row(const RowInputs& in, int row) {
  const ParticleSet& particles = in.particles;
  const NeighbourList& neighbours = in.neighbours;
  const WallSampleList& samples = in.samples;
  const std::vector<double>& number_density = in.number_density;
  const std::vector<char>& carries_pressure = in.carries_pressure;
  const PressureSolveSettings& settings = in.settings;
  const double n0 = in.n0;
  const double source = in.source;
  const auto i = static_cast<std::size_t>(particle_of_[static_cast<std::size_t>(row)]);
  auto writer = assembler_.row(row);
  writer.add(row, 0.0);  // the diagonal, summed below
  double diagonal = 0.0;
  bool grounded = false;
  double known_part = 0.0;  // known terms of the Laplacian (Dirichlet neighbours, wall offsets), moved to b_i
  for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
    if (!carries_pressure[j] || particles.type[j] == ParticleType::Ghost) return;
    const double a = laplacian_term(in, (particles.position[j] - particles.position[i]).norm());
    if (a == 0.0) return;
    diagonal += a;
    if (row_of_[j] >= 0) {
      writer.add(row_of_[j], -a);
    } else {
      grounded = true;  // a Dirichlet neighbour: P_j known (0, or its surface value)
      known_part += a * particles.pressure[j];
    }
  });
  for_each_neighbour(samples, i, [&](const WallSample& wall) {
    const double a = wall.volume * laplacian_term(in, (wall.position - particles.position[i]).norm());
    if (a == 0.0) return;
    known_part += a * sample_pressure_offset(wall, particles.position, settings.density, settings.gravity);
    if (wall.source == i) return;  // p_i - p_i
    diagonal += a;
    if (row_of_[wall.source] >= 0) {
      writer.add(row_of_[wall.source], -a);
    } else {
      grounded = true;  // the image of a Dirichlet particle
      known_part += a * particles.pressure[wall.source];
    }
  });
  writer.value(0) = diagonal == 0.0 ? 1.0 : diagonal;
  writer.close();
  grounded_[static_cast<std::size_t>(row)] = grounded || diagonal == 0.0 ? 1 : 0;
  if (diagonal == 0.0) {
    // Isolated: no pressure-carrying neighbour at all, only walls whose samples carry its own
    // pressure (dummy layers, the distance function: a Neumann wall), so nothing fixes P_i. A
    // droplet on a wall: P_i = 0 (the row 1 * P_i = 0). Its source, (n*_i - n0)/n0 from the
    // wall's share of n*_i, once made P_i = b_i / (1 m^-2): 1e8-3e8 Pa for a lone particle in a
    // corner (docs/methods/mps.md, "Wall samples: an isolated row").
    rhs_[static_cast<std::size_t>(row)] = 0.0;
    return;
  }
  // b_i = relaxation (rho/dt^2) (n*_i - n0)/n0   [sign: A = -<lap>]
  if (settings.source_term != nullptr) {  // a scheme's source term (methods/mps/mps_schemes.hpp)
    rhs_[static_cast<std::size_t>(row)] = (*settings.source_term)[i] + known_part;
    return;
  }
  rhs_[static_cast<std::size_t>(row)] = source * (number_density[i] - n0) / n0 + known_part;
}

// Dirichlet value of a free-surface fluid particle when the water surface lies `surface_offset`
// (delta) beyond its centre (docs/methods/mps.md, "The water surface"): the hydrostatic head
// P_s = rho |g| delta where the water lies below it, i.e. where its outward normal
// n_i = -sum_j w(r_ij) r_ij / |r_ij| over the fluid neighbours (spec §2 weight) has a part
// against gravity (-g . n_i > 0); 0 where it faces sideways or down (a jet's underside). The
// full head, not |g . n_i| delta: a still surface's normals tilt by the particles' disorder, and
// the cosine's mean of about 0.85 left the shallow sensors 3-4 % low (measured 2026-11-29).
double PressurePoissonSolver::surface_pressure(const ParticleSet& particles, const NeighbourList& neighbours,
                                               const OperatorRadius& radius, const PressureSolveSettings& settings,
                                               std::size_t i) {
  Vec2 outward = Vec2::Zero();
  for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
    if (particles.type[j] != ParticleType::Fluid) return;
    const Vec2 r = particles.position[j] - particles.position[i];
    const double distance = r.norm();
    if (distance > 0.0) outward -= mps_weight(distance, radius.re, radius.r_min) * r / distance;
  });
  const bool water_below = -settings.gravity.dot(outward) > 0.0;
  return water_below ? settings.density * settings.gravity.norm() * settings.surface_offset : 0.0;  // Pa
}

// Dirichlet value of a wall particle on the free surface (the spec's walls carry pressure, §8)
// when the water surface lies `surface_offset` (delta) beyond the fluid surface particles'
// centres: the hydrostatic head below that surface, P_w = rho |g| max(0, delta - Delta), Delta
// the wall particle's height above its highest fluid neighbour within the Laplacian's radius
// (negative when the water stands higher beside it). A wall particle level with the top row
// holds the fluid surface particles' head rho |g| delta, one half a spacing or more above it 0,
// as the wall in the air above the water; one with no fluid neighbour 0. Held at 0 instead, the
// wall at the water line pulled the pool's pressure down at the contact line and the still water
// read 2-4 % low from the first steps (docs/methods/mps.md, "The water line on the wall").
double PressurePoissonSolver::wall_surface_pressure(const ParticleSet& particles, const NeighbourList& neighbours,
                                                    const OperatorRadius& radius, const PressureSolveSettings& settings,
                                                    std::size_t i) {
  const Vec2 up = -settings.gravity.normalized();
  double highest_fluid = -std::numeric_limits<double>::infinity();  // m, along `up`
  for_each_neighbour(neighbours, i, [&](std::uint32_t j) {
    if (particles.type[j] != ParticleType::Fluid) return;
    if ((particles.position[j] - particles.position[i]).norm() >= radius.re) return;
    highest_fluid = std::max(highest_fluid, particles.position[j].dot(up));
  });
  if (!std::isfinite(highest_fluid)) return 0.0;
  const double height_above_water = particles.position[i].dot(up) - highest_fluid;  // Delta, m
  return settings.density * settings.gravity.norm() * std::max(0.0, settings.surface_offset - height_above_water);
}

// The Dirichlet value of surface particle i (Pa): the spec's 0 (§3), or with a water surface
// `surface_offset` beyond the surface particles the head of a fluid or wall particle.
double PressurePoissonSolver::surface_value(const ParticleSet& particles, const NeighbourList& neighbours,
                                            const OperatorRadius& radius, const PressureSolveSettings& settings,
                                            std::size_t i) {
  if (settings.surface_offset <= 0.0) return 0.0;
  if (particles.type[i] == ParticleType::Fluid) return surface_pressure(particles, neighbours, radius, settings, i);
  if (particles.type[i] == ParticleType::Wall) return wall_surface_pressure(particles, neighbours, radius, settings, i);
  return 0.0;
}

double PressurePoissonSolver::laplacian_term(const RowInputs& in, double r) {
  if (in.settings.laplacian_scheme == PpeLaplacianScheme::Hl) {
    return higher_order_laplacian_coefficient(r, in.laplacian);  // Khayyer & Gotoh (2010)
  }
  return in.coefficient * mps_weight(r, in.laplacian.re, in.laplacian.r_min);  // spec §2
}

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
      particles.pressure[i] = surface_value(particles, neighbours, laplacian, settings, i);
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
  const double source = settings.relaxation * settings.density / (dt * dt);         // kg/(m^3 s^2)
  rhs_.resize(static_cast<std::size_t>(unknowns));
  grounded_.assign(static_cast<std::size_t>(unknowns), 0);
  const RowInputs in{particles, neighbours, samples, number_density, carries_pressure,
                     laplacian, settings,   n0,      coefficient,    source};
  // The entries of every row, counted (in parallel), then placed: the rows' storage in matrix_.
  assembler_.start(matrix_, unknowns);
#pragma omp parallel for schedule(static)
  for (int row = 0; row < unknowns; ++row) {
    assembler_.count(row, row_count(in, static_cast<std::size_t>(particle_of_[static_cast<std::size_t>(row)])));
  }
  assembler_.place(matrix_);
#pragma omp parallel for schedule(static)
  for (int row = 0; row < unknowns; ++row) assemble_row(in, row);
  assembler_.finish(matrix_, /*diagonal_first=*/true);

  // A group of unknowns with no Dirichlet row (core/linalg/pressure_system.hpp) makes A singular
  // (pressure defined up to a constant). The remedy of the public MPS-Basic code (Kondo lab)
  // is kept: double the diagonal of such a group's rows, which pins its mean pressure near zero.
  result.ungrounded_groups = pin_ungrounded_groups(matrix_, grounded_, particle_of_.size(), reached_);
  return result;
}

void PressurePoissonSolver::solve_assembled(ParticleSet& particles, const PressureSolveSettings& settings,
                                            PressureSolveResult& result) {
  ProjectionSolverSettings solver;
  solver.method = KrylovMethod::ConjugateGradient;  // A symmetric positive definite
  solver.preconditioner = settings.preconditioner;
  solver.amg_reuse_budget = settings.amg_reuse_budget;
  solver.tolerance = settings.tolerance;
  solver.max_iterations = settings.max_iterations;
  solver.warm_start = settings.warm_start;
  solver.clamp_negative = settings.clamp_negative;  // spec §5.2-7
  const ProjectionSolveStatistics solved = solver_.solve(matrix_, rhs_, particle_of_, solver, particles.pressure);
  result.iterations = solved.iterations;
  result.residual = solved.residual;
  result.converged = solved.converged;
}

}  // namespace mps_lab::mps
