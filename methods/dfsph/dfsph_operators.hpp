#pragma once
// The SPH operators of Divergence-Free SPH, as free functions over a ParticleSet and the
// cached neighbour list. 2-D; masses are per metre of depth (m = rho0 l0^2, kg/m), so that
// densities come out in kg/m^3 and pressures in Pa.
//
//   [BK17]  J. Bender, D. Koschier, "Divergence-Free SPH for Incompressible and Viscous
//           Fluids", IEEE TVCG 23(3), 1193-1206 (2017); SCA 2015 for the first version.
//           Equation numbers are the TVCG paper's, as the authors' SPlisHSPlasH cites them.
//   [AIA12] N. Akinci, M. Ihmsen, G. Akinci, B. Solenthaler, M. Teschner, "Versatile
//           rigid-fluid coupling for incompressible SPH", ACM TOG 31(4) 62 (SIGGRAPH 2012).
//   [AHA12] S. Adami, X. Y. Hu, N. A. Adams, "A generalized wall boundary condition for smoothed
//           particle hydrodynamics", J. Comput. Phys. 231, 7057-7075 (2012): the wall pressure
//           extrapolated from the fluid with the hydrostatic term, eq. (27).
//   [BGI18] S. Band, C. Gissler, M. Ihmsen, J. Cornelis, A. Peer, M. Teschner, "Pressure
//           boundaries for implicit incompressible SPH", ACM TOG 37(2) 14 (2018): boundary
//           samples with a pressure of their own in the symmetric pressure force.
//   [MFZ97] J. P. Morris, P. J. Fox, Y. Zhu, "Modeling low Reynolds number incompressible
//           flows using SPH", J. Comput. Phys. 136, 214-226 (1997).
//
// Roles. A particle is *fluid* (type Fluid), a *boundary* particle (type Wall with a
// boundary mass Psi_b = rho0 V_b > 0, [AIA12]) or inert (ghosts, wall layers the method does
// not use): inert particles are skipped in every sum. Boundary particles never move
// (v_b = 0), carry no unknown and take the pressure of the fluid particle they act on
// (pressure mirroring, as in the authors' implementation).
//
// Wall samples (core/walls/wall_samples.hpp: dummy_layers, mirror_particles, distance_function).
// When the boundary model puts no wall particles into the ParticleSet, every fluid particle i
// has a list of wall samples w, and every sum below has a second part over them, in which a
// sample is a boundary particle of mass Psi_w = rho0 V_w l0^2 (V_w: the sample's volume in
// l0^2) at x_w, moving with u_w = M_w v_s (v_s: the current velocity of its source s) and
// mirroring the pressure of its source: where a boundary particle's term has
// s_i = kappa_i / rho_i, a sample's has s_s (for s = i exactly [AIA12]'s mirroring).
#include <algorithm>
#include <cstddef>
#include <string>
#include <vector>

#include "core/base/particles.hpp"
#include "core/kernels/sph_kernels.hpp"
#include "core/search/neighbour_search.hpp"
#include "core/walls/wall_sample_reactions.hpp"
#include "core/walls/wall_samples.hpp"

