// Divergence-Free SPH (Bender & Koschier 2015, 2017: [BK17]) with the boundary particles of
// Akinci et al. 2012, on the shared core. One step, in the order of the authors' loop
// (Algorithm 1 of [BK17], started at the neighbour search):
//   1. neighbourhoods at x^n (cell list, radius = kernel support);  [after_neighbour_search]
//   2. densities rho_i and factors alpha_i;
//   3. divergence-free solver (Algorithm 2, warm-started): D rho/Dt -> 0 on v^n;
//   4. non-pressure forces: gravity, viscosity (Morris et al. 1997; skipped when nu = 0);
//   5. time step (CFL, chosen by time_step() before the step: the driver's interface);
//   6. predicted velocities v* = v^n + dt a_np;                      [after_explicit_velocity]
//   7. constant-density solver (Algorithm 3, warm-started): rho* -> rho0;
//      pressure p = (kappa + kappa^v) rho, Pa;
//   8. advection x^{n+1} = x^n + dt v^{n+1};                          [after_correction]
//      escaped fluid particles become ghosts.
// Bracketed: the wall-treatment hooks (no measure is on by default for dfsph). The wall is the
// run's boundary model: Akinci boundary particles (akinci_boundary, the default: the
// wall-particle model AkinciMirrored, whose layers and volume rule this method reads from its
// WallParticleModel), or wall samples (dummy_layers, mirror_particles,
// distance_function) rebuilt right after every neighbour search and summed in every operator
// like boundary particles (methods/dfsph/dfsph_operators.hpp). The wall's pressure in the
// pressure force (methods.dfsph.wall_pressure): mirrored from the fluid particle ([AIA12], the
// default) or extrapolated from the fluid (Adami et al. 2012 eq. (27), after step 2; its
// hydrostatic part with the non-pressure forces, step 4). Decisions where the papers
// leave a choice are listed in docs/methods/dfsph.md.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "core/base/error.hpp"
#include "core/base/memory_bytes.hpp"
#include "core/io/checkpoint.hpp"
#include "core/io/geometry.hpp"
#include "core/io/output.hpp"
#include "core/io/scene.hpp"
#include "core/run/method.hpp"
#include "core/run/profile.hpp"
#include "core/run/time_step.hpp"
#include "core/search/cell_order.hpp"
#include "methods/dfsph/dfsph_global_density.hpp"
#include "methods/dfsph/dfsph_operators.hpp"
#include "methods/dfsph/dfsph_solvers.hpp"

namespace mps_lab::dfsph {
namespace {

SolverSettings solver_settings(const ParameterValues& p, const std::string& prefix, double warm_start_fraction) {
  SolverSettings settings;
  settings.tolerance = p.number(prefix + "_tolerance");
  settings.min_iterations = p.integer(prefix + "_min_iterations");
  settings.max_iterations = p.integer(prefix + "_max_iterations");
  settings.warm_start_fraction = warm_start_fraction;
  return settings;
}

// Running statistics of one solver over the run, for run.json.
struct SolverTotals {
  long long solves = 0;
  long long iterations = 0;
  long long max_iterations = 0;
  long long not_converged = 0;
  double error_sum = 0.0;

  void add(const SolverOutcome& outcome) {
    ++solves;
    iterations += outcome.iterations;
    max_iterations = std::max(max_iterations, outcome.iterations);
    not_converged += outcome.converged ? 0 : 1;
    error_sum += outcome.error;
  }
  void save(CheckpointWriter& out) const {
    out.write_int(solves);
    out.write_int(iterations);
    out.write_int(max_iterations);
    out.write_int(not_converged);
    out.write_double(error_sum);
  }
  void restore(CheckpointReader& in) {
    solves = in.read_int();
    iterations = in.read_int();
    max_iterations = in.read_int();
    not_converged = in.read_int();
    error_sum = in.read_double();
  }
  nlohmann::json to_json() const {
    const double count = std::max(1.0, static_cast<double>(solves));
    return {{"solves", solves},
            {"mean_iterations", static_cast<double>(iterations) / count},
            {"max_iterations", max_iterations},
            {"not_converged", not_converged},
            {"mean_error", error_sum / count}};
  }
};

// Running statistics of the global density solve (density_solver = amg_cg), for run.json.
struct GlobalSolveTotals {
  long long solves = 0;  // steps with compression (a CG solve)
  long long iterations = 0;
  long long max_iterations = 0;
  long long not_converged = 0;

