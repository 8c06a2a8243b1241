// The reference method: semi-implicit MPS exactly as the specification (spec §5), on the
// shared core. Step order (spec §5.1, §5.2):
//   explicit:  a = g + nu <lap u>;  u* = u + dt a;  [CFL clamp];  r* = r + dt u*;
//              walls fixed;  [position clamp]
//   implicit:  neighbour search at r*;  [repulsion];  [collision];  n*;  free surface;
//              PPE by CG;  P < 0 -> 0;  u = u* - dt grad P / rho;  r = r* + dt (dt a_p);
//              walls fixed;  [position clamp];  escaped particles -> ghosts
// Bracketed steps are wall treatments (core/walls/), on by default, each switchable.
// Decisions where the spec is open are documented in docs/methods/mps.md.
#include <algorithm>
#include <cmath>
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
#include "core/run/time_step.hpp"
#include "core/search/cell_order.hpp"
#include "core/walls/obstacle_membership.hpp"
#include "methods/mps/mps_loads.hpp"
#include "methods/mps/mps_operators.hpp"
#include "methods/mps/mps_pressure.hpp"
#include "methods/mps/mps_schemes.hpp"

namespace mps_lab::mps {
namespace {

// The wall hooks the step calls (MethodInfo::wall_hooks): all four points of spec §5.
constexpr WallHooks kWallHooks = WallHooks::all();
// Defaults of the source-term coefficients: the spec's relaxation (§3, the literal of its
// declaration below) and Tanaka & Masunaga's gamma (2010).
constexpr double kDefaultRelaxation = 0.2;
constexpr double kDefaultMixedRelaxation = 0.01;
// The CFL rule's factor: below the spec's velocity clamp (cfl_velocity_clamp, v_max = 0.2 l0 / dt),
// so the clamp sits at 0.2 / 0.16 = 1.25 times the speed the step is sized for.
constexpr double kDefaultCflNumber = 0.16;

class MpsMethod final : public Method {
 public:
  explicit MpsMethod(const MethodSetup& setup)
      : scene_(setup.scene),
        walls_(setup.wall_treatments, setup.scene, setup.timers, kWallHooks),
        timers_(setup.timers),
        search_phase_(phase_id(timers_, "neighbour_search")),
        operators_phase_(phase_id(timers_, "operators")),
        assembly_phase_(phase_id(timers_, "matrix_assembly")),
        solve_phase_(phase_id(timers_, "pressure_solve")),
        integration_phase_(phase_id(timers_, "integration")) {
    const auto& p = setup.parameters;
    ppe_.observe(setup.pressure_system_observer);
    ppe_.projection_solver().configure_amg(amg_options(p));
    const double l0 = scene_.particle_spacing;
    const double r_min = p.number("r_min") * l0;
    density_radius_ = make_operator_radius(l0, p.number("re_number_density") * l0, r_min);
    gradient_radius_ = make_operator_radius(l0, p.number("re_gradient") * l0, r_min);
    laplacian_radius_ = make_operator_radius(l0, p.number("re_laplacian") * l0, r_min);
    search_radius_ = std::max({density_radius_.re, gradient_radius_.re, laplacian_radius_.re});
    // The wall-particle model (spec_wall_particles): which wall layers carry pressure (the other
    // boundary models have no wall particles; their wall samples carry extrapolated pressures).
    if (const WallParticleModel* model = walls_.wall_particle_model()) {
      if (model->pressure() != WallParticlePressure::SolvedInPpe) {
        throw std::logic_error(std::string("mps: wall-particle model ") +
                               wall_particle_pressure_name(model->pressure()) + " is not implemented by this method");
      }
      pressure_wall_layers_ = model->pressure_layers();
    }
    min_includes_self_ = p.boolean("min_pressure_includes_self");
    settings_.density = scene_.physics.density;
    settings_.gravity = scene_.physics.gravity;
    settings_.relaxation = p.number("relaxation");
    settings_.free_surface_threshold = p.number("free_surface_threshold");
    settings_.surface_offset = p.number("free_surface_offset") * scene_.particle_spacing;  // m
    settings_.tolerance = p.number("cg_tolerance");
    settings_.max_iterations = p.integer("cg_max_iterations");
    settings_.warm_start = p.boolean("warm_start");
    time_step_settings_ = time_step_settings(p, scene_.time.time_step, scene_.source);
    preconditioner_choice_ = p.string("preconditioner");
    amg_min_fluid_particles_ = static_cast<std::size_t>(p.integer("amg_min_fluid_particles"));
    settings_.amg_reuse_budget = p.number("amg_reuse_budget");
    settings_.clamp_negative = p.boolean("clamp_negative_pressure");
    read_schemes(p);
    // Loads on obstacles (MethodInfo::obstacle_loads): the reaction on wall particles, when there are both.
    // obstacle_load: wall_pressure (the wall particles' pressure over the surface; with wall samples,
    // which have no pressure of their own, the fluid's), pair_reaction, or fluid_pressure (the
    // fluid's pressure carried to the surface, integrated by the driver: core/walls/
    // surface_pressure_loads.hpp, with any boundary model).
    const std::string load = p.string("obstacle_load");
    fluid_pressure_load_ = load == "fluid_pressure" || (load == "wall_pressure" && !walls_.wall_particles());
    surface_loads_ = load == "wall_pressure" && walls_.wall_particles();
    const bool obstacles = !scene_.walls.obstacles.empty();
    computes_reactions_ = obstacles && walls_.wall_particles() && !fluid_pressure_load_;
    computes_sample_loads_ = obstacles && !walls_.wall_particles() && !fluid_pressure_load_;
    particle_mass_ = scene_.physics.density * l0 * l0;
  }