namespace mps_lab::dfsph {

// Particle loops shorter than this run on one thread. At the spec's 444 particles a loop is
// ~20 us of work, and a solver iteration is three loops with a barrier each; when the two
// cores are shared with other jobs a barrier can wait a whole scheduler slice (measured on
// a loaded machine: the dam break took 3.2 s on 2 threads, 0.2 s on 1). Results do not
// depend on the thread count either way (no reductions across threads).
constexpr std::ptrdiff_t kThreadedLoopMinimum = 1024;

// W and grad_i W(x_i - x_j) for every entry of the neighbour list (CSR-aligned), evaluated
// once per step at the positions of the search and reused by every operator and solver
// iteration of the step.
struct KernelCache {
  std::vector<double> value;   // W_ij, 1/m^2
  std::vector<Vec2> gradient;  // grad_i W_ij, 1/m^3
  double self_value = 0.0;     // W(0), 1/m^2
  // m_j, the mass particle j has as a neighbour (kg/m, per particle): m for fluid, Psi_b for a
  // boundary particle, 0 for an inert one. The pair's coefficient in D rho_i/Dt =
  // sum_j c_ij . (v_i - v_j) ([BK17] eq. (9)) and in the pressure correction (eqs. (7)-(8)) is
  // c_ij = m_j grad W_ij (kg/m^4), formed where it is used: a per-pair copy would cost 16 B
  // per pair to write and hold (docs/performance.md, "Memory"). Empty unless the cache was
  // computed with the masses (the solvers then fill their own).
  std::vector<double> neighbour_mass;
};

// W, grad_i W(x_i - x_w), Psi_w and the constraint gradients of every wall sample (aligned
// with WallSampleList::samples; i = the particle whose sample it is), evaluated once per step
// like the KernelCache. A sample w of i with source s enters D rho_i/Dt as
// Psi_w (v_i - M_w v_s) . grad W_iw, i.e. d(D rho_i/Dt)/dv_i gets `own` and, for s != i,
// d(D rho_i/Dt)/dv_s gets -`reaction`.
struct SampleCache {
  std::vector<double> value;         // W_iw, 1/m^2
  std::vector<Vec2> gradient;        // grad_i W_iw, 1/m^3
  std::vector<double> mass;          // Psi_w = rho0 V_w l0^2, kg/m
  std::vector<Vec2> own;             // Psi_w (I - M_w)^T grad W_iw for s = i, else Psi_w grad W_iw; kg/m^4
  std::vector<Vec2> reaction;        // Psi_w M_w^T grad W_iw for s != i, else 0; kg/m^4
  std::vector<std::uint32_t> owner;  // i
  // The samples whose source is j and whose owner is not j: by_source[by_source_offsets[j] ..
  // by_source_offsets[j + 1]) (indices into the sample list, in owner order).
  std::vector<std::uint32_t> by_source_offsets;
  std::vector<std::uint32_t> by_source;
};

struct WallPressureStencil;

// Everything an operator reads besides the particles: one bundle per step.
struct SphSystem {
  const NeighbourList& neighbours;
  const KernelCache& kernel;
  const std::vector<double>& boundary_mass;  // Psi_b = rho0 V_b (kg/m) for boundary particles, else 0
  double particle_mass;                      // m = rho0 l0^2, kg/m
  double rest_density;                       // rho0, kg/m^3
  // The wall samples of this step and their kernel values; null (or a list without samples)
  // for a boundary model of wall particles: then the sample sums are skipped.
  const WallSampleList* samples = nullptr;
  const SampleCache* sample_kernel = nullptr;
  // wall_pressure = extrapolated: the boundary particles' Shepard weights of this step; null
  // for wall_pressure = mirrored.
  const WallPressureStencil* wall_pressure = nullptr;