  void add(const GlobalDensityOutcome& outcome) {
    if (!outcome.solved) return;  // nothing compressed
    ++solves;
    iterations += outcome.iterations;
    max_iterations = std::max(max_iterations, outcome.iterations);
    not_converged += outcome.converged ? 0 : 1;
  }
  void save(CheckpointWriter& out) const {
    for (long long v : {solves, iterations, max_iterations, not_converged}) out.write_int(v);
  }
  void restore(CheckpointReader& in) {
    solves = in.read_int();
    iterations = in.read_int();
    max_iterations = in.read_int();
    not_converged = in.read_int();
  }
  nlohmann::json to_json() const {
    const double count = std::max(1.0, static_cast<double>(solves));
    return {{"solves", solves},
            {"mean_iterations", static_cast<double>(iterations) / count},
            {"max_iterations", max_iterations},
            {"not_converged", not_converged}};
  }
};

// The wall hooks the step calls (MethodInfo::wall_hooks): no explicit position update, so no
// after_explicit_position; the advection ends the step with after_correction.
constexpr WallHooks kWallHooks = {WallHook::AfterNeighbourSearch, WallHook::AfterExplicitVelocity,
                                  WallHook::AfterCorrection};

class DfsphMethod final : public Method {
 public:
  explicit DfsphMethod(const MethodSetup& setup)
      : scene_(setup.scene),
        walls_(setup.wall_treatments, setup.scene, setup.timers, kWallHooks),
        timers_(setup.timers),
        search_phase_(phase_id(timers_, "neighbour_search")),
        operators_phase_(phase_id(timers_, "operators")),
        divergence_phase_(phase_id(timers_, "divergence_solve")),
        density_phase_(phase_id(timers_, "density_solve")),
        integration_phase_(phase_id(timers_, "integration")),
        kernel_(sph_kernel_from_name(setup.parameters.string("kernel")),
                setup.parameters.number("kernel_support") * setup.scene.particle_spacing) {
    const auto& p = setup.parameters;
    const double l0 = scene_.particle_spacing;
    rest_density_ = scene_.physics.density;
    // 2-D: kg per metre of depth. "spacing": m = rho0 l0^2, whose lattice density is
    // m sum_lattice W = 1.0009 rho0 with the cubic spline at 2 l0 (run.json:
    // lattice_density_over_rho0); "lattice": m = rho0 / sum_lattice W, so that the initial
    // lattice is at rest density (SPlisHSPlasH scales its particle volume for the same reason).
    const bool lattice_mass = p.string("particle_mass") == "lattice";
    particle_mass_ = lattice_mass ? rest_density_ / lattice_kernel_sum(kernel_, l0) : rest_density_ * l0 * l0;
    particle_volume_ = lattice_mass ? 1.0 / lattice_kernel_sum(kernel_, l0) : l0 * l0;
    // Loads on obstacles (MethodInfo::obstacle_loads): the reaction on wall particles, when there are both.
    computes_reactions_ = !scene_.walls.obstacles.empty() && walls_.wall_particles();
    // ... and on each obstacle's wall samples (MethodInfo::sample_obstacle_loads).
    computes_sample_loads_ = !scene_.walls.obstacles.empty() && !walls_.wall_particles();
    time_step_settings_ = time_step_settings(p, scene_.time.time_step, scene_.source);
    const double warm_start_fraction = p.number("warm_start_fraction");
    density_settings_ = solver_settings(p, "density", warm_start_fraction);
    density_settings_.local_tolerance = p.number("density_local_tolerance");
    divergence_settings_ = solver_settings(p, "divergence", warm_start_fraction);
    divergence_enabled_ = p.boolean("divergence_solver");
    full_neighbour_count_ = lattice_neighbour_count(kernel_.support(), l0);
    divergence_min_neighbours_ = static_cast<std::uint32_t>(
        std::ceil(p.number("divergence_neighbour_fraction") * static_cast<double>(full_neighbour_count_) - 1e-9));
    sample_hydrostatic_ = p.boolean("wall_sample_hydrostatic");
    wall_pressure_ = wall_pressure_from_name(p.string("wall_pressure"));
    hydrostatic_start_ = p.string("initial_stiffness") == "hydrostatic";
    global_density_ = p.string("density_solver") == "amg_cg";
    global_settings_.tolerance = p.number("density_cg_tolerance");
    global_settings_.max_iterations = p.integer("density_cg_max_iterations");
    global_settings_.min_neighbours = divergence_min_neighbours_;
    global_cycles_ = p.integer("density_cg_cycles");
    global_smoothing_ = p.integer("density_cg_smoothing");
    if (const WallParticleModel* model = walls_.wall_particle_model()) {  // akinci_boundary
      if (model->pressure() != WallParticlePressure::AkinciMirrored) {
        throw std::logic_error(std::string("dfsph: wall-particle model ") +
                               wall_particle_pressure_name(model->pressure()) + " is not implemented by this method");
      }
      boundary_wall_layers_ = model->pressure_layers();
      boundary_volume_ =
          model->volume() == WallParticleVolume::KernelSum ? BoundaryVolume::Akinci : BoundaryVolume::Lattice;
    } else if (walls_.wall_particles()) {
      throw std::logic_error("dfsph: a boundary model of wall particles without a wall-particle model");
    } else {
      boundary_wall_layers_ = 0;  // no wall particles in the ParticleSet: the wall is samples
    }

    const std::string block = "methods.dfsph.";
    if (sample_hydrostatic_ && wall_pressure_ == WallPressure::Extrapolated) {
      throw_input_error(scene_.source, block + "wall_sample_hydrostatic",
                        "got true, expected false with wall_pressure \"extrapolated\" (which includes the "
                        "hydrostatic part of the wall pressure)");
    }
    check_global_density(p, block);
    for (const auto* prefix : {"density", "divergence"}) {
      const SolverSettings& s = std::string(prefix) == "density" ? density_settings_ : divergence_settings_;
      if (s.min_iterations > s.max_iterations) {
        throw_input_error(scene_.source, block + prefix + "_min_iterations",
                          "got " + std::to_string(s.min_iterations) + ", expected at most " + prefix +
                              "_max_iterations (" + std::to_string(s.max_iterations) + ")");
      }
    }
  }

  // density_solver = amg_cg needs boundary particles and the extrapolated wall pressure (its
  // surrogate's Neumann wall is the symmetric wall term; with the mirrored one the still tank
  // diverged in 2 steps: dfsph_global_density.hpp); its own parameters apply to it alone.
  void check_global_density(const ParameterValues& p, const std::string& block) const {
    if (!global_density_) {
      std::string changed;
      if (p.number("density_cg_tolerance") != kDefaultCgTolerance) changed = "density_cg_tolerance";
      if (p.integer("density_cg_max_iterations") != kDefaultCgIterations) changed = "density_cg_max_iterations";
      if (p.integer("density_cg_cycles") != kDefaultCgCycles) changed = "density_cg_cycles";
      if (p.integer("density_cg_smoothing") != kDefaultCgSmoothing) changed = "density_cg_smoothing";
      if (!changed.empty()) {
        throw_input_error(scene_.source, block + changed,
                          "applies to density_solver amg_cg only, got density_solver " + p.string("density_solver"));
      }
      return;
    }
    if (!walls_.wall_particles()) {
      throw_input_error(scene_.source, block + "density_solver",
                        "got amg_cg with the wall samples of " + walls_.boundary_name() +
                            ", expected a boundary model of wall particles (akinci_boundary, dummy_layers)");
    }
    if (wall_pressure_ != WallPressure::Extrapolated) {
      throw_input_error(scene_.source, block + "density_solver",
                        "got amg_cg with wall_pressure mirrored, expected wall_pressure extrapolated (the symmetric "
                        "wall of the solve's Neumann surrogate; docs/methods/dfsph.md)");
    }
  }