  void initialise(ParticleSet& particles) override {
    const std::size_t n = particles.size();
    // "auto": AMG from amg_min_fluid_particles on (kDefaultAmgMinFluidParticles: the measured
    // break-even), decided once per run from the initial particles, so a restored checkpoint
    // decides the same.
    settings_.preconditioner =
        choose_preconditioner(preconditioner_choice_, particles.count(ParticleType::Fluid), amg_min_fluid_particles_);
    carries_pressure_.assign(n, 0);
    for (std::size_t i = 0; i < n; ++i) {
      carries_pressure_[i] =
          particles.type[i] == ParticleType::Fluid ||
          (particles.type[i] == ParticleType::Wall && particles.wall_layer[i] <= pressure_wall_layers_);
    }
    acceleration_.assign(n, Vec2::Zero());
    if (computes_reactions_ && surface_loads_) {  // the obstacles' surfaces where the scene puts them
      const ParticleSet rest = build_particles(scene_, true);
      surface_ = obstacle_surface(scene_, rest, obstacle_of_wall_particles(scene_, rest));
    }
    WallContext context{particles, &neighbours_, 0.0, scene_};
    search_with_samples(particles, context);
    number_density(particles, neighbours_, samples_, density_radius_, particles.field("number_density"));
  }

  // "fixed" (the default): the spec's constant dt, the scene's time.time_step (spec §3). "cfl"
  // (core/run/time_step.hpp): dt = cfl_number l0 / v_max, v_max = max_i |u_i| + |g| dt_prev over
  // the fluid, within [min_time_step, max_time_step]; docs/methods/mps.md, "Time step".
  double time_step(const ParticleSet& particles) const override {
    if (!time_step_settings_.cfl) return scene_.time.time_step;
    return clock_.next(time_step_settings_, largest_speed_with_gravity(particles, scene_.physics.gravity, clock_),
                       scene_.particle_spacing, scene_.time.end_time);
  }

  StepReport step(ParticleSet& particles, double dt) override {
    WallContext context{particles, &neighbours_, dt, scene_};
    context.samples = &samples_;
    context.support = search_radius_;
    explicit_step(particles, dt, context);  // 5.1
    // --- 5.2 implicit step -------------------------------------------------------------
    search_with_samples(particles, context);                          // 5.2-1 (and the wall samples at r*)
    walls_.after_neighbour_search(context);                           // 5.2-2 repulsion, 5.2-3 collision
    const PressureSolveResult solve = solve_pressure(particles, dt);  // 5.2-4 to 5.2-7
    correct(particles, dt, context);                                  // 5.2-8 to 5.2-11
    total_iterations_ += solve.iterations;
    clock_.advance(dt);
    ungrounded_groups_ += solve.ungrounded_groups;
    return step_report(particles, solve, context);
  }

  nlohmann::json summary() const override {
    const double l0 = scene_.particle_spacing;
    const auto radius_json = [l0](const OperatorRadius& radius) {
      return nlohmann::json{
          {"re_over_l0", radius.re / l0}, {"n0", radius.n0}, {"lambda_over_l0_squared", radius.lambda / (l0 * l0)}};
    };
    return {{"number_density_radius", radius_json(density_radius_)},
            {"gradient_radius", radius_json(gradient_radius_)},
            {"laplacian_radius", radius_json(laplacian_radius_)},
            {"wall_treatments", walls_.names()},
            {"boundary_model", walls_.boundary_name()},
            {"preconditioner", preconditioner_name(settings_.preconditioner)},
            {"preconditioner_setups", ppe_.projection_solver().setups()},
            {"amg_reused_solves", ppe_.projection_solver().reused_solves()},
            {"schemes", scheme_names_},
            {"time_step", clock_.summary(time_step_settings_)},
            {"ghosts_created", ghosts_},
            {"ungrounded_groups_regularised", ungrounded_groups_},
            {"nonconverged_solves", nonconverged_solves_}};
  }

