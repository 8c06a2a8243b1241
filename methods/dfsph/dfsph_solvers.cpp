#include "methods/dfsph/dfsph_solvers.hpp"

#include <algorithm>
#include <cstddef>

#include "core/search/for_each_neighbour.hpp"

namespace mps_lab::dfsph {
namespace {

// Fluid particles per block of the error sum. Fixed (not per thread), so that the partial
// sums and their ordered total are the same for every thread count.
constexpr std::size_t kErrorBlock = 64;

// Fills the workspace for one solve: the fluid list, the solver's velocities (fluid, 0 for
// every other particle: boundary particles do not move), no correction pending, s = 0 and
// zero stiffness outside the fluid; the neighbour masses m_j if the kernel cache has none.
// Returns m_j (KernelCache::neighbour_mass).
const double* prepare(const ParticleSet& particles, const SphSystem& system, std::vector<double>& stiffness,
                      SolverWorkspace& w) {
  const std::size_t n = particles.size();
  stiffness.resize(n, 0.0);
  w.velocity.resize(n);
  w.increment.resize(n);
  w.stiffness_over_density.resize(n);
  w.fluid.clear();
  w.fluid.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const bool fluid = particles.type[i] == ParticleType::Fluid;
    if (fluid) w.fluid.push_back(static_cast<std::uint32_t>(i));
    // A boundary particle at rest, or moving with its obstacle (core/walls/moving_walls.hpp).
    w.velocity[i] = fluid ? particles.velocity[i] : particles.prescribed_wall_velocity(i);
    w.increment[i] = 0.0;
    w.stiffness_over_density[i] = 0.0;
    if (!fluid) stiffness[i] = 0.0;
  }
  w.block_error.resize((w.fluid.size() + kErrorBlock - 1) / kErrorBlock);
  w.block_largest.resize(w.block_error.size());
  if (system.kernel.neighbour_mass.size() == n) return system.kernel.neighbour_mass.data();
  w.neighbour_mass.resize(n);  // as compute_kernel_cache with the masses
  for (std::size_t j = 0; j < n; ++j) {
    w.neighbour_mass[j] = neighbour_mass_of(particles, system.particle_mass, system.boundary_mass, j);
  }
  return w.neighbour_mass.data();
}

// The arrays one solve iterates over (raw pointers: the loops below are the solver's hot path).
struct IterationArrays {
  const Vec2* gradient;            // grad W_ij of the kernel cache, 1/m^3
  const double* neighbour_mass;    // m_j, kg/m
  const std::uint32_t* offsets;    // the neighbour list's rows
  const std::uint32_t* neighbour;  // and its indices
  const std::uint32_t* fluid;      // the fluid particles
  Vec2* velocity;                  // the solver's velocities, m/s
  double* s;                       // stiffness over density
  double* increment;               // pending stiffness increments, m^2/s^2
  double* block_error;             // per block of kErrorBlock fluid particles
  double* block_largest;           // the largest relative error, per block
  const WallSampleList* samples;   // null without wall samples
  const SampleCache* sample;
  const WallPressureStencil* wall_pressure;  // null: wall_pressure = mirrored
  const std::vector<double>* density;        // rho_i, kg/m^3
  double rest_density;                       // rho0, kg/m^3
  std::ptrdiff_t fluid_count;
  std::ptrdiff_t blocks;
};

IterationArrays iteration_arrays(ParticleSet& particles, const SphSystem& system, const std::vector<double>& density,
                                 std::vector<double>& stiffness, SolverWorkspace& w) {
  IterationArrays arrays{};
  arrays.neighbour_mass = prepare(particles, system, stiffness, w);
  arrays.gradient = system.kernel.gradient.data();
  arrays.offsets = system.neighbours.offsets.data();
  arrays.neighbour = system.neighbours.indices.data();
  arrays.fluid = w.fluid.data();
  arrays.velocity = w.velocity.data();
  arrays.s = w.stiffness_over_density.data();
  arrays.increment = w.increment.data();
  arrays.block_error = w.block_error.data();
  arrays.block_largest = w.block_largest.data();
  arrays.samples = system.has_samples() ? system.samples : nullptr;
  arrays.sample = system.sample_kernel;
  arrays.wall_pressure = system.wall_pressure;
  arrays.density = &density;
  arrays.rest_density = system.rest_density;
  arrays.fluid_count = static_cast<std::ptrdiff_t>(w.fluid.size());
  arrays.blocks = static_cast<std::ptrdiff_t>(w.block_error.size());
  return arrays;
}

// The fluid particles of error block `block`: [first, last).
inline std::ptrdiff_t block_first(std::ptrdiff_t block) { return block * static_cast<std::ptrdiff_t>(kErrorBlock); }
inline std::ptrdiff_t block_last(const IterationArrays& a, std::ptrdiff_t block) {
  return std::min(a.fluid_count, (block + 1) * static_cast<std::ptrdiff_t>(kErrorBlock));
}

// c_ij = m_j grad W_ij of neighbour pair k (kg/m^4): the pair's coefficient in D rho_i/Dt and
// in the pressure correction (KernelCache::neighbour_mass).
inline Vec2 coefficient(const IterationArrays& a, std::uint32_t k) {
  return a.neighbour_mass[a.neighbour[k]] * a.gradient[k];
}

// sum_k term(k) over the neighbour pairs k of particle i, in two partial sums (even and odd
// pairs), which halves the chain of dependent additions.
template <typename Term>
inline Vec2 pair_sum(const IterationArrays& a, std::uint32_t i, Term term) {
  Vec2 even = Vec2::Zero(), odd = Vec2::Zero();
  std::uint32_t k = a.offsets[i];
  const std::uint32_t end = a.offsets[i + 1];
  for (; k + 1 < end; k += 2) {
    even += term(k);
    odd += term(k + 1);
  }
  if (k < end) even += term(k);
  return even + odd;
}

// correct: kappa_i += its pending increment, and the pressure correction
//   v_i <- v_i - dt [ sum_j m (s_i + s_j) grad W_ij + sum_b Psi_b s_i grad W_ib ]   ([BK17] eqs. (7)-(8))
//        = v_i - dt sum_j (s_i + s_j) c_ij        (a boundary neighbour has s = 0: p_b = p_i, once,
//                                                  [AIA12] and the authors' code)
// Reads s of the neighbours, writes only particle i. Two partial sums (even and odd
// neighbours) halve the chain of dependent additions.
// Same partition (blocks) as predict: a thread corrects the particles it predicts, so that
// with two threads each one's share of the neighbour lists stays in its own cache.
// Called by every thread of the solver's parallel region (an orphaned omp for).
void correct(const IterationArrays& a, double dt, std::vector<double>& stiffness) {
  double* s = a.s;
  if (a.wall_pressure != nullptr) {
    // wall_pressure = extrapolated: s_b = p_b / rho0^2 of the boundary particles from the
    // fluid's pending s ([AHA12] eq. (27), the stiffness part; [BGI18]), so that the pair sum
    // below gives the symmetric wall term (s_i + s_b) c_ib. The omp for ends in a barrier.
    const WallPressureStencil& stencil = *a.wall_pressure;
    const auto rows = static_cast<std::ptrdiff_t>(stencil.boundary.size());
#pragma omp for schedule(static)
    for (std::ptrdiff_t r = 0; r < rows; ++r) {
      s[stencil.boundary[r]] =
          extrapolated_wall_stiffness(stencil, static_cast<std::size_t>(r), s, *a.density, a.rest_density);
    }
  }
#pragma omp for schedule(static)
  for (std::ptrdiff_t block = 0; block < a.blocks; ++block) {
    const std::ptrdiff_t last = block_last(a, block);
    for (std::ptrdiff_t f = block_first(block); f < last; ++f) {
      const std::uint32_t i = a.fluid[f];
      stiffness[i] += a.increment[i];
      const double s_i = s[i];
      // sum (s_i + s_j) c_ij: (1/rho) grad p, m/s^2
      Vec2 gradient =
          pair_sum(a, i, [&](std::uint32_t k) -> Vec2 { return (s_i + s[a.neighbour[k]]) * coefficient(a, k); });
      if (a.samples != nullptr) {
        // The constraint force of the samples: -s_i G_ii (for a sample at rest Psi_w s_i grad W_iw,
        // [AIA12]'s mirroring), and the reaction of every constraint k whose samples move with i
        // (images of i seen by k): -s_k G_ki = +s_k Psi M^T grad W_kw.
        const SampleCache* sample = a.sample;
        // wall_pressure = extrapolated: a sample at rest carrying i's pressure has the symmetric
        // term (s_i + s_w) Psi_w grad W_iw, s_w its own extrapolated p_w / rho0^2 ([AHA12] eq. (27),
        // [BGI18]; the hydrostatic part is explicit). 0 for a sample without a row.
        const WallPressureStencil* stencil = a.wall_pressure;
        for_each_neighbour(*a.samples, i, [&](std::uint32_t q, const WallSample&) {
          const double s_w =
              stencil != nullptr ? extrapolated_sample_stiffness(*stencil, q, s, *a.density, a.rest_density) : 0.0;
          gradient += (s_i + s_w) * sample->own[q];
        });
        for (std::uint32_t q = sample->by_source_offsets[i]; q < sample->by_source_offsets[i + 1]; ++q) {
          const std::uint32_t kw = sample->by_source[q];
          gradient -= s[sample->owner[kw]] * sample->reaction[kw];
        }
      }
      a.velocity[i] -= dt * gradient;
    }
  }
}

// predict: D rho_i/Dt = sum_j c_ij . (v_i - v_j) = sum_j m (v_i - v_j) . grad W_ij + sum_b Psi_b v_i . grad W_ib
// ([BK17] eq. (9); v_b = 0; + the wall samples), the error of i and its next increment;
// returns the mean and the largest error (block sums in block order: the same on every thread
// and for every thread count). The x and y products are summed apart, in two partial sums as
// above. Called by every thread of the solver's parallel region (an orphaned omp for).
struct IterationError {
  double mean = 0.0;
  double largest = 0.0;
};

template <class Settle>
IterationError predict(const IterationArrays& a, const std::vector<double>& density, const SolverWorkspace& w,
                       Settle& settle) {
#pragma omp for schedule(static)
  for (std::ptrdiff_t block = 0; block < a.blocks; ++block) {
    const std::ptrdiff_t last = block_last(a, block);
    double error_sum = 0.0, largest = 0.0;
    for (std::ptrdiff_t f = block_first(block); f < last; ++f) {
      const std::uint32_t i = a.fluid[f];
      const Vec2 vi = a.velocity[i];
      double rate = pair_sum(a, i, [&](std::uint32_t k) -> Vec2 {
                      return (vi - a.velocity[a.neighbour[k]]).cwiseProduct(coefficient(a, k));
                    }).sum();  // kg/(m^3 s)
      if (a.samples != nullptr) {
        const SampleCache* sample = a.sample;
        for_each_neighbour(*a.samples, i, [&](std::uint32_t q, const WallSample& wall) {
          const Vec2 uw = sample_velocity(wall, w.velocity);  // u_w = M v_s, now
          rate += sample->mass[q] * (vi - uw).dot(sample->gradient[q]);
        });
      }
      double relative = 0.0;
      const double change = settle(i, rate, relative);
      a.increment[i] = change;
      a.s[i] = change / density[i];
      error_sum += relative;
      largest = std::max(largest, relative);
    }
    a.block_error[block] = error_sum;
    a.block_largest[block] = largest;
  }
  IterationError error;
  for (std::ptrdiff_t block = 0; block < a.blocks; ++block) {
    error.mean += a.block_error[block];
    error.largest = std::max(error.largest, a.block_largest[block]);
  }
  if (a.fluid_count > 0) error.mean /= static_cast<double>(a.fluid_count);
  return error;
}

// The stopping rule: the mean error at most the tolerance ([BK17]) and, with a local
// tolerance, every particle's error at most that.
bool within_tolerance(const IterationError& error, const SolverSettings& settings) {
  return error.mean <= settings.tolerance &&
         (settings.local_tolerance <= 0.0 || error.largest <= settings.local_tolerance);
}

// Warm start ([BK17]; the fraction and the reset are the authors' code's): apply the last
// step's total stiffness, times the fraction, to the particles that are compressed now;
// the others start from zero, so that a stiffness left over from a past compression
// cannot push apart particles that are no longer compressed (increments are >= 0: a
// stiffness can only grow within a step); with keep_uncompressed (a start that is this
// step's own estimate, not a past step's) every particle keeps it. Without a warm start every stiffness restarts
// from zero. Called by every thread of the solver's parallel region (an orphaned omp for).
void start_stiffness(const IterationArrays& a, const std::vector<double>& density, const SolverSettings& settings,
                     std::vector<double>& stiffness) {
  const bool warm = settings.warm_start_fraction > 0.0;
#pragma omp for schedule(static)
  for (std::ptrdiff_t f = 0; f < a.fluid_count; ++f) {
    const std::uint32_t i = a.fluid[f];
    const bool keep = warm && (settings.keep_uncompressed || a.increment[i] > 0.0);
    stiffness[i] = keep ? settings.warm_start_fraction * stiffness[i] : 0.0;
    if (warm) {  // the warm start is this correction; the increments are predicted again after it
      a.s[i] = keep ? stiffness[i] / density[i] : 0.0;
      a.increment[i] = 0.0;
    }
  }
}

// The iteration shared by Algorithms 2 and 3 of [BK17].
//   settle(i, rate, relative): from D rho_i/Dt (kg/(m^3 s), [BK17] eq. (9)) sets the relative
//   error of i (its clamped source over rho0) and returns its stiffness increment (m^2/s^2, >= 0).
template <class Settle>
SolverOutcome iterate(ParticleSet& particles, const SphSystem& system, const std::vector<double>& density, double dt,
                      const SolverSettings& settings, std::vector<double>& stiffness, SolverWorkspace& w,
                      Settle settle) {
  const IterationArrays arrays = iteration_arrays(particles, system, density, stiffness, w);
  const bool warm = settings.warm_start_fraction > 0.0;
  SolverOutcome outcome;
#pragma omp parallel if (arrays.fluid_count >= kThreadedLoopMinimum)
  {
    IterationError error = predict(arrays, density, w, settle);
    start_stiffness(arrays, density, settings, stiffness);
    if (warm) {
      correct(arrays, dt, stiffness);
      error = predict(arrays, density, w, settle);
    }
    const double initial_error = error.mean;
    long long iterations = 0;  // every thread runs the same loop on the same error
    while (iterations < settings.max_iterations &&
           (iterations < settings.min_iterations || !within_tolerance(error, settings))) {
      correct(arrays, dt, stiffness);
      error = predict(arrays, density, w, settle);
      ++iterations;
    }
#pragma omp single
    {
      outcome.iterations = iterations;
      outcome.initial_error = initial_error;
      outcome.error = error.mean;
      outcome.largest_error = error.largest;
      outcome.converged = within_tolerance(error, settings);
      for (std::ptrdiff_t f = 0; f < arrays.fluid_count; ++f) {
        particles.velocity[arrays.fluid[f]] = arrays.velocity[arrays.fluid[f]];
      }
    }
  }
  return outcome;
}

}  // namespace