  void initialise(ParticleSet& particles) override {
    const std::size_t n = particles.size();
    search(particles);
    WallContext context{particles, &neighbours_, scene_.time.time_step, scene_};
    build_samples(context);
    compute_kernel_cache(particles, neighbours_, kernel_, cache_);  // the boundary masses need W_bk
    compute_boundary_masses(particles, neighbours_, cache_, boundary_wall_layers_, rest_density_, boundary_volume_,
                            lattice_wall_volume(), boundary_mass_);
    cache_kernels(particles);
    auto& volume = particles.field("boundary_volume");
    for (std::size_t i = 0; i < n; ++i) volume[i] = boundary_mass_[i] / rest_density_;
    start_stiffnesses(particles);
    acceleration_.assign(n, Vec2::Zero());
    for (std::size_t i = 0; i < n; ++i) {
      if (particles.type[i] == ParticleType::Fluid) acceleration_[i] = scene_.physics.gravity;
    }
    clock_.start(scene_.time.time_step);
    auto& density = particles.field("density");
    compute_densities(particles, system(), density);  // for the frame at t = 0
    for (std::size_t i = 0; i < n; ++i) {             // the pressure of the initial stiffness, for the frame at t = 0
      if (particles.type[i] == ParticleType::Fluid)
        particles.pressure[i] = stiffness_pressure(density_stiffness_[i], 0.0, density[i]);
    }
  }

  // CFL rule ([BK17], Algorithm 1: dt <= 0.4 d / |v_max|, d = l0 the particle diameter),
  // with v_max estimated as in the authors' code from v + dt a over the fluid: v^n and the
  // non-pressure acceleration of the last step (gravity before the first), clamped to
  // [min_time_step, max_time_step]; the last one or two steps are evened out so that the
  // run ends on time.end_time.
  double time_step(const ParticleSet& particles) const override {
    if (!time_step_settings_.cfl) return scene_.time.time_step;
    const double last_time_step = clock_.last();
    double max_speed2 = 0.0;
    for (std::size_t i = 0; i < particles.size(); ++i) {
      if (particles.type[i] != ParticleType::Fluid) continue;
      max_speed2 = std::max(max_speed2, (particles.velocity[i] + last_time_step * acceleration_[i]).squaredNorm());
    }
    return clock_.next(time_step_settings_, std::sqrt(max_speed2), scene_.particle_spacing, scene_.time.end_time);
  }

  StepReport step(ParticleSet& particles, double dt) override {
    WallContext context{particles, &neighbours_, dt, scene_};
    find_neighbourhoods(particles, context);  // 1.
    const SphSystem sph = system();
    if (computes_reactions_) reaction_.assign(particles.size(), Vec2::Zero());
    if (computes_sample_loads_) sample_loads_.reset(scene_.walls.obstacles.size());
    const double compression = densities_and_factors(particles, sph);       // 2.
    const SolverOutcome divergence = solve_divergence(particles, sph, dt);  // 3.
    add_non_pressure_forces(particles, sph);                                // 4.
    // 5. the time step dt was chosen by time_step(); 6. predicted velocities
    predict_velocities(particles, dt);
    walls_.after_explicit_velocity(context);
    const SolverOutcome pressure = solve_density(particles, sph, dt);  // 7.
    advect(particles, sph, dt, context);                               // 8.
    clock_.advance(dt);
    return step_report(divergence, pressure, compression, context);
  }

  nlohmann::json summary() const override {
    const double l0 = scene_.particle_spacing;
    double volume_min = std::numeric_limits<double>::infinity(), volume_max = 0.0;
    std::size_t boundary_particles = 0;
    for (double psi : boundary_mass_) {
      if (psi <= 0.0) continue;
      ++boundary_particles;
      volume_min = std::min(volume_min, psi / rest_density_);
      volume_max = std::max(volume_max, psi / rest_density_);
    }
    nlohmann::json summary = {
        {"kernel", kernel_.kind() == SphKernelKind::CubicSpline ? "cubic_spline" : "wendland_c2"},
        {"kernel_support_over_l0", kernel_.support() / l0},
        {"particle_mass", particle_mass_},
        {"lattice_density_over_rho0", particle_mass_ * lattice_kernel_sum(kernel_, l0) / rest_density_},
        {"lattice_neighbours", full_neighbour_count_},
        {"divergence_min_neighbours", divergence_min_neighbours_},
        {"boundary_model", walls_.boundary_name()},
        {"wall_pressure", wall_pressure_ == WallPressure::Extrapolated ? "extrapolated" : "mirrored"},
        {"time_step", clock_.summary(time_step_settings_)},
        {"density_solver", density_totals_.to_json()},
        {"density_solver_kind", global_density_ ? "amg_cg" : "relaxed_jacobi"},
        {"divergence_solver", divergence_totals_.to_json()},
        {"wall_treatments", walls_.names()},
        {"ghosts_created", ghosts_}};
    if (walls_.wall_particles()) {
      summary["boundary_particles"] = boundary_particles;
      summary["boundary_volume"] = boundary_volume_ == BoundaryVolume::Akinci ? "akinci" : "lattice";
      summary["boundary_volume_over_l0_squared"] = {{"min", boundary_particles > 0 ? volume_min / (l0 * l0) : 0.0},
                                                    {"max", volume_max / (l0 * l0)}};
    } else {
      summary["wall_samples"] = {{"hydrostatic_offset", sample_hydrostatic_}, {"last_step", samples_.samples.size()}};
    }
    if (global_density_) summary["density_cg"] = global_totals_.to_json();
    return summary;
  }

  // State between steps: the warm-start stiffnesses of both solvers, the last non-pressure
  // acceleration and step (the CFL estimate of the next time_step()), the method's clock
  // (it evens out the last steps before end_time), the boundary masses and the summary's
  // totals. The neighbour list, kernel cache and wall samples are rebuilt at the start of
  // every step (from the positions alone), so they are not saved.
  void save_state(CheckpointWriter& out) const override {
    out.write_doubles(boundary_mass_);
    out.write_doubles(density_stiffness_);
    out.write_doubles(divergence_stiffness_);
    out.write_vec2s(acceleration_);
    clock_.save(out);
    density_totals_.save(out);
    divergence_totals_.save(out);
    out.write_size(ghosts_);
    if (global_density_) global_totals_.save(out);
  }