  // State between steps: the explicit step of the next step reuses the neighbour list of
  // this step's search at r* (spec §5.1-2), which the end-of-step positions cannot rebuild;
  // carries_pressure_ (from the initial types) and the summary's totals. acceleration_,
  // the cell list and the solver's matrices are rebuilt every step; CG's warm start is
  // particles.pressure.
  void save_state(CheckpointWriter& out) const override {
    write_neighbour_list(out, neighbours_);
    write_wall_samples(out, samples_);
    out.write_chars(carries_pressure_);
    out.write_int(total_iterations_);
    clock_.save(out);
    out.write_size(ghosts_);
    out.write_size(ungrounded_groups_);
    out.write_int(nonconverged_solves_);
    ppe_.projection_solver().save_state(out);
  }

  void restore_state(CheckpointReader& in) override {
    read_neighbour_list(in, neighbours_);
    read_wall_samples(in, samples_);
    carries_pressure_ = in.read_chars();
    total_iterations_ = in.read_int();
    clock_.restore(in);
    ghosts_ = in.read_size();
    ungrounded_groups_ = in.read_size();
    nonconverged_solves_ = in.read_int();
    ppe_.projection_solver().restore_state(in, settings_.preconditioner);
    if (carries_pressure_.size() != acceleration_.size() || neighbours_.particle_count() != acceleration_.size()) {
      in.fail("mps state for " + std::to_string(carries_pressure_.size()) + " particles, the scene has " +
              std::to_string(acceleration_.size()));
    }
  }

  // Loads on obstacles (core/walls/obstacle_loads.hpp): the fluid's force on each wall particle
  // in the last step, N/m; null without obstacles or without wall particles (Method::wall_reactions).
  const std::vector<Vec2>* wall_reactions() const override { return computes_reactions_ ? &reaction_ : nullptr; }
  const WallSampleLoads* wall_sample_loads() const override {
    return computes_sample_loads_ ? &sample_loads_ : nullptr;
  }
  // obstacle_load wall_pressure: the surface integral of the wall particles' pressure (or, with wall
  // samples, of the fluid's); pair_reaction: the wall pairs'; fluid_pressure: the fluid's pressure.
  ObstacleLoadKind obstacle_load_kind() const override {
    if (fluid_pressure_load_) return ObstacleLoadKind::FluidPressure;
    return surface_loads_ ? ObstacleLoadKind::SurfacePressure : ObstacleLoadKind::PairReaction;
  }

  // `mps_lab bench`'s memory breakdown (docs/performance.md, "Memory"): the search, the
  // per-particle arrays of the step, the obstacles' surface and the pressure solve.
  MemoryBreakdown memory_breakdown() const override {
    MemoryBreakdown out = {
        {"neighbour_list", held_bytes(neighbours_.offsets, neighbours_.indices)},
        {"cell_list", cells_.held_bytes()},
        {"wall_samples", held_bytes(samples_.offsets, samples_.samples)},
        {"step_arrays", held_bytes(acceleration_, reaction_, sample_scratch_, wetted_, carries_pressure_, scheme_rate_,
                                   scheme_source_, minimum_pressure_, correction_)},
        {"obstacle_surface",
         held_bytes(surface_.element_of_id, surface_.rest_position_of_id, surface_.rest_mean, surface_.members)}};
    append_breakdown(out, "ppe", ppe_.memory_breakdown());
    return out;
  }

  // Cell-ordered particles (core/search/cell_order.hpp): what save_state keeps per particle.
  void permute_state(const ParticleOrder& order) override {
    permute_neighbour_list(neighbours_, order);
    permute_wall_samples(samples_, order);
    permute_values(carries_pressure_, order);
    ppe_.projection_solver().permute_state(order);
    walls_.permute_state(order);
  }