SolverOutcome correct_divergence_error(ParticleSet& particles, const SphSystem& system,
                                       const std::vector<double>& density, const std::vector<double>& alpha, double dt,
                                       const SolverSettings& settings, std::uint32_t min_neighbours,
                                       std::vector<double>& stiffness, SolverWorkspace& workspace) {
  count_active_neighbours(particles, system, workspace.neighbour_counts);
  const std::vector<double>& counts = workspace.neighbour_counts;
  const double rho0 = system.rest_density;
  const auto settle = [&](std::uint32_t i, double change_rate, double& relative) {
    // Only compression is corrected (max(D rho_i/Dt, 0), kg/(m^3 s)); a particle short of
    // neighbours is left alone.
    const double r = counts[i] < min_neighbours ? 0.0 : std::max(change_rate, 0.0);
    relative = dt * r / rho0;
    return r / dt * alpha[i];  // [BK17] eq. (11)
  };
  return iterate(particles, system, density, dt, settings, stiffness, workspace, settle);
}

SolverOutcome correct_density_error(ParticleSet& particles, const SphSystem& system, const std::vector<double>& density,
                                    const std::vector<double>& alpha, double dt, const SolverSettings& settings,
                                    std::vector<double>& stiffness, SolverWorkspace& workspace) {
  const double rho0 = system.rest_density;
  const double inverse_dt2 = 1.0 / (dt * dt);
  const auto settle = [&](std::uint32_t i, double change_rate, double& relative) {
    // rho*_i = rho_i + dt D rho_i/Dt ([BK17] §3.3), clamped: only compression is corrected.
    const double predicted = std::max(density[i] + dt * change_rate, rho0);  // kg/m^3
    relative = (predicted - rho0) / rho0;
    return (predicted - rho0) * inverse_dt2 * alpha[i];  // [BK17] eq. (12)
  };
  return iterate(particles, system, density, dt, settings, stiffness, workspace, settle);
}

}  // namespace mps_lab::dfsph