  void restore_state(CheckpointReader& in) override {
    const std::size_t n = acceleration_.size();
    boundary_mass_ = in.read_doubles();
    density_stiffness_ = in.read_doubles();
    divergence_stiffness_ = in.read_doubles();
    acceleration_ = in.read_vec2s();
    clock_.restore(in);
    density_totals_.restore(in);
    divergence_totals_.restore(in);
    ghosts_ = in.read_size();
    if (global_density_) global_totals_.restore(in);
    for (const std::size_t size :
         {boundary_mass_.size(), density_stiffness_.size(), divergence_stiffness_.size(), acceleration_.size()}) {
      if (size != n) {
        in.fail("dfsph state for " + std::to_string(size) + " particles, the scene has " + std::to_string(n));
      }
    }
  }

  // Loads on obstacles (core/walls/obstacle_loads.hpp): the fluid's force on each wall particle
  // in the last step, N/m; null without obstacles or without wall particles (Method::wall_reactions).
  const std::vector<Vec2>* wall_reactions() const override { return computes_reactions_ ? &reaction_ : nullptr; }
  // The same on each obstacle's wall samples (core/walls/wall_sample_reactions.hpp); null without
  // obstacles or with wall particles.
  const WallSampleLoads* wall_sample_loads() const override {
    return computes_sample_loads_ ? &sample_loads_ : nullptr;
  }

  // `mps_lab bench`'s memory breakdown (docs/performance.md, "Memory"): the search, the kernel
  // caches, the wall samples and their caches, the per-particle arrays and the solvers' workspace.
  MemoryBreakdown memory_breakdown() const override {
    const SampleCache& sc = sample_cache_;
    const WallPressureStencil& ws = wall_stencil_;
    const SolverWorkspace& w = workspace_;
    MemoryBreakdown breakdown = {
        {"neighbour_list", held_bytes(neighbours_.offsets, neighbours_.indices)},
        {"cell_list", cells_.held_bytes()},
        {"kernel_cache", held_bytes(cache_.value, cache_.gradient, cache_.neighbour_mass)},
        {"wall_samples", held_bytes(samples_.offsets, samples_.samples)},
        {"sample_cache",
         held_bytes(sc.value, sc.gradient, sc.mass, sc.own, sc.reaction, sc.owner, sc.by_source_offsets, sc.by_source)},
        {"wall_pressure_stencil",
         held_bytes(ws.boundary, ws.offsets, ws.fluid, ws.weight, ws.hydrostatic, ws.sample_offsets, ws.sample_fluid,
                    ws.sample_weight, ws.sample_hydrostatic)},
        {"step_arrays",
         held_bytes(boundary_mass_, reaction_, density_stiffness_, divergence_stiffness_, acceleration_)},
        {"solver_workspace", held_bytes(w.fluid, w.velocity, w.increment, w.stiffness_over_density, w.block_error,
                                        w.block_largest, w.neighbour_counts, w.neighbour_mass)}};
    if (global_density_) append_global_density_memory(breakdown);
    return breakdown;
  }

  // density_solver = amg_cg: the surrogate's matrix, its AMG hierarchy, the CG vectors and the
  // per-particle arrays of the global solve.
  void append_global_density_memory(MemoryBreakdown& breakdown) const {
    const GlobalDensityWorkspace& g = global_workspace_;
    breakdown.push_back({"global_density.matrix", g.matrix.held_bytes()});
    breakdown.push_back({"global_density.arrays", held_bytes(g.row_of, g.particle_of, g.rhs, g.excess, g.solution,
                                                             g.neighbour_mass, g.grounded, g.reached) +
                                                      held_bytes(global_counts_, predicted_velocity_)});
    breakdown.push_back({"global_density.krylov", g.krylov.held_bytes()});
    if (g.preconditioner) append_breakdown(breakdown, "global_density.amg", g.preconditioner->memory_breakdown());
  }

  // Cell-ordered particles (core/search/cell_order.hpp): what save_state keeps per particle.
  void permute_state(const ParticleOrder& order) override {
    permute_values(boundary_mass_, order);
    permute_values(density_stiffness_, order);
    permute_values(divergence_stiffness_, order);
    permute_values(acceleration_, order);
    walls_.permute_state(order);
  }

 private:
  // 1. neighbourhoods (and the wall samples of a boundary model without wall particles), the
  // kernel cache, the wall hook after the search.
  void find_neighbourhoods(ParticleSet& particles, WallContext& context) {
    {
      const auto timed = measure(timers_, search_phase_);
      search(particles);
    }
    build_samples(context);  // the boundary model's samples: timed as "wall_treatment" by walls_
    {
      const auto timed = measure(timers_, operators_phase_);
      cache_kernels(particles);
    }
    walls_.after_neighbour_search(context);
  }

  // 2. densities and factors alpha_i; returns the mean compression.
  double densities_and_factors(ParticleSet& particles, const SphSystem& sph) {
    auto& density = particles.field("density");
    auto& alpha = particles.field("dfsph_factor");
    double compression = 0.0;
    {
      const auto timed = measure(timers_, operators_phase_);
      compute_densities(particles, sph, density);
      compute_dfsph_factors(particles, sph, density, alpha);
      compression = mean_compression(particles, density);
      if (wall_pressure_ == WallPressure::Extrapolated) {
        compute_wall_pressure_stencil(particles, sph, kernel_, density, scene_.physics.gravity, wall_stencil_);
      }
    }
    return compression;
  }

  // 3. divergence-free solver (Algorithm 2)
  SolverOutcome solve_divergence(ParticleSet& particles, const SphSystem& sph, double dt) {
    const auto& density = particles.field("density");
    const auto& alpha = particles.field("dfsph_factor");
    SolverOutcome divergence;
    if (divergence_enabled_) {
      const auto timed = measure(timers_, divergence_phase_);
      divergence = correct_divergence_error(particles, sph, density, alpha, dt, divergence_settings_,
                                            divergence_min_neighbours_, divergence_stiffness_, workspace_);
      divergence_totals_.add(divergence);
    } else {
      std::fill(divergence_stiffness_.begin(), divergence_stiffness_.end(), 0.0);
    }
    return divergence;
  }