 private:
  // The pressure schemes (mps_schemes.hpp). A coefficient of a source term that is not chosen
  // would be ignored: set to other than its default, it is an input error.
  void read_schemes(const ParameterValues& p) {
    gradient_scheme_ = pressure_gradient_scheme(p.string("pressure_gradient"));
    source_scheme_ = source_term_scheme(p.string("source_term"));
    settings_.laplacian_scheme = ppe_laplacian_scheme(p.string("ppe_laplacian"));
    mixed_relaxation_ = p.number("mixed_relaxation");
    gradient_correction_ = p.boolean("gradient_correction");
    dry_ = dry_wall_rule(p.string("dry_wall_points") == "excluded", settings_);
    scheme_names_ = {{"pressure_gradient", p.string("pressure_gradient")},
                     {"gradient_correction", gradient_correction_},
                     {"source_term", p.string("source_term")},
                     {"ppe_laplacian", p.string("ppe_laplacian")},
                     {"dry_wall_points", p.string("dry_wall_points")}};
    const std::string block = p.block_path().empty() ? std::string("methods.mps") : p.block_path();
    if (source_scheme_ != SourceTermScheme::Spec && settings_.relaxation != kDefaultRelaxation) {
      throw_input_error(scene_.source, block + ".relaxation",
                        "applies to source_term spec only, got source_term " + p.string("source_term") +
                            " (leave relaxation at " + format_double(kDefaultRelaxation) + ")");
    }
    if (source_scheme_ != SourceTermScheme::Mixed && mixed_relaxation_ != kDefaultMixedRelaxation) {
      throw_input_error(scene_.source, block + ".mixed_relaxation",
                        "applies to source_term mixed only, got source_term " + p.string("source_term"));
    }
  }

  // Spec §5.1: gravity and viscosity, u*, r*, with the wall hooks after the velocity and the
  // position.
  void explicit_step(ParticleSet& particles, double dt, WallContext& context) {
    const auto count = static_cast<std::ptrdiff_t>(particles.size());
    const Vec2 gravity = scene_.physics.gravity;
    {
      const auto timed = measure(timers_, operators_phase_);
#pragma omp parallel for schedule(static)
      for (std::ptrdiff_t i = 0; i < count; ++i) {
        acceleration_[i] = particles.type[i] == ParticleType::Fluid ? gravity : Vec2::Zero();  // 5.1-1
      }
      if (computes_reactions_) reaction_.assign(particles.size(), Vec2::Zero());
      if (computes_sample_loads_) sample_loads_.reset(scene_.walls.obstacles.size());
      if (scene_.physics.kinematic_viscosity > 0.0) {  // 5.1-2 (costs nothing when nu = 0)
        add_viscous_acceleration(particles, neighbours_, samples_, laplacian_radius_,
                                 scene_.physics.kinematic_viscosity, acceleration_);
        if (computes_reactions_) {  // its wall terms' reaction, before u changes
          add_viscous_wall_reactions(particles, neighbours_, laplacian_radius_, scene_.physics.kinematic_viscosity,
                                     particle_mass_, reaction_);
        }
        if (computes_sample_loads_) {  // with the samples the viscous term used (those of the last search)
          add_viscous_sample_reactions(particles, samples_, laplacian_radius_, scene_.physics.kinematic_viscosity,
                                       particle_mass_, sample_scratch_, sample_loads_);
        }
      }
    }
    {
      const auto timed = measure(timers_, integration_phase_);
#pragma omp parallel for schedule(static)
      for (std::ptrdiff_t i = 0; i < count; ++i) {
        if (particles.type[i] == ParticleType::Fluid) particles.velocity[i] += dt * acceleration_[i];  // 5.1-3
      }
    }
    walls_.after_explicit_velocity(context);  // 5.1-4 CFL clamp
    {
      const auto timed = measure(timers_, integration_phase_);
#pragma omp parallel for schedule(static)
      for (std::ptrdiff_t i = 0; i < count; ++i) {
        if (particles.type[i] == ParticleType::Fluid) particles.position[i] += dt * particles.velocity[i];  // 5.1-5
      }
      hold_walls_at_prescribed_velocity(particles);  // 5.1-6
    }
    walls_.after_explicit_position(context);  // 5.1-7 position clamp
  }

  // Spec §5.2-4 to 5.2-7: n*, the free surface, the PPE and its solve.
  PressureSolveResult solve_pressure(ParticleSet& particles, double dt) {
    auto& n_star = particles.field("number_density");
    {
      const auto timed = measure(timers_, operators_phase_);
      number_density(particles, neighbours_, samples_, density_radius_, n_star);  // 5.2-4
    }
    PressureSolveResult solve = [&] {  // 5.2-5 free surface, PPE matrix and right-hand side
      const auto timed = measure(timers_, assembly_phase_);
      settings_.source_term = scheme_source_term(particles, dt);
      return ppe_.assemble(particles, neighbours_, samples_, n_star, carries_pressure_, laplacian_radius_,
                           density_radius_.n0, dt, settings_, particles.field("free_surface"));
    }();
    {  // 5.2-6 CG, 5.2-7 P < 0 -> 0
      const auto timed = measure(timers_, solve_phase_);
      ppe_.solve_assembled(particles, settings_, solve);
    }
    if (!solve.converged) ++nonconverged_solves_;  // the stability monitor records it (StepReport)
    return solve;
  }