  bool has_samples() const { return samples != nullptr && sample_kernel != nullptr && samples->has_samples(); }
};

// How the wall's pressure enters the pressure force (methods.dfsph.wall_pressure,
// docs/methods/dfsph.md "At the walls"). s = p / rho^2 = kappa / rho (m^5/(kg s^2)).
enum class WallPressure {
  // [AIA12] and the authors' code: a boundary particle b (or wall sample at rest) takes the
  // pressure of the fluid particle i it acts on, once: a_i -= Psi_b s_i grad W_ib.
  Mirrored,
  // [BGI18]: the wall has a pressure p_b of its own, extrapolated from the fluid ([AHA12] eq. (27)
  // with the wall particle's acceleration a_b), in the symmetric force a_i -= Psi_b (s_i + p_b / rho0^2) grad W_ib:
  //   boundary particle b:  p_b = sum_f [p_f + rho_f (g - a_b).(x_b - x_f)] W_bf / sum_f W_bf (fluid f near b;
  //                         a_b = particles.prescribed_wall_acceleration(b): 0 at rest, a moving obstacle's)
  //   wall sample w at rest (source i): the same sum over i and its fluid neighbours f
  //   mirror image w of a fluid particle: as Mirrored (its source's pressure already enters
  //   both ways through the constraint), plus the hydrostatic part rho0 g.(x_w - x_s).
  // The part of p_b linear in the fluid's stiffness enters every solver iteration; the
  // hydrostatic part is an explicit acceleration (add_wall_hydrostatic_acceleration).
  Extrapolated,
};
WallPressure wall_pressure_from_name(const std::string& name);  // "mirrored" | "extrapolated"

// The boundary particles' extrapolation weights of one step (WallPressure::Extrapolated):
// rows of the boundary particles that have fluid within the support, in index order.
struct WallPressureStencil {
  std::vector<std::uint32_t> boundary;  // b
  std::vector<std::uint32_t> offsets;   // the fluid of row r: [offsets[r], offsets[r + 1])
  std::vector<std::uint32_t> fluid;     // f
  std::vector<double> weight;           // W_bf / sum_f W_bf ([AHA12] eq. (27): Shepard weights)
  // Per particle (0 but for the rows' b): the hydrostatic part of s_b,
  // max(0, sum_f rho_f (g - a_b).(x_b - x_f) W_bf / sum_f W_bf) / rho0^2, m^5/(kg s^2).
  std::vector<double> hydrostatic;
  // The same for the wall samples at rest that carry their owner's pressure
  // (is_resting_own_sample), by sample index q (rows of the other samples are empty; no rows
  // without samples): the fluid f is the owner i and its fluid neighbours, W_wf = W(|x_w - x_f|).
  std::vector<std::uint32_t> sample_offsets;
  std::vector<std::uint32_t> sample_fluid;
  std::vector<double> sample_weight;
  std::vector<double> sample_hydrostatic;  // per sample, m^5/(kg s^2)
};

// The stencil of the boundary particles for this step's positions and densities (fluid rows of
// the neighbour list: the pairs are symmetric). `gravity` in m/s^2.
void compute_wall_pressure_stencil(const ParticleSet& particles, const SphSystem& system, const SphKernel& kernel,
                                   const std::vector<double>& density, const Vec2& gravity,
                                   WallPressureStencil& stencil);

// s_b = p_b / rho0^2 of row r from the fluid's s_f = kappa_f / rho_f (the part linear in the
// stiffness): sum_f weight_bf rho_f^2 s_f / rho0^2, i.e. p_b = sum_f weight_bf p_f ([AHA12] eq. (27)).
inline double extrapolated_wall_stiffness(const WallPressureStencil& stencil, std::size_t row, const double* s,
                                          const std::vector<double>& density, double rest_density) {
  double pressure = 0.0;  // sum_f weight p_f / rho_f^2 * rho_f^2 = sum_f weight_bf p_f (in s units x rho0^2)
  for (std::uint32_t k = stencil.offsets[row]; k < stencil.offsets[row + 1]; ++k) {
    const std::uint32_t f = stencil.fluid[k];
    pressure += stencil.weight[k] * density[f] * density[f] * s[f];
  }
  return pressure / (rest_density * rest_density);
}

// s_w = p_w / rho0^2 of wall sample q (its stiffness part, as extrapolated_wall_stiffness); 0
// for a sample without a row (a mirror image: it carries its source's s through the constraint).
inline double extrapolated_sample_stiffness(const WallPressureStencil& stencil, std::size_t q, const double* s,
                                            const std::vector<double>& density, double rest_density) {
  double pressure = 0.0;
  for (std::uint32_t k = stencil.sample_offsets[q]; k < stencil.sample_offsets[q + 1]; ++k) {
    const std::uint32_t f = stencil.sample_fluid[k];
    pressure += stencil.sample_weight[k] * density[f] * density[f] * s[f];
  }
  return pressure / (rest_density * rest_density);
}

// The hydrostatic part of the extrapolated wall pressure as an explicit acceleration (wall_pressure
// = extrapolated): a_i -= sum_b Psi_b s_b,hyd grad W_ib over boundary particles, and
// a_i -= sum_w Psi_w s_w,hyd grad W_iw over wall samples (the sample row's part, or for a mirror
// image max(0, rho0 g.(x_w - x_s)) / rho0^2). m/s^2.
void add_wall_hydrostatic_acceleration(const ParticleSet& particles, const SphSystem& system, const Vec2& gravity,
                                       std::vector<Vec2>& acceleration);
// Its term of wall sample q: Psi_w s_w,hyd grad W_iw, m/s^2 (subtracted from a_i); s_w,hyd the sample
// row's part (a wall point at rest, [AHA12] eq. (27)) or, for a mirror image, p_w - p_s =
// rho0 g.(x_w - x_s) over rho_w^2 = rho0^2, clamped at 0 as the boundary particles' part.
inline Vec2 wall_hydrostatic_sample_pair(const ParticleSet& particles, const SphSystem& system, const Vec2& gravity,
                                         std::uint32_t q) {
  const WallPressureStencil* stencil = system.wall_pressure;
  const double rho0 = system.rest_density;
  double s_hyd = 0.0;  // m^5/(kg s^2)
  if (stencil != nullptr && stencil->sample_offsets[q + 1] > stencil->sample_offsets[q]) {
    s_hyd = stencil->sample_hydrostatic[q];
  } else {
    s_hyd = std::max(sample_pressure_offset(system.samples->samples[q], particles.position, rho0, gravity), 0.0) /
            (rho0 * rho0);
  }
  return system.sample_kernel->mass[q] * s_hyd * system.sample_kernel->gradient[q];
}

// True if the wall sample is a wall point at rest that carries its owner's pressure (source =
// owner, velocity_map = 0): under wall_pressure = extrapolated its pressure term is symmetric,
// (s_i + p_w / rho0^2) Psi_w grad W_iw.
inline bool is_resting_own_sample(const WallSample& sample, std::uint32_t owner) {
  return sample.source == owner && sample.velocity_map.isZero(0.0);
}

inline bool is_boundary(const ParticleSet& particles, const SphSystem& system, std::size_t j) {
  return particles.type[j] == ParticleType::Wall && system.boundary_mass[j] > 0.0;
}

// m_j, the mass particle j has as a neighbour (KernelCache::neighbour_mass), kg/m: m for fluid,
// Psi_b for a wall particle (0 for an unused wall layer), 0 for any other.
inline double neighbour_mass_of(const ParticleSet& particles, double particle_mass,
                                const std::vector<double>& boundary_mass, std::size_t j) {
  const ParticleType type = particles.type[j];
  return type == ParticleType::Fluid ? particle_mass : type == ParticleType::Wall ? boundary_mass[j] : 0.0;
}

void compute_kernel_cache(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                          KernelCache& cache);
// The step's cache: the rows of fluid particles only (all that the step's operators and
// solvers read; the other rows are left as they were), with their weighted gradients c_ij
// from the fluid particle mass m (kg/m) and the boundary masses Psi_b (compute_boundary_masses).
void compute_kernel_cache(const ParticleSet& particles, const NeighbourList& neighbours, const SphKernel& kernel,
                          double particle_mass, const std::vector<double>& boundary_mass, KernelCache& cache);

// W_iw, grad_i W_iw and Psi_w = rho0 V_w `lattice_volume` for every sample of `samples`
// (`lattice_volume` = l0^2, m^2). Empty for a list without samples.
void compute_sample_cache(const ParticleSet& particles, const WallSampleList& samples, const SphKernel& kernel,
                          double rest_density, double lattice_volume, SampleCache& cache);

// How the volume V_b of a boundary particle is obtained.
enum class BoundaryVolume {
  Akinci,   // [AIA12]: V_b = 1 / sum_k W_bk over the boundary particles k (b included)
  Lattice,  // V_b = l0^2: the area a wall particle represents on the lattice, = m / rho0 of a fluid particle
};
BoundaryVolume boundary_volume_from_name(const std::string& name);  // "akinci" | "lattice"

// Psi_b = rho0 V_b ([AIA12]) for the wall particles of layers 1..`wall_layers` (layer 1
// faces the fluid), 0 for every other particle. `lattice_volume` (m^2) is V_b of the Lattice
// rule (l0^2).
void compute_boundary_masses(const ParticleSet& particles, const NeighbourList& neighbours, const KernelCache& kernel,
                             int wall_layers, double rest_density, BoundaryVolume rule, double lattice_volume,
                             std::vector<double>& boundary_mass);

// The SPH density sum with [AIA12]'s boundary term: rho_i = sum_j m W_ij (i included) + sum_b Psi_b W_ib
// (+ sum_w Psi_w W_iw over wall samples). Fluid particles only; others get 0.
void compute_densities(const ParticleSet& particles, const SphSystem& system, std::vector<double>& density);

// [BK17] eq. (11): alpha_i = rho_i / (|sum_j m grad W_ij + sum_b Psi_b grad W_ib|^2 + sum_j |m grad W_ij|^2)
// (boundary particles do not move, so they enter only the first term; so do wall samples). m^5/kg
// in 2-D; 0 for a particle without neighbours and for non-fluid particles.
void compute_dfsph_factors(const ParticleSet& particles, const SphSystem& system, const std::vector<double>& density,
                           std::vector<double>& alpha);

// [BK17] eq. (9): D rho_i / Dt = sum_j m (v_i - v_j) . grad W_ij + sum_b Psi_b (v_i - v_b) . grad W_ib,
// v_b = 0 (+ sum_w Psi_w (v_i - M_w v_s) . grad W_iw over wall samples). kg/(m^3 s); fluid
// particles only, others 0.
void compute_density_change_rate(const ParticleSet& particles, const SphSystem& system, std::vector<double>& rate);

// The pair term of [MFZ97] eq. (8) (without nu): what neighbour j (mass m_j, density rho_j, velocity
// v_j; r_ij = x_i - x_j, grad W_ij) adds to the viscous acceleration of i, 1/s per m^2/s. Shared by
// add_viscous_acceleration and the reaction on boundary particles (add_boundary_viscous_reactions).
inline Vec2 viscous_pair(double mass_j, double rho_i, double rho_j, const Vec2& r_ij, const Vec2& gradient, double eta2,
                         const Vec2& v_i, const Vec2& v_j) {
  const double weight = r_ij.dot(gradient) / (r_ij.squaredNorm() + eta2);  // 1/m^2
  return mass_j * (rho_i + rho_j) / (rho_i * rho_j) * weight * (v_i - v_j);
}

// What wall sample q of fluid particle i adds to the viscous sum of i (over nu): viscous_pair with
// mass Psi_w, density rho0 and the sample's velocity u_w = M v_s + u_wall. rho_i in kg/m^3.
inline Vec2 viscous_sample_pair(const ParticleSet& particles, const SphSystem& system, double rho_i, double eta2,
                                std::size_t i, std::uint32_t q) {
  const WallSample& sample = system.samples->samples[q];
  const Vec2 uw = sample_velocity(sample, particles.velocity);
  return viscous_pair(system.sample_kernel->mass[q], rho_i, system.rest_density,
                      particles.position[i] - sample.position, system.sample_kernel->gradient[q], eta2,
                      particles.velocity[i], uw);
}

// Laminar viscosity of [MFZ97] eq. (8) with mu = rho nu:
//   a_i += sum_j m_j nu (rho_i + rho_j) / (rho_i rho_j) (r_ij . grad W_ij) / (|r_ij|^2 + eta^2) (v_i - v_j),
// r_ij = x_i - x_j, eta = 0.1 h (h = support / 2). Boundary neighbours count with mass
// Psi_b, density rho0 and velocity 0 (no-slip walls); wall samples with mass Psi_w, density
// rho0 and velocity M_w v_s.
void add_viscous_acceleration(const ParticleSet& particles, const SphSystem& system, const std::vector<double>& density,
                              double kinematic_viscosity, double support, std::vector<Vec2>& acceleration);

// Pressure of the boundary particles, for output: the pressure force the fluid exerts on
// boundary particle b (the reaction to the boundary term of the solvers' pressure correction,
// with the fluid pressures p_f = particles.pressure of this step) divided by the wall face
// a particle carries, `face_length` = l0 (per metre of depth):
//   p_b = | sum_f m Psi_b (p_f / rho_f^2 + s_b) grad_f W_fb | / l0,
// s_b = 0 (wall_pressure = mirrored) or the wall's own extrapolated p_b / rho0^2 (extrapolated).
// On a flat wall this is the wall pressure; summed over a wall it is the force the fluid
// exerts on it (momentum balance). 0 for wall particles without fluid neighbours.
// Evaluates grad W itself (`kernel`): it reads the rows of boundary particles.
//
// boundary_pressure_force: that force on boundary particle b, N/m, with `s[f]` the stiffness over
// density of each fluid neighbour f (p_f / rho_f^2, m^5/(kg s^2)) and `wall_s` the wall's own s_b:
// sum_f m Psi_b (s_f + s_b) grad_f W_fb, [AIA12] eq. (10) with its reaction F_b = -F_f. Shared with
// add_boundary_pressure_reactions (which takes s_b of wall_pressure = extrapolated from the
// stiffness the same way, plus the hydrostatic part the step applies explicitly).
Vec2 boundary_pressure_force(const ParticleSet& particles, const SphSystem& system, const SphKernel& kernel,
                             std::size_t b, const std::vector<double>& s, double wall_s);
void compute_boundary_pressures(ParticleSet& particles, const SphSystem& system, const SphKernel& kernel,
                                const std::vector<double>& density, double face_length);

// Neighbours that take part in the sums (fluid or boundary), per fluid particle (0 for the
// others); a wall sample counts as its volume V_w (a lattice point of the wall counts 1, as a
// boundary particle).
void count_active_neighbours(const ParticleSet& particles, const SphSystem& system, std::vector<double>& counts);

// The hydrostatic part of the wall samples' pressure (core/walls/wall_samples.hpp), as an explicit
// acceleration: a_i -= sum_w Psi_w (rho0 g . (x_w - x_s)) / rho_s^2 grad W_iw. Optional
// (methods.dfsph.wall_sample_hydrostatic, docs/methods/dfsph.md). No-op without samples.
void add_sample_hydrostatic_acceleration(const ParticleSet& particles, const SphSystem& system,
                                         const std::vector<double>& density, const Vec2& gravity,
                                         std::vector<Vec2>& acceleration);
// Its term of sample q: Psi_w (rho0 g . (x_w - x_s)) / rho_s^2 grad W_iw, m/s^2 (subtracted from a_i).
inline Vec2 sample_hydrostatic_pair(const ParticleSet& particles, const SphSystem& system,
                                    const std::vector<double>& density, const Vec2& gravity, std::uint32_t q) {
  const WallSample& sample = system.samples->samples[q];
  const double offset = sample_pressure_offset(sample, particles.position, system.rest_density, gravity);  // Pa
  const double rho_s = density[sample.source];
  return system.sample_kernel->mass[q] * offset / (rho_s * rho_s) * system.sample_kernel->gradient[q];
}

// The pressure (Pa) of fluid particle i from the stiffnesses its two solvers applied in one
// step: p_i = (kappa_i + kappa^v_i) rho_i. [BK17] eqs. (7)-(8) move i by
// -dt sum_j m (kappa_i/rho_i + kappa_j/rho_j) grad W_ij, the symmetric SPH pressure force
// -dt sum_j m (p_i/rho_i^2 + p_j/rho_j^2) grad W_ij for p = kappa rho (docs/methods/dfsph.md,
// "Pressure in Pa"). kappa in m^2/s^2, rho in kg/m^3.
inline double stiffness_pressure(double density_stiffness, double divergence_stiffness, double density) {
  return (density_stiffness + divergence_stiffness) * density;
}

// The hydrostatic stiffness kappa_i = |g| d_i (m^2/s^2; p = kappa rho ~ rho0 |g| d_i) of fluid
// at rest, d_i the depth of i below the nearest free surface: the free surface is half a
// spacing beyond the fluid particles short of neighbours (`neighbour_counts` below
// `full_count`: count_active_neighbours against the lattice count), and d_i the shortest path
// to one of them through the fluid pairs of the neighbour list (on the lattice at most 8 %
// longer than the straight line, exact along a lattice line). Fluid without a free surface
// (a tank filled to its lid) and every other particle get 0. The density solver's first warm
// start (methods.dfsph.initial_stiffness).
void hydrostatic_stiffness(const ParticleSet& particles, const NeighbourList& neighbours,
                           const std::vector<double>& neighbour_counts, double full_count, double gravity,
                           double spacing, std::vector<double>& stiffness);

// (The lattice density of a fluid particle with full support is m lattice_kernel_sum, in
// core/kernels/sph_kernels.hpp.)
// Points (i, j) != 0 of that lattice within the support: the full neighbour count.
std::uint32_t lattice_neighbour_count(double support, double spacing);

// The fluid's reaction on boundary particles in this step (docs/walls.md, "Loads on obstacles"),
// N/m, added to `reaction`; 0 on other particles. Pressure: both solvers move fluid particle f by
// -dt s_f Psi_b grad_f W_fb per correction (dfsph_solvers.cpp, correct), and the corrections' s_f
// add up to (kappa_f + kappa^v_f) / rho_f, the solvers' total stiffnesses: the force on f is
// -m Psi_b (kappa_f + kappa^v_f) / rho_f grad_f W_fb ([AIA12] eq. (10)), its reaction is
// boundary_pressure_force with those s_f. Call it at the positions of the solves (before advection).
void add_boundary_pressure_reactions(const ParticleSet& particles, const SphSystem& system, const SphKernel& kernel,
                                     const std::vector<double>& density, const std::vector<double>& density_stiffness,
                                     const std::vector<double>& divergence_stiffness, std::vector<Vec2>& reaction);
// The same on wall samples (core/walls/wall_sample_reactions.hpp), added to `loads` per obstacle
// (`scratch` is reused storage). Pressure: the corrections of both solvers moved the owner i of
// sample q by -dt (s_i + s_w) own[q] and its source s, if another particle (a mirror image), by
// +dt s_i reaction[q] (dfsph_solvers.cpp, correct); with the total s_f = (kappa_f + kappa^v_f) /
// rho_f the force on the fluid is m [s_i reaction[q] - (s_i + s_w) own[q]], s_w the sample's own
// extrapolated part (wall_pressure = extrapolated) or 0. At the positions of the solves.
void add_sample_pressure_reactions(const ParticleSet& particles, const SphSystem& system,
                                   const std::vector<double>& density, const std::vector<double>& density_stiffness,
                                   const std::vector<double>& divergence_stiffness, std::vector<Vec2>& scratch,
                                   WallSampleLoads& loads);
// Viscosity: m nu viscous_sample_pair, as add_viscous_acceleration gives i (support in m).
void add_sample_viscous_reactions(const ParticleSet& particles, const SphSystem& system,
                                  const std::vector<double>& density, double kinematic_viscosity, double support,
                                  std::vector<Vec2>& scratch, WallSampleLoads& loads);
// The explicit hydrostatic parts: add_sample_hydrostatic_acceleration (`sample_offset`) and the
// samples' part of add_wall_hydrostatic_acceleration (`wall_pressure`, = extrapolated).
void add_sample_hydrostatic_reactions(const ParticleSet& particles, const SphSystem& system,
                                      const std::vector<double>& density, const Vec2& gravity, bool sample_offset,
                                      bool wall_pressure, std::vector<Vec2>& scratch, WallSampleLoads& loads);

// Viscosity: minus m nu viscous_pair over the fluid neighbours f of each boundary particle b (mass
// Psi_b, density rho0, its prescribed velocity), as add_viscous_acceleration gives f.
void add_boundary_viscous_reactions(const ParticleSet& particles, const SphSystem& system, const SphKernel& kernel,
                                    const std::vector<double>& density, double kinematic_viscosity,
                                    std::vector<Vec2>& reaction);

}  // namespace mps_lab::dfsph