  // 4. non-pressure forces
  void add_non_pressure_forces(const ParticleSet& particles, const SphSystem& sph) {
    const auto count = static_cast<std::ptrdiff_t>(particles.size());
    const bool threaded = count >= kThreadedLoopMinimum;
    const auto& density = particles.field("density");
    {
      const auto timed = measure(timers_, operators_phase_);
      const Vec2 gravity = scene_.physics.gravity;
#pragma omp parallel for schedule(static) if (threaded)
      for (std::ptrdiff_t i = 0; i < count; ++i) {
        acceleration_[i] = particles.type[i] == ParticleType::Fluid ? gravity : Vec2::Zero();
      }
      if (scene_.physics.kinematic_viscosity > 0.0) {
        add_viscous_acceleration(particles, sph, density, scene_.physics.kinematic_viscosity, kernel_.support(),
                                 acceleration_);
        if (computes_reactions_) {  // its boundary terms' reaction, before v changes
          add_boundary_viscous_reactions(particles, sph, kernel_, density, scene_.physics.kinematic_viscosity,
                                         reaction_);
        }
        if (computes_sample_loads_) {
          add_sample_viscous_reactions(particles, sph, density, scene_.physics.kinematic_viscosity, kernel_.support(),
                                       sample_scratch_, sample_loads_);
        }
      }
      if (computes_sample_loads_) {  // the explicit hydrostatic parts of the samples' pressure
        add_sample_hydrostatic_reactions(particles, sph, density, gravity, sample_hydrostatic_,
                                         wall_pressure_ == WallPressure::Extrapolated, sample_scratch_, sample_loads_);
      }
      if (sample_hydrostatic_) add_sample_hydrostatic_acceleration(particles, sph, density, gravity, acceleration_);
      if (wall_pressure_ == WallPressure::Extrapolated) {
        add_wall_hydrostatic_acceleration(particles, sph, gravity, acceleration_);
      }
    }
  }

  // 6. predicted velocities
  void predict_velocities(ParticleSet& particles, double dt) {
    const auto count = static_cast<std::ptrdiff_t>(particles.size());
    const bool threaded = count >= kThreadedLoopMinimum;
    {
      const auto timed = measure(timers_, integration_phase_);
#pragma omp parallel for schedule(static) if (threaded)
      for (std::ptrdiff_t i = 0; i < count; ++i) {
        if (particles.type[i] == ParticleType::Fluid) particles.velocity[i] += dt * acceleration_[i];
      }
    }
  }

  // The stiffnesses the solvers start from: zero, or (initial_stiffness = hydrostatic) the
  // density solver's kappa of the fluid at rest, |g| times the depth below the nearest free
  // surface (hydrostatic_stiffness). Needs the kernel cache and the boundary masses.
  void start_stiffnesses(const ParticleSet& particles) {
    const std::size_t n = particles.size();
    if (hydrostatic_start_) {
      std::vector<double> counts;
      count_active_neighbours(particles, system(), counts);
      hydrostatic_stiffness(particles, neighbours_, counts, static_cast<double>(full_neighbour_count_),
                            scene_.physics.gravity.norm(), scene_.particle_spacing, density_stiffness_);
    } else {
      density_stiffness_.assign(n, 0.0);
    }
    divergence_stiffness_.assign(n, 0.0);
  }

  // 7. constant-density solver (Algorithm 3). The run's first solve starts from the initial
  // stiffness in full (where compressed, as every warm start): it estimates this step's
  // stiffness, not a last step's total to be scaled by warm_start_fraction.
  SolverOutcome solve_density(ParticleSet& particles, const SphSystem& sph, double dt) {
    const auto& density = particles.field("density");
    const auto& alpha = particles.field("dfsph_factor");
    SolverOutcome pressure;
    {
      const auto timed = measure(timers_, density_phase_);
      SolverSettings settings = density_settings_;
      if (hydrostatic_start_ && density_totals_.solves == 0) settings.warm_start_fraction = 1.0;
      pressure = global_density_ ? solve_density_in_cycles(particles, sph, density, alpha, dt)
                                 : correct_density_error(particles, sph, density, alpha, dt, settings,
                                                         density_stiffness_, workspace_);
      density_totals_.add(pressure);
    }
    return pressure;
  }

  // 7a. density_solver = amg_cg (dfsph_global_density.hpp; docs/methods/dfsph.md, "A density
  // solve with global reach"): from zero stiffness, cycles of
  //   a global correction (AMG-CG on the surrogate, from the corrected velocities' error) and
  //   the relaxed Jacobi iteration from the predicted velocities v* with the new total,
  // at least density_cg_smoothing iterations per cycle (the Jacobi iteration removes the local
  // error the surrogate leaves), at most that many but in the last cycle, until the error is
  // below density_tolerance. Returns the Jacobi iterations of all cycles.
  SolverOutcome solve_density_in_cycles(ParticleSet& particles, const SphSystem& sph,
                                        const std::vector<double>& density, const std::vector<double>& alpha,
                                        double dt) {
    count_active_neighbours(particles, sph, global_counts_);
    assemble_density_system(particles, sph, global_counts_, global_settings_, global_workspace_);
    predicted_velocity_ = particles.velocity;
    SolverSettings jacobi = density_settings_;
    jacobi.warm_start_fraction = 1.0;  // the start is this step's estimate: applied in full, everywhere
    jacobi.keep_uncompressed = true;
    // Every step starts from zero stiffness: the global corrections are >= 0 (A is an M-matrix
    // and b >= 0), so a stiffness carried over could only grow (measured: the still tank
    // diverged within 4 steps with the last step's total as the start).
    for (std::size_t i = 0; i < particles.size(); ++i) density_stiffness_[i] = 0.0;
    SolverOutcome outcome;
    double initial_error = -1.0;
    long long iterations = 0;
    for (long long cycle = 0; cycle < global_cycles_; ++cycle) {
      global_totals_.add(
          add_density_increment(particles, sph, density, dt, global_settings_, density_stiffness_, global_workspace_));
      restore_predicted_velocities(particles);
      SolverSettings run = jacobi;  // a smoother: at least density_cg_smoothing iterations
      run.min_iterations = std::max(run.min_iterations, global_smoothing_);
      if (cycle + 1 < global_cycles_) run.max_iterations = std::min(run.max_iterations, global_smoothing_);
      outcome = correct_density_error(particles, sph, density, alpha, dt, run, density_stiffness_, workspace_);
      if (initial_error < 0.0) initial_error = outcome.initial_error;
      iterations += outcome.iterations;
      if (outcome.converged) break;
    }
    outcome.iterations = iterations;
    outcome.initial_error = initial_error;
    return outcome;
  }