  // b_i of the chosen source term at the provisional state (mps_schemes.hpp); null for the spec's.
  const std::vector<double>* scheme_source_term(const ParticleSet& particles, double dt) {
    if (source_scheme_ == SourceTermScheme::Spec) return nullptr;
    const SourceTermInputs in{particles.field("number_density"),
                              scheme_rate_,
                              density_radius_.n0,
                              dt,
                              scene_.physics.density,
                              mixed_relaxation_};
    source_terms(source_scheme_, particles, neighbours_, samples_, density_radius_, in, scheme_rate_, scheme_source_);
    return &scheme_source_;
  }

  // Spec §5.2-8 to 5.2-11: the pressure acceleration, u and r corrected, the wall hook after
  // the correction, escaped particles to ghosts.
  void correct(ParticleSet& particles, double dt, WallContext& context) {
    const auto count = static_cast<std::ptrdiff_t>(particles.size());
    {
      const auto timed = measure(timers_, operators_phase_);
      if (gradient_scheme_ == PressureGradientScheme::Cmps) {  // Khayyer & Gotoh (2008)
        cmps_pressure_acceleration(particles, neighbours_, samples_, gradient_radius_, carries_pressure_,
                                   scene_.physics.density, scene_.physics.gravity, min_includes_self_,
                                   minimum_pressure_, acceleration_, dry_);
      } else {
        pressure_acceleration(particles, neighbours_, samples_, gradient_radius_, carries_pressure_,
                              scene_.physics.density, scene_.physics.gravity, min_includes_self_, acceleration_, dry_);
      }
      if (gradient_correction_) {  // GC, Khayyer & Gotoh (2011)
        gradient_correction_matrices(particles, neighbours_, samples_, gradient_radius_, carries_pressure_, correction_,
                                     dry_);
        apply_gradient_correction(particles, correction_, acceleration_);
      }
      if (computes_reactions_ || computes_sample_loads_) pressure_reactions(particles);
    }
    {
      const auto timed = measure(timers_, integration_phase_);
#pragma omp parallel for schedule(static)
      for (std::ptrdiff_t i = 0; i < count; ++i) {  // 5.2-8
        if (particles.type[i] != ParticleType::Fluid) continue;
        particles.velocity[i] += dt * acceleration_[i];
        particles.position[i] += dt * (dt * acceleration_[i]);
      }
      hold_walls_at_prescribed_velocity(particles);  // 5.2-9
    }
    walls_.after_correction(context);  // 5.2-10 position clamp
    {
      const auto timed = measure(timers_, integration_phase_);
      ghosts_ += mark_escaped_as_ghosts(particles, scene_);  // 5.2-11
    }
  }

  // The pressure's load on the wall particles: obstacle_load wall_pressure, the wall particles'
  // pressure of this step's solve over the surface each stands for (mps_loads.hpp); pair_reaction,
  // the reaction of the pressure term's wall pairs (add_pressure_wall_reactions), or of its wall
  // samples' pairs (add_pressure_sample_reactions), with the P_min of the spec's gradient (CMPS has
  // its Phat already).
  void pressure_reactions(const ParticleSet& particles) {
    if (surface_loads_) {
      wetted_wall_particles(particles, neighbours_, gradient_radius_.re, wetted_);
      add_surface_pressure_loads(particles, wetted_, surface_, obstacle_rotations(scene_, surface_, particles),
                                 scene_.physics.density, scene_.physics.gravity, 0.5 * scene_.particle_spacing,
                                 reaction_);
      return;
    }
    const bool cmps = gradient_scheme_ == PressureGradientScheme::Cmps;
    const std::vector<Eigen::Matrix2d>* correction = gradient_correction_ ? &correction_ : nullptr;
    if (!cmps) {
      neighbourhood_minimum(particles, neighbours_, samples_, gradient_radius_, carries_pressure_,
                            scene_.physics.density, scene_.physics.gravity, min_includes_self_, minimum_pressure_,
                            dry_);
    }
    if (computes_sample_loads_) {
      add_pressure_sample_reactions(particles, samples_, gradient_radius_, minimum_pressure_, cmps,
                                    scene_.physics.density, scene_.physics.gravity, particle_mass_, sample_scratch_,
                                    sample_loads_, correction, dry_);
      return;
    }
    add_pressure_wall_reactions(particles, neighbours_, gradient_radius_, carries_pressure_, minimum_pressure_, cmps,
                                scene_.physics.density, particle_mass_, reaction_, correction, dry_);
  }