  void restore_predicted_velocities(ParticleSet& particles) const {
    for (std::size_t i = 0; i < particles.size(); ++i) {
      if (particles.type[i] == ParticleType::Fluid) particles.velocity[i] = predicted_velocity_[i];
    }
  }

  // 8. advection, the pressure the step applied, the wall pressures, the wall hook after the
  // correction, escaped particles to ghosts.
  void advect(ParticleSet& particles, const SphSystem& sph, double dt, WallContext& context) {
    const auto count = static_cast<std::ptrdiff_t>(particles.size());
    const bool threaded = count >= kThreadedLoopMinimum;
    const auto& density = particles.field("density");
    // The pressure the step applied, in Pa, and 8. advection. Both solvers applied the
    // pressure-force operator at x^n during this step, so the momentum the step gave is that
    // of p = (kappa + kappa^v) rho (docs/methods/dfsph.md).
    if (computes_reactions_) {  // the solvers' boundary terms' reaction, at x^n
      const auto timed = measure(timers_, operators_phase_);
      add_boundary_pressure_reactions(particles, sph, kernel_, density, density_stiffness_, divergence_stiffness_,
                                      reaction_);
    }
    if (computes_sample_loads_) {  // the same on the wall samples of the step
      const auto timed = measure(timers_, operators_phase_);
      add_sample_pressure_reactions(particles, sph, density, density_stiffness_, divergence_stiffness_, sample_scratch_,
                                    sample_loads_);
    }
    {
      const auto timed = measure(timers_, integration_phase_);
      auto& divergence_pressure = particles.field("divergence_pressure");
#pragma omp parallel for schedule(static) if (threaded)
      for (std::ptrdiff_t i = 0; i < count; ++i) {
        const bool fluid = particles.type[i] == ParticleType::Fluid;
        divergence_pressure[i] = fluid ? divergence_stiffness_[i] * density[i] : 0.0;
        if (!fluid) continue;
        particles.pressure[i] = stiffness_pressure(density_stiffness_[i], divergence_stiffness_[i], density[i]);
        particles.position[i] += dt * particles.velocity[i];
      }
    }
    if (walls_.wall_particles()) {  // reads the fluid pressures and the kernel cache at x^n, not positions
      const auto timed = measure(timers_, operators_phase_);
      compute_boundary_pressures(particles, sph, kernel_, density, scene_.particle_spacing);
    }
    walls_.after_correction(context);
    {
      const auto timed = measure(timers_, integration_phase_);
      ghosts_ += mark_escaped_as_ghosts(particles, scene_);
    }
  }

  StepReport step_report(const SolverOutcome& divergence, const SolverOutcome& pressure, double compression,
                         const WallContext& context) const {
    StepReport report;
    report.speed_limited_particles = context.speed_limited;
    report.solver_iterations = pressure.iterations;
    report.solver_residual = pressure.error;
    report.solver_converged = pressure.converged && divergence.converged;
    report.solver_note = convergence_note(divergence, divergence_settings_, "divergence") +
                         convergence_note(pressure, density_settings_, "density");
    report.extra = {static_cast<double>(divergence.iterations), divergence.error,
                    static_cast<double>(pressure.iterations), pressure.error, compression};
    return report;
  }

  SphSystem system() const {
    const WallPressureStencil* stencil = wall_pressure_ == WallPressure::Extrapolated ? &wall_stencil_ : nullptr;
    return {neighbours_, cache_, boundary_mass_, particle_mass_, rest_density_, &samples_, &sample_cache_, stencil};
  }

  // The boundary model's wall samples for the fresh neighbour list (none for a model of wall
  // particles), their kernel values, and what the hooks of this step see of them.
  void build_samples(WallContext& context) {
    context.support = kernel_.support();
    walls_.build_wall_samples(context, samples_);
    context.samples = &samples_;
  }

  void search(const ParticleSet& particles) {
    cells_.build(particles.position, particles.type, kernel_.support());
    cells_.find_neighbours(particles.position, particles.type, kernel_.support(), neighbours_);
  }

  // W and grad W of every neighbour pair and wall sample, once per step at x^n: every operator
  // and solver iteration of the step reads them.
  // The volume of a boundary particle of the lattice rule (akinci_boundary's volume "lattice",
  // dummy_layers), m^2: the fluid particle's, m / rho0 (l0^2, or 1 / sum_lattice W with
  // particle_mass "lattice"). A wall row then weighs what a fluid row weighs, so a uniform
  // stiffness exerts no force on the fluid next to a wall (the global solve's Neumann wall);
  // with l0^2 walls and lattice fluid a column 1419 particles high diverged at step 2
  // (docs/methods/dfsph.md, "A density solve with global reach").
  double lattice_wall_volume() const { return particle_volume_; }

  void cache_kernels(const ParticleSet& particles) {
    const double l0 = scene_.particle_spacing;
    if (!particles.wall_velocity.empty() && boundary_volume_ == BoundaryVolume::Akinci) {
      // Moving walls (core/walls/moving_walls.hpp): Akinci's V_b = 1 / sum_k W_bk changes as
      // they move, so it is summed again at the wall positions of this step.
      compute_kernel_cache(particles, neighbours_, kernel_, cache_);
      compute_boundary_masses(particles, neighbours_, cache_, boundary_wall_layers_, rest_density_, boundary_volume_,
                              lattice_wall_volume(), boundary_mass_);
    }
    compute_kernel_cache(particles, neighbours_, kernel_, particle_mass_, boundary_mass_, cache_);
    compute_sample_cache(particles, samples_, kernel_, rest_density_, l0 * l0, sample_cache_);
  }