  // The step's report: solver statistics, and the compressibility left for the solver.
  StepReport step_report(const ParticleSet& particles, const PressureSolveResult& solve,
                         const WallContext& context) const {
    const std::size_t n = particles.size();
    const auto& n_star = particles.field("number_density");
    // Compressibility left for the solver: mean |n* - n0| / n0 over interior fluid.
    double deviation = 0.0;
    std::size_t interior = 0;
    const auto& surface = particles.field("free_surface");
    for (std::size_t i = 0; i < n; ++i) {
      if (particles.type[i] != ParticleType::Fluid || surface[i] != 0.0) continue;
      deviation += std::fabs(n_star[i] - density_radius_.n0) / density_radius_.n0;
      ++interior;
    }
    StepReport report;
    report.speed_limited_particles = context.speed_limited;
    report.solver_iterations = solve.iterations;
    report.solver_residual = solve.residual;
    report.solver_converged = solve.converged;
    if (!solve.converged) {
      report.solver_note = "CG residual " + format_double(solve.residual) + " > cg_tolerance " +
                           format_double(settings_.tolerance) + " after " + std::to_string(solve.iterations) +
                           " iterations";
    }
    report.extra = {interior > 0 ? deviation / static_cast<double>(interior) : 0.0, static_cast<double>(solve.surface),
                    static_cast<double>(solve.unknowns), static_cast<double>(solve.ungrounded_groups)};
    return report;
  }

  // Neighbours within the largest radius, then the boundary model's wall samples there.
  void search(const ParticleSet& particles, WallContext& context) {
    const auto timed = measure(timers_, search_phase_);
    cells_.build(particles.position, particles.type, search_radius_);
    cells_.find_neighbours(particles.position, particles.type, search_radius_, neighbours_);
    context.support = search_radius_;
  }

  void search_with_samples(const ParticleSet& particles, WallContext& context) {
    search(particles, context);
    walls_.build_wall_samples(context, samples_);  // timed as "wall_treatment"
  }