  // Mean max(rho_i - rho0, 0) / rho0 over the fluid at the start of the step: the compression
  // the last step actually left (the solver's error is a prediction).
  double mean_compression(const ParticleSet& particles, const std::vector<double>& density) const {
    double sum = 0.0;
    std::size_t fluid = 0;
    for (std::size_t i = 0; i < particles.size(); ++i) {
      if (particles.type[i] != ParticleType::Fluid) continue;
      sum += std::max(density[i] - rest_density_, 0.0) / rest_density_;
      ++fluid;
    }
    return fluid > 0 ? sum / static_cast<double>(fluid) : 0.0;
  }

  static std::string convergence_note(const SolverOutcome& outcome, const SolverSettings& settings, const char* name) {
    if (outcome.converged) return "";
    return std::string(name) + " solver error " + format_double(outcome.error) + " > tolerance " +
           format_double(settings.tolerance) + " after " + std::to_string(outcome.iterations) + " iterations; ";
  }

  const Scene& scene_;
  WallTreatmentSet walls_;
  PhaseTimers* timers_;  // core/run/profile.hpp; null outside a run
  PhaseTimers::Id search_phase_, operators_phase_, divergence_phase_, density_phase_, integration_phase_;
  SphKernel kernel_;
  double rest_density_ = 1000.0;         // kg/m^3
  double particle_mass_ = 0.0;           // kg/m
  double particle_volume_ = 0.0;         // m^2, particle_mass_ / rho0
  TimeStepSettings time_step_settings_;  // core/run/time_step.hpp
  SolverSettings density_settings_, divergence_settings_;
  bool divergence_enabled_ = true;
  std::uint32_t full_neighbour_count_ = 0;
  std::uint32_t divergence_min_neighbours_ = 0;
  int boundary_wall_layers_ = 3;
  BoundaryVolume boundary_volume_ = BoundaryVolume::Akinci;
  bool sample_hydrostatic_ = false;
  WallPressure wall_pressure_ = WallPressure::Mirrored;
  bool hydrostatic_start_ = false;  // initial_stiffness = hydrostatic

  CellList cells_;
  NeighbourList neighbours_;
  KernelCache cache_;
  WallSampleList samples_;  // wall samples of this step (boundary models without wall particles)
  SampleCache sample_cache_;
  WallPressureStencil wall_stencil_;   // wall_pressure = extrapolated: this step's boundary extrapolation
  std::vector<double> boundary_mass_;  // Psi_b, kg/m
  bool computes_reactions_ = false;
  std::vector<Vec2> reaction_;  // the fluid's force on each wall particle in this step, N/m
  bool computes_sample_loads_ = false;
  WallSampleLoads sample_loads_;              // the fluid's force on each obstacle's wall samples in this step
  std::vector<Vec2> sample_scratch_;          // per sample, N/m (core/walls/wall_sample_reactions.hpp)
  std::vector<double> density_stiffness_;     // kappa_i of the density solver, m^2/s^2
  std::vector<double> divergence_stiffness_;  // kappa^v_i of the divergence solver, m^2/s^2
  std::vector<Vec2> acceleration_;            // non-pressure acceleration of the last step, m/s^2
  SolverWorkspace workspace_;
  bool global_density_ = false;  // density_solver = amg_cg
  GlobalDensitySettings global_settings_;
  GlobalDensityWorkspace global_workspace_;
  std::vector<double> global_counts_;  // fluid + boundary neighbours of this step
  long long global_cycles_ = 1, global_smoothing_ = 1;
  std::vector<Vec2> predicted_velocity_;  // v* of this step, m/s
  GlobalSolveTotals global_totals_;

  TimeStepClock clock_;  // simulated time, the last step (the CFL estimate's dt), min/max/mean
  SolverTotals density_totals_, divergence_totals_;
  std::size_t ghosts_ = 0;
};

}  // namespace
}  // namespace mps_lab::dfsph