  const Scene& scene_;
  WallTreatmentSet walls_;
  PhaseTimers* timers_;  // core/run/profile.hpp; null outside a run
  PhaseTimers::Id search_phase_, operators_phase_, assembly_phase_, solve_phase_, integration_phase_;
  OperatorRadius density_radius_, gradient_radius_, laplacian_radius_;
  double search_radius_ = 0.0;
  int pressure_wall_layers_ = 1;
  bool min_includes_self_ = true;
  PressureSolveSettings settings_;
  PressureGradientScheme gradient_scheme_ = PressureGradientScheme::Spec;
  SourceTermScheme source_scheme_ = SourceTermScheme::Spec;
  double mixed_relaxation_ = kDefaultMixedRelaxation;
  std::vector<double> scheme_rate_;          // Dn/Dt or <div u*> of the source term, 1/s
  std::vector<double> scheme_source_;        // b_i of the source term, Pa/m^2
  std::vector<double> minimum_pressure_;     // Phat of CMPS, Pa
  bool gradient_correction_ = false;         // GC (mps_schemes.hpp)
  DryWallRule dry_;                          // dry_wall_points (core/walls/wall_samples.hpp)
  std::vector<Eigen::Matrix2d> correction_;  // C_i of GC, per particle
  nlohmann::json scheme_names_;              // for run.json
  std::string preconditioner_choice_;        // the parameter: "auto" or a preconditioner
  std::size_t amg_min_fluid_particles_ = kDefaultAmgMinFluidParticles;
  std::vector<char> carries_pressure_;
  std::vector<Vec2> acceleration_;  // m/s^2
  bool computes_reactions_ = false;
  bool surface_loads_ = true;         // obstacle_load wall_pressure with wall particles
  bool fluid_pressure_load_ = false;  // the driver's integral of the fluid's pressure (FluidPressure)
  std::vector<char> wetted_;          // wall particles with a fluid neighbour within re (wall_pressure loads)
  ObstacleSurface surface_;           // the obstacles' surface wall particles (wall_pressure)
  double particle_mass_ = 0.0;        // rho l0^2, kg/m
  std::vector<Vec2> reaction_;        // the fluid's force on each wall particle in this step, N/m
  bool computes_sample_loads_ = false;
  WallSampleLoads sample_loads_;      // the fluid's force on each obstacle's wall samples in this step
  std::vector<Vec2> sample_scratch_;  // per sample, N/m (core/walls/wall_sample_reactions.hpp)
  CellList cells_;
  NeighbourList neighbours_;
  WallSampleList samples_;  // of the boundary model, at the positions of the last search
  PressurePoissonSolver ppe_;
  long long total_iterations_ = 0;
  TimeStepSettings time_step_settings_;  // core/run/time_step.hpp
  TimeStepClock clock_;                  // simulated time, steps taken and the last step (CFL rule)
  std::size_t ghosts_ = 0;
  std::size_t ungrounded_groups_ = 0;
  long long nonconverged_solves_ = 0;
};

}  // namespace
// The pressure schemes' parameters (mps_schemes.hpp, "Pressure schemes" of docs/methods/mps.md)
// and the dry-wall rule (DryWallRule, core/walls/wall_samples.hpp), in the order `mps_lab methods -p` lists them.
std::vector<ParameterSpec> pressure_scheme_parameters() {
  return {
      string_parameter("pressure_gradient", "spec",
                       "pressure gradient: spec (§2, P_j - P_min) or cmps (Khayyer & Gotoh 2008, antisymmetric)")
          .one_of(mps::pressure_gradient_choices()),
      boolean_parameter("gradient_correction", false,
                        "multiply the pressure gradient by the corrective matrix C_i (GC, Khayyer & Gotoh 2011): "
                        "exact for a linear pressure at any arrangement (methods/mps/mps_schemes.hpp)"),
      string_parameter("dry_wall_points", "extended",
                       "a wall point above a fluid particle with pressure <= 0 (above the water; a wall particle also "
                       "less than free_surface_offset below it): extended (enters "
                       "P_min and the gradient as it is: a wall sample with its hydrostatic extension, negative there) "
                       "or excluded (left out: air; core/walls/wall_samples.hpp)")
          .one_of({"extended", "excluded"}),
      string_parameter("source_term", "spec",
                       "PPE source: spec (§8, relaxation (n* - n0)/n0), hs (Khayyer & Gotoh 2009, Dn/Dt), ecs "
                       "(Khayyer & Gotoh 2011, hs + error compensation) or mixed (Tanaka & Masunaga 2010)")
          .one_of(mps::source_term_choices()),
      number_parameter("mixed_relaxation", mps::kDefaultMixedRelaxation, "",
                       "gamma of source_term mixed: weight of (n* - n0)/n0 beside div u* (Tanaka & Masunaga 2010)")
          .above(0.0)
          .at_most(1.0),
      string_parameter("ppe_laplacian", "spec",
                       "Laplacian of the PPE matrix: spec (§2, 2d/(n0 lambda) w) or hl (Khayyer & Gotoh 2010, "
                       "re/(n0 r^3))")
          .one_of(mps::ppe_laplacian_choices()),
  };
}

// For wall loads: the mixed source of Tanaka & Masunaga (2010), whose still water stays still
// (the spec's source has no settled level there: its half-second means wander by 5 %); the wall
// above the water left out of P_min and the gradient (dry_wall_points excluded: a wall sample's
// negative hydrostatic extension there lowered P_min at the contact line); the gradient
// correction with the water surface half a spacing beyond the surface particles (gc and
// free_surface_offset 0.5: GC alone reads the pressure's zero on the surface particles' centres,
// -rho g l0/2; docs/methods/mps.md, "The water surface"; with the offset the spec's wall particles
// at the water line hold the same water's head, "The water line on the wall"); and the spec's
// collision (6.4) from 0.9 l0 instead of 0.5 l0 (a default of the particle_collision treatment's
// block, which a --set naming the boundary model keeps: with 0.5 l0 the spec's dam break stopped
// with every boundary model but the spec walls, and the still water's kinetic energy at 3 s
// was five times larger; docs/methods/mps.md, "The collision distance"). Still water: 0.988-1.022 of rho g h
// over [0.5, 3] s in 24 realisations (gravity x (1 + k 1e-10), 2026-11-29, seventeenth sitting;
// 0.968-1.017 with the spec's collision distance, 0.934-1.019 before GC and the offset), one run
// at 1.5 g 0.991-1.016, so 3 % (docs/validation.md, "Each method's load setting", "Expected
// readings"). The promise is for the tank's spacing (docs/validation.md, "Against the particle
// spacing").
LoadSetting load_setting() {
  return {{{"source_term", "\"mixed\""},
           {"dry_wall_points", "\"excluded\""},
           {"gradient_correction", "true"},
           {"free_surface_offset", "0.5"}},
          0.03,
          "measured within 2.2 % (0.988-1.022) with every boundary model in 24 realisations of the still water "
          "at the tank's l0 = 0.025 m (1.5 g: 0.991-1.016 in one run); means over [0.5, 3] s, docs/validation.md",
          {{"wall_treatments.particle_collision.distance", "0.9"}}};
}

}  // namespace mps_lab::mps

void mps_lab_register_method_mps(mps_lab::MethodRegistry& registry) {
  using namespace mps_lab;
  MethodInfo info;
  info.name = "mps";
  info.description = "semi-implicit MPS of the specification (Koshizuka & Oka 1996): number-density PPE by CG";
  info.parameters = {
      number_parameter("re_number_density", 2.1, "l0", "radius of influence of the number density (spec §3)")
          .above(1.0)
          .at_most(4.0),
      number_parameter("re_gradient", 2.1, "l0", "radius of influence of the pressure gradient (spec §3)")
          .above(1.0)
          .at_most(4.0),
      number_parameter("re_laplacian", 2.1, "l0",
                       "radius of influence of the Laplacian, viscosity and PPE (spec: 2.1; K&O 1996: 4.0)")
          .above(1.0)
          .at_most(4.0),
      number_parameter("r_min", 0.01, "l0", "R_MIN: smaller distances are clamped in the weight (spec §2)")
          .above(0.0)
          .below(1.0),
      number_parameter("free_surface_threshold", 0.97, "", "beta: n*/n0 < beta marks a free-surface particle (spec §3)")
          .above(0.0)
          .below(1.0),
      number_parameter("free_surface_offset", 0.0, "l0",
                       "the water surface's distance beyond a free-surface particle's centre: a fluid surface "
                       "particle with water below it holds the head rho |g| offset instead of the spec's P = 0, a "
                       "wall particle on the surface the head of that surface at its height, and with "
                       "dry_wall_points excluded a wall particle at P <= 0 less than offset below is dry "
                       "(§3; 0: the spec's; docs/methods/mps.md, \"The water surface\")")
          .at_least(0.0)
          .below(1.0),
      number_parameter("relaxation", 0.2, "",
                       "pressure relaxation coefficient on the PPE source (spec §3); source_term spec only")
          .above(0.0)
          .at_most(1.0),
  };
  for (ParameterSpec& spec : mps::pressure_scheme_parameters()) info.parameters.push_back(std::move(spec));
  for (ParameterSpec& spec : std::vector<ParameterSpec>{
           integer_parameter("cg_max_iterations", 10000, "conjugate-gradient iteration cap (spec §3)").at_least(1),
           number_parameter("cg_tolerance", 1.0e-8, "",
                            "CG stops at ||b - A p|| / ||b|| below this (spec §3, read as relative)")
               .above(0.0)
               .below(1.0),
           boolean_parameter("warm_start", true, "start CG from the previous step's pressure"),
           boolean_parameter("min_pressure_includes_self", true,
                             "P_min of the gradient includes particle i (K&O 1996)"),
           boolean_parameter("clamp_negative_pressure", true, "set P < 0 to 0 after the solve (spec §5.2-7)"),
           string_parameter("obstacle_load", "fluid_pressure",
                            "the fluid's load on obstacles: wall_pressure (the surface wall particles' pressure times "
                            "their normal and surface, methods/mps/mps_loads.hpp; with wall samples the fluid's "
                            "pressure), pair_reaction (minus the wall pair terms of spec §2) or fluid_pressure (the "
                            "fluid's pressure carried to the surface, core/walls/surface_pressure_loads.hpp); drives "
                            "bodies only, the fluid's dynamics are the same")
               .one_of({"wall_pressure", "pair_reaction", "fluid_pressure"}),
       })
    info.parameters.push_back(std::move(spec));

  for (ParameterSpec& spec : projection_solver_parameters("CG", "IC(0)")) info.parameters.push_back(std::move(spec));
  for (ParameterSpec& spec : time_step_parameters({"fixed", mps::kDefaultCflNumber, 1.0e-6, 5.0e-4,
                                                   "0.16: below the spec clamp's 0.2, docs/methods/mps.md",
                                                   "max: the spec's dt, §3; docs/methods/mps.md, \"Time step\""}))
    info.parameters.push_back(std::move(spec));
  info.fields = {{"number_density", "", "n* at the provisional positions (spec §5.2-4)", true},
                 {"free_surface", "", "1 where n*/n0 < free_surface_threshold (P = 0)", true}};
  info.series_columns = {"number_density_error", "free_surface_particles", "ppe_unknowns", "ungrounded_groups"};
  info.default_wall_treatments = {"spec_wall_particles", "cfl_velocity_clamp", "wall_repulsion", "wall_position_clamp",
                                  "particle_collision"};
  info.wall_samples = true;
  info.wall_particle_models = {WallParticlePressure::SolvedInPpe};  // spec_wall_particles
  info.moving_walls = true;  // wall velocity in the viscous term and the wall pressure (docs/walls.md, "Moving walls")
  info.obstacle_loads = true;  // obstacle_load: the wall pressure over the surface, or the spec §2 wall pairs' reaction
  info.sample_obstacle_loads = true;  // ... with wall samples too (the surface pressure: the driver's)
  info.load_setting = mps::load_setting();
  info.wall_hooks = mps::kWallHooks;
  info.create = [](const MethodSetup& setup) { return std::make_unique<mps::MpsMethod>(setup); };
  registry.add(std::move(info));
}