namespace {

// The density solver's choice and the parameters of the global solve (density_solver amg_cg).
std::vector<mps_lab::ParameterSpec> global_density_parameters() {
  using namespace mps_lab;
  return {
      string_parameter("density_solver", "relaxed_jacobi",
                       "relaxed_jacobi (BK17 Algorithm 3) or amg_cg: the density constraints as one linear system, "
                       "solved by AMG-preconditioned conjugate gradients, then finished by the relaxed Jacobi "
                       "iteration (global reach; docs/methods/dfsph.md 'A density solve with global reach')")
          .one_of({"amg_cg", "relaxed_jacobi"}),
      number_parameter("density_cg_tolerance", dfsph::kDefaultCgTolerance, "",
                       "amg_cg: relative residual ||b - A s|| / ||b|| at which the linear solve stops")
          .above(0.0)
          .below(1.0),
      integer_parameter("density_cg_max_iterations", dfsph::kDefaultCgIterations, "amg_cg: CG iteration cap")
          .at_least(1)
          .at_most(100000),
      integer_parameter("density_cg_cycles", dfsph::kDefaultCgCycles,
                        "amg_cg: at most this many cycles of a global correction and relaxed Jacobi iterations")
          .at_least(1)
          .at_most(1000),
      integer_parameter("density_cg_smoothing", dfsph::kDefaultCgSmoothing,
                        "amg_cg: relaxed Jacobi iterations after each global correction, a smoother (the last cycle: "
                        "at least this many, up to density_max_iterations)")
          .at_least(1)
          .at_most(100000),
  };
}

// The parameters of methods.dfsph (core/base/parameters.hpp), documented in docs/methods/dfsph.md.
std::vector<mps_lab::ParameterSpec> dfsph_parameters() {
  using namespace mps_lab;
  std::vector<ParameterSpec> parameters{
      string_parameter("kernel", "cubic_spline", "SPH kernel (BK17: cubic spline)")
          .one_of({"cubic_spline", "wendland_c2"}),
      number_parameter("kernel_support", 2.0, "l0",
                       "kernel support radius (where W = 0): BK17/SPlisHSPlasH 4 r = 2 l0, i.e. h = l0")
          .above(1.0)
          .at_most(4.0),
      number_parameter("density_tolerance", 1.0e-4, "",
                       "density solver stops at mean max(rho* - rho0, 0)/rho0 below this (BK17: 0.01 %)")
          .above(0.0)
          .below(1.0),
      number_parameter("density_local_tolerance", 0.0, "",
                       "density solver also iterates until every particle's max(rho* - rho0, 0)/rho0 is at most this "
                       "(0: off, BK17's mean alone)")
          .at_least(0.0)
          .below(1.0),
      integer_parameter("density_min_iterations", 2, "density solver: at least this many iterations (BK17: 2)")
          .at_least(0)
          .at_most(100000),
      integer_parameter("density_max_iterations", 100, "density solver iteration cap").at_least(1).at_most(100000),
      boolean_parameter("divergence_solver", true,
                        "run the divergence-free solver (false: constant-density solver only)"),
      number_parameter("divergence_tolerance", 1.0e-3, "",
                       "divergence solver stops at dt mean max(D rho/Dt, 0)/rho0 below this (BK17: 0.1 %)")
          .above(0.0)
          .below(1.0),
      integer_parameter("divergence_min_iterations", 1, "divergence solver: at least this many iterations (BK17: 1)")
          .at_least(0)
          .at_most(100000),
      integer_parameter("divergence_max_iterations", 100, "divergence solver iteration cap")
          .at_least(1)
          .at_most(100000),
      number_parameter("divergence_neighbour_fraction", 0.875, "",
                       "no divergence correction for particles with fewer neighbours than this fraction of the full "
                       "lattice count (SPlisHSPlasH 2-D: 7 of 8)")
          .at_least(0.0)
          .at_most(1.0),
      number_parameter(
          "warm_start_fraction", 0.5, "",
          "share of the last step's stiffness both solvers start from (SPlisHSPlasH 0.5; BK17 text: the sum)")
          .at_least(0.0)
          .at_most(1.0),
      string_parameter("particle_mass", "spacing",
                       "spacing (m = rho0 l0^2: the lattice's SPH density is 1.0009 rho0 with the default kernel) or "
                       "lattice (m = rho0 / sum_lattice W: the initial lattice is at rest density)")
          .one_of({"lattice", "spacing"}),
      string_parameter("initial_stiffness", "zero",
                       "the density solver's stiffness before the first step: zero (cold start) or hydrostatic (|g| "
                       "times the depth below the nearest free surface, applied in full by the first solve)")
          .one_of({"hydrostatic", "zero"}),
      string_parameter("wall_pressure", "mirrored",
                       "the wall's pressure in the pressure force: mirrored (Akinci et al. 2012: the fluid "
                       "particle's own, once) or extrapolated (Adami et al. 2012 eq. 27 with the hydrostatic term, "
                       "in the symmetric force of Band et al. 2018; docs/methods/dfsph.md 'At the walls')")
          .one_of({"extrapolated", "mirrored"}),
      boolean_parameter("wall_sample_hydrostatic", false,
                        "wall samples (boundary models without wall particles): add the hydrostatic part "
                        "rho0 g.(x_w - x_s) of their pressure as an explicit force (measured harmful)"),
  };
  for (ParameterSpec& spec : global_density_parameters()) parameters.push_back(std::move(spec));
  return parameters;
}

}  // namespace

void mps_lab_register_method_dfsph(mps_lab::MethodRegistry& registry) {
  using namespace mps_lab;
  MethodInfo info;
  info.name = "dfsph";
  info.description =
      "Divergence-Free SPH (Bender & Koschier 2015/2017): divergence and constant-density solvers, Akinci boundaries "
      "or wall samples";
  info.parameters = dfsph_parameters();
  info.fields = {{"density", "kg/m^3", "SPH density rho_i at the start of the step (fluid; 0 elsewhere)", true},
                 {"divergence_pressure", "Pa", "kappa^v rho: the divergence-free solver's part of `pressure`", true},
                 {"boundary_volume", "m^2", "Akinci volume V_b = 1 / sum_k W_bk of the boundary particles", true},
                 {"dfsph_factor", "m^5/kg", "alpha_i of BK17 eq. (11)", false}};
  info.series_columns = {"divergence_iterations", "divergence_error", "density_iterations", "density_error",
                         "compression"};
  // The step ([BK17] Algorithm 1: dt <= 0.4 d / v_max, d = l0), bounded as in SPlisHSPlasH.
  const auto time_step_specs = time_step_parameters({"cfl", 0.4, 1.0e-4, 5.0e-3, "BK17: 0.4", "SPlisHSPlasH default"});
  info.parameters.insert(info.parameters.begin() + 2, time_step_specs.begin(), time_step_specs.end());
  info.default_wall_treatments = {"akinci_boundary"};
  info.wall_samples = true;  // its operators sum over wall samples (core/walls/wall_samples.hpp)
  info.wall_particle_models = {WallParticlePressure::AkinciMirrored};  // akinci_boundary
  info.moving_walls = true;  // wall velocity in the viscous term and the wall pressure (docs/walls.md, "Moving walls")
  info.obstacle_loads =
      true;  // [AIA12] eq. (10)'s reaction on boundary particles (docs/walls.md, "Loads on obstacles")
  info.sample_obstacle_loads = true;  // ... and on wall samples (add_sample_pressure_reactions)
  // For wall loads: the wall's own extrapolated pressure in a symmetric force and a kernel of
  // support 2.4 l0 (docs/methods/dfsph.md, "A wider kernel"); at the defaults the walls read
  // 1.5-1.6 rho g h (the one-sided wall term). And a quiet pool (docs/methods/dfsph.md, "The load
  // setting's quiet pool"): the density solve to 0.001 % and particle shifting with a fixed part
  // B = 0.01, which together remove the particle-scale motion that biased the pressure gradient.
  info.load_setting = {
      {{"wall_pressure", "\"extrapolated\""}, {"kernel_support", "2.4"}, {"density_tolerance", "1e-5"}},
      0.02,
      "measured within 1.4 % (0.986-1.012) with every boundary model in 24 realisations over [0.5, 3] s "
      "(280 of 288 sensors within 1 %; in expectation 0.996-1.009, all 12 within 1 %); at 1.5 g within 1.6 % "
      "(0.986-1.016, 8 realisations, 81 of 96 within 1 %); 2026-12-07, docs/validation.md",
      {{"wall_treatments.particle_shifting", "{\"fixed_coefficient\": 0.01}"}}};
  info.wall_hooks = dfsph::kWallHooks;
  info.create = [](const MethodSetup& setup) { return std::make_unique<dfsph::DfsphMethod>(setup); };
  registry.add(std::move(info));
}
