// Weakly compressible SPH with delta-SPH density diffusion (Antuono et al. 2010; Marrone et al.
// 2011): the density of every fluid particle is integrated by the continuity equation with the
// delta-term, the pressure follows from it by the Tait equation of state, and no linear system is
// solved. One step of the kick-drift-kick (velocity Verlet) integrator, one evaluation of the
// derivatives per step (a^n and D rho^n are kept from the previous step):
//   kick:   u^{n+1/2} = u^n + dt/2 a^n;  rho^{n+1/2} = rho^n + dt/2 D rho^n;  [after_explicit_velocity]
//   drift:  x^{n+1} = x^n + dt u^{n+1/2};  walls fixed;                           [after_explicit_position]
//   search: neighbours at x^{n+1} (and the wall samples);                          [after_neighbour_search]
//   derivatives at x^{n+1} with the predicted u~ = u^{n+1/2} + dt/2 a^n, rho~ = rho^{n+1/2} + dt/2 D rho^n:
//           p~ = Tait(rho~), Adami wall pressures, <grad rho>^L, D rho^{n+1}, a^{n+1};
//   kick:   u^{n+1} = u^{n+1/2} + dt/2 a^{n+1};  rho^{n+1} = rho^{n+1/2} + dt/2 D rho^{n+1};
//           p^{n+1} = Tait(rho^{n+1}) and the wall pressures from it;             [after_correction]
//           escaped particles -> ghosts.
// Bracketed: the wall-treatment hooks (core/walls/); none is on by default. The time step is
// adaptive (time_step()): the acoustic CFL limit with c0, the viscous and the force limits.
// docs/methods/wcsph.md gives the equations, the decisions and the measurements behind every
// default.
#include <algorithm>
#include <cmath>
#include <memory>

#include "core/base/error.hpp"
#include "core/io/checkpoint.hpp"
#include "core/io/geometry.hpp"
#include "core/io/scene.hpp"
#include "core/run/method.hpp"
#include "core/run/time_step.hpp"
#include "core/search/cell_order.hpp"
#include "core/search/for_each_neighbour.hpp"
#include "methods/wcsph/wcsph_operators.hpp"

namespace mps_lab::wcsph {
namespace {

// The wall hooks the step calls (MethodInfo::wall_hooks): after each kick, after the drift and
// after the search.
constexpr WallHooks kWallHooks = WallHooks::all();

// eta^2 = (0.1 h)^2 of the viscous denominators (Monaghan 1992).
constexpr double kEtaOverSmoothingLength = 0.1;

// The largest speed the scene's flow can reach, m/s: sqrt(2 |g| H) (a column of height H falling
// freely; Ritter's dam-break front moves at 2 sqrt(g H) <= this x 1.42, which the factor 10 of
// c0 covers) plus the largest initial speed of a fluid block. H: from the lowest bottom to the
// highest top of the scene's fluid blocks.
struct ExpectedSpeed {
  double height = 0.0;  // H, m
  double speed = 0.0;   // m/s
};
ExpectedSpeed expected_speed(const Scene& scene) {
  if (scene.fluid_blocks.empty()) return {};
  double bottom = scene.fluid_blocks.front().region.min.y(), top = scene.fluid_blocks.front().region.max.y();
  double initial = 0.0;
  for (const FluidBlock& block : scene.fluid_blocks) {
    bottom = std::min(bottom, block.region.min.y());
    top = std::max(top, block.region.max.y());
    initial = std::max(initial, block.velocity.norm());
  }
  const double height = top - bottom;
  return {height, std::sqrt(2.0 * scene.physics.gravity.norm() * height) + initial};
}

class WcsphMethod final : public Method {
 public:
  explicit WcsphMethod(const MethodSetup& setup)
      : scene_(setup.scene),
        walls_(setup.wall_treatments, setup.scene, setup.timers, kWallHooks),
        timers_(setup.timers),
        search_phase_(phase_id(timers_, "neighbour_search")),
        operators_phase_(phase_id(timers_, "operators")),
        integration_phase_(phase_id(timers_, "integration")),
        kernel_(sph_kernel_from_name(setup.parameters.string("kernel")),
                2.0 * setup.parameters.number("smoothing_length") * setup.scene.particle_spacing) {
    const auto& p = setup.parameters;
    const double l0 = scene_.particle_spacing;
    smoothing_length_ = kernel_.support() / 2.0;
    expected_ = expected_speed(scene_);
    sound_speed_factor_ = p.number("sound_speed_factor");
    const double explicit_sound_speed = p.number("sound_speed");
    eos_.rest_density = scene_.physics.density;
    eos_.sound_speed = explicit_sound_speed > 0.0 ? explicit_sound_speed : sound_speed_factor_ * expected_.speed;
    sound_speed_source_ = explicit_sound_speed > 0.0 ? "sound_speed" : "sound_speed_factor x sqrt(2 g H)";
    if (!(eos_.sound_speed > 0.0)) {
      throw InputError(scene_.source +
                       ": methods.wcsph.sound_speed: got 0 with no fluid or no gravity to derive "
                       "it from, expected a speed of sound > 0 m/s");
    }
    mass_ = eos_.rest_density * l0 * l0;
    // Loads on obstacles (MethodInfo::obstacle_loads): the reaction on wall particles, when there are both.
    computes_reactions_ = !scene_.walls.obstacles.empty() && walls_.wall_particles();
    // ... and on each obstacle's wall samples (MethodInfo::sample_obstacle_loads).
    computes_sample_loads_ = !scene_.walls.obstacles.empty() && !walls_.wall_particles();
    diffusion_ = density_diffusion_from_name(p.string("density_diffusion"));
    delta_ = p.number("delta");
    viscosity_.model = p.string("viscosity") == "laminar" ? Viscosity::Laminar : Viscosity::Artificial;
    alpha_ = p.number("artificial_viscosity");
    viscosity_.alpha_h_c0 = alpha_ * smoothing_length_ * eos_.sound_speed;
    viscosity_.kinematic_viscosity = scene_.physics.kinematic_viscosity;
    viscosity_.eta2 = std::pow(kEtaOverSmoothingLength * smoothing_length_, 2);
    clamp_wall_pressure_ = p.boolean("clamp_negative_wall_pressure");
    time_step_settings_ = time_step_settings(p, scene_.time.time_step, scene_.source);
  }

  void initialise(ParticleSet& particles) override {
    const std::size_t n = particles.size();
    acceleration_.assign(n, Vec2::Zero());
    density_rate_.assign(n, 0.0);
    predicted_velocity_.assign(n, Vec2::Zero());
    predicted_density_.assign(n, eos_.rest_density);
    hydrostatic_start(particles);
    WallContext context{particles, &neighbours_, 0.0, scene_};
    search(particles, context);
    predicted_velocity_ = particles.velocity;
    predicted_density_ = particles.field("density");
    evaluate(particles);
    auto& density = particles.field("density");
    for (std::size_t i = 0; i < n; ++i) {
      if (particles.type[i] == ParticleType::Wall) density[i] = predicted_density_[i];  // Adami's rho_w
    }
    clock_.start(time_step_settings_.max_time_step);
  }

  // "fixed": the scene's step. "cfl": the smallest of the acoustic, viscous and force limits
  // (wcsph_operators.hpp), from the fluid's largest speed now and the accelerations of the last
  // evaluation (those the coming step's first kick applies), clamped to [min, max]_time_step.
  double time_step(const ParticleSet& particles) const override {
    if (!time_step_settings_.cfl) return scene_.time.time_step;
    const double limit = stable_time_step(particles);
    // TimeStepClock::next gives cfl_number l0 / speed, clamped and evened out at the end: the speed
    // for which that is `limit`.
    const double speed = time_step_settings_.cfl_number * scene_.particle_spacing / limit;
    return clock_.next(time_step_settings_, speed, scene_.particle_spacing, scene_.time.end_time);
  }

  StepReport step(ParticleSet& particles, double dt) override {
    WallContext context{particles, &neighbours_, dt, scene_};
    context.samples = &samples_;
    context.support = kernel_.support();
    kick_and_drift(particles, dt, context);
    search(particles, context);  // and the wall samples at x^{n+1}
    walls_.after_neighbour_search(context);
    predict(particles, dt);
    evaluate(particles);
    final_kick(particles, dt, context);
    clock_.advance(dt);
    StepReport result = report(particles);
    result.speed_limited_particles = context.speed_limited;
    return result;
  }

  nlohmann::json summary() const override {
    const double l0 = scene_.particle_spacing;
    return {{"kernel", kernel_.kind() == SphKernelKind::CubicSpline ? "cubic_spline" : "wendland_c2"},
            {"support_over_l0", kernel_.support() / l0},
            {"particle_mass", mass_},
            {"fluid_height_H", expected_.height},
            {"expected_speed_sqrt_2gH", expected_.speed},
            {"sound_speed", eos_.sound_speed},
            {"sound_speed_from", sound_speed_source_},
            {"tait_stiffness_B", eos_.stiffness()},
            {"density_diffusion", diffusion_name()},
            {"delta", delta_},
            {"viscosity", viscosity_.model == Viscosity::Artificial ? "artificial" : "laminar"},
            {"artificial_viscosity_alpha", alpha_},
            {"wall_treatments", walls_.names()},
            {"boundary_model", walls_.boundary_name()},
            {"time_step", clock_.summary(time_step_settings_)},
            {"largest_density_deviation", largest_deviation_},
            {"ghosts_created", ghosts_}};
  }

  // State between steps: a^n and D rho^n of the last evaluation (the next step's first kick), the
  // neighbour list and wall samples of the last search (the hooks before the next search see
  // them), the clock and the totals. The density is the ParticleSet's "density" field.
  void save_state(CheckpointWriter& out) const override {
    out.write_vec2s(acceleration_);
    out.write_doubles(density_rate_);
    write_neighbour_list(out, neighbours_);
    write_wall_samples(out, samples_);
    out.write_double(largest_deviation_);
    out.write_size(ghosts_);
    clock_.save(out);
  }

  void restore_state(CheckpointReader& in) override {
    const std::size_t n = acceleration_.size();
    acceleration_ = in.read_vec2s();
    density_rate_ = in.read_doubles();
    read_neighbour_list(in, neighbours_);
    read_wall_samples(in, samples_);
    largest_deviation_ = in.read_double();
    ghosts_ = in.read_size();
    clock_.restore(in);
    if (acceleration_.size() != n || density_rate_.size() != n || neighbours_.particle_count() != n) {
      in.fail("wcsph state for " + std::to_string(acceleration_.size()) + " particles, the scene has " +
              std::to_string(n));
    }
    if (samples_.has_samples() != !walls_.wall_particles() ||
        (samples_.has_samples() && samples_.offsets.size() != n + 1)) {
      in.fail("wcsph wall samples that do not fit the boundary model " + walls_.boundary_name());
    }
  }

  // Loads on obstacles (core/walls/obstacle_loads.hpp): the fluid's force on each wall particle
  // in the last step, N/m; null without obstacles or without wall particles (Method::wall_reactions).
  const std::vector<Vec2>* wall_reactions() const override { return computes_reactions_ ? &reaction_ : nullptr; }
  // The same on each obstacle's wall samples (core/walls/wall_sample_reactions.hpp).
  const WallSampleLoads* wall_sample_loads() const override {
    return computes_sample_loads_ ? &sample_loads_ : nullptr;
  }

  // Cell-ordered particles (core/search/cell_order.hpp): what save_state keeps per particle.
  void permute_state(const ParticleOrder& order) override {
    permute_values(acceleration_, order);
    permute_values(density_rate_, order);
    permute_neighbour_list(neighbours_, order);
    permute_wall_samples(samples_, order);
    walls_.permute_state(order);
  }

 private:
  double stable_time_step(const ParticleSet& particles) const {
    double max_speed2 = 0.0, max_acceleration2 = 0.0;
    for (std::size_t i = 0; i < particles.size(); ++i) {
      if (particles.type[i] != ParticleType::Fluid) continue;
      max_speed2 = std::max(max_speed2, particles.velocity[i].squaredNorm());
      max_acceleration2 = std::max(max_acceleration2, acceleration_[i].squaredNorm());
    }
    const double h = smoothing_length_;
    // The artificial viscosity acts as nu = alpha h c0 / 8 in 2-D (Monaghan 2005).
    const double nu =
        viscosity_.model == Viscosity::Artificial ? viscosity_.alpha_h_c0 / 8.0 : viscosity_.kinematic_viscosity;
    return std::min({acoustic_time_step(time_step_settings_.cfl_number, scene_.particle_spacing, eos_.sound_speed,
                                        std::sqrt(max_speed2)),
                     viscous_time_step(h, nu), force_time_step(h, std::sqrt(max_acceleration2))});
  }

  // p = rho0 |g| (y_s - y) below the surface y_s of the particle's fluid block (its highest
  // particle centre + l0/2; core/io/geometry.hpp), rho by the inverse Tait equation: still water
  // starts in the equilibrium of its equation of state. Walls get Adami's pressure at the first
  // evaluation.
  void hydrostatic_start(ParticleSet& particles) const {
    auto& density = particles.field("density");
    particles.pressure = hydrostatic_block_pressure(scene_, particles, 0.5 * scene_.particle_spacing);
    for (std::size_t i = 0; i < particles.size(); ++i) {
      density[i] = particles.type[i] == ParticleType::Fluid ? eos_.density(particles.pressure[i]) : eos_.rest_density;
    }
  }

  // The first kick and the drift, with the wall hooks after each.
  void kick_and_drift(ParticleSet& particles, double dt, WallContext& context) {
    auto& density = particles.field("density");
    {
      const auto timed = measure(timers_, integration_phase_);
      for_each_fluid_particle(particles, [&](std::ptrdiff_t i) {
        particles.velocity[i] += 0.5 * dt * acceleration_[i];  // u^{n+1/2}
        density[i] += 0.5 * dt * density_rate_[i];             // rho^{n+1/2}
      });
    }
    walls_.after_explicit_velocity(context);
    {
      const auto timed = measure(timers_, integration_phase_);
      for_each_fluid_particle(particles,
                              [&](std::ptrdiff_t i) { particles.position[i] += dt * particles.velocity[i]; });
      hold_walls_at_prescribed_velocity(particles);
    }
    walls_.after_explicit_position(context);
  }

  // The state the derivatives are evaluated at: u~ = u^{n+1/2} + dt/2 a^n, rho~ = rho^{n+1/2} +
  // dt/2 D rho^n for fluid; walls keep u = 0 (their rho is set by the evaluation).
  void predict(const ParticleSet& particles, double dt) {
    const auto& density = particles.field("density");
    const auto count = static_cast<std::ptrdiff_t>(particles.size());
    const auto timed = measure(timers_, integration_phase_);
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < count; ++i) {
      const bool fluid = particles.type[i] == ParticleType::Fluid;
      predicted_velocity_[i] = fluid ? Vec2(particles.velocity[i] + 0.5 * dt * acceleration_[i]) : Vec2::Zero();
      predicted_density_[i] = fluid ? density[i] + 0.5 * dt * density_rate_[i] : eos_.rest_density;
    }
  }

  // p~ = Tait(rho~) for fluid, the wall pressures, then D rho and a at the predicted state.
  void evaluate(ParticleSet& particles) {
    const auto timed = measure(timers_, operators_phase_);
    const auto count = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < count; ++i) {
      particles.pressure[i] = particles.type[i] == ParticleType::Fluid ? eos_.pressure(predicted_density_[i]) : 0.0;
    }
    adami_wall_pressure(particles, neighbours_, kernel_, eos_, scene_.physics.gravity, clamp_wall_pressure_,
                        particles.pressure, predicted_density_);
    const FluidState state{
        particles,           neighbours_,         samples_,           kernel_, mass_,
        predicted_density_,  predicted_velocity_, particles.pressure, eos_,    scene_.physics.gravity,
        clamp_wall_pressure_};
    if (diffusion_ == DensityDiffusion::Antuono) renormalised_density_gradient(state, density_gradient_);
    continuity(state, density_rate_);
    density_diffusion(state, diffusion_, delta_ * smoothing_length_ * eos_.sound_speed, density_gradient_,
                      diffusion_rate_);
#pragma omp parallel for schedule(static)
    for (std::ptrdiff_t i = 0; i < count; ++i) density_rate_[i] += diffusion_rate_[i];
    momentum(state, viscosity_, acceleration_);
    if (computes_reactions_) {  // the reaction of its wall pairs at the same state
      reaction_.assign(particles.size(), Vec2::Zero());
      add_momentum_wall_reactions(state, viscosity_, reaction_);
    }
    if (computes_sample_loads_) {  // the same on the wall samples
      sample_loads_.reset(scene_.walls.obstacles.size());
      add_momentum_sample_reactions(state, viscosity_, sample_scratch_, sample_loads_);
    }
  }

  // The second kick, the end-of-step pressures (fluid by Tait, walls by Adami), the hook after
  // the correction and escaped particles to ghosts.
  void final_kick(ParticleSet& particles, double dt, WallContext& context) {
    auto& density = particles.field("density");
    {
      const auto timed = measure(timers_, integration_phase_);
      for_each_fluid_particle(particles, [&](std::ptrdiff_t i) {
        particles.velocity[i] += 0.5 * dt * acceleration_[i];  // u^{n+1}
        density[i] += 0.5 * dt * density_rate_[i];             // rho^{n+1}
        particles.pressure[i] = eos_.pressure(density[i]);     // p^{n+1}
      });
      adami_wall_pressure(particles, neighbours_, kernel_, eos_, scene_.physics.gravity, clamp_wall_pressure_,
                          particles.pressure, density);
    }
    walls_.after_correction(context);
    {
      const auto timed = measure(timers_, integration_phase_);
      ghosts_ += mark_escaped_as_ghosts(particles, scene_);
    }
  }

  // Neighbours within the kernel support, then the boundary model's wall samples within it
  // (none for wall particles), handed to the wall treatments in `context`.
  void search(const ParticleSet& particles, WallContext& context) {
    search_neighbours_and_wall_samples(particles, kernel_.support(), timers_, search_phase_, cells_, neighbours_,
                                       walls_, context, samples_);
  }

  StepReport report(const ParticleSet& particles) {
    const auto& density = particles.field("density");
    double largest = 0.0, mean = 0.0;
    std::size_t fluid = 0;
    for (std::size_t i = 0; i < particles.size(); ++i) {
      if (particles.type[i] != ParticleType::Fluid) continue;
      const double deviation = std::fabs(density[i] / eos_.rest_density - 1.0);
      largest = std::max(largest, deviation);
      mean += deviation;
      ++fluid;
    }
    largest_deviation_ = std::max(largest_deviation_, largest);
    StepReport result;
    result.extra = {fluid > 0 ? mean / static_cast<double>(fluid) : 0.0, largest};
    return result;
  }

  std::string diffusion_name() const {
    switch (diffusion_) {
      case DensityDiffusion::None:
        return "none";
      case DensityDiffusion::MolteniColagrossi:
        return "molteni_colagrossi";
      default:
        return "antuono";
    }
  }

  const Scene& scene_;
  WallTreatmentSet walls_;
  PhaseTimers* timers_;  // core/run/profile.hpp; null outside a run
  PhaseTimers::Id search_phase_, operators_phase_, integration_phase_;
  SphKernel kernel_;
  double smoothing_length_ = 0.0;  // h = support / 2, m
  ExpectedSpeed expected_;
  double sound_speed_factor_ = 10.0;
  std::string sound_speed_source_;
  TaitEquation eos_;
  double mass_ = 0.0;  // kg/m
  DensityDiffusion diffusion_ = DensityDiffusion::Antuono;
  double delta_ = 0.1;
  double alpha_ = 0.02;
  ViscositySettings viscosity_;
  bool clamp_wall_pressure_ = true;
  CellList cells_;
  NeighbourList neighbours_;
  WallSampleList samples_;          // of the boundary model, at the positions of the last search
  std::vector<Vec2> acceleration_;  // a of the last evaluation, m/s^2
  bool computes_reactions_ = false;
  std::vector<Vec2> reaction_;  // the fluid's force on each wall particle at the last evaluation, N/m
  bool computes_sample_loads_ = false;
  WallSampleLoads sample_loads_;           // the fluid's force on each obstacle's wall samples, last evaluation
  std::vector<Vec2> sample_scratch_;       // per sample, N/m (core/walls/wall_sample_reactions.hpp)
  std::vector<double> density_rate_;       // D rho / Dt of the last evaluation, delta-term included, kg/(m^3 s)
  std::vector<double> diffusion_rate_;     // the delta-term alone, kg/(m^3 s)
  std::vector<Vec2> density_gradient_;     // <grad rho>^L, kg/m^4
  std::vector<Vec2> predicted_velocity_;   // u~, m/s (walls 0)
  std::vector<double> predicted_density_;  // rho~ (walls: Adami's rho_w), kg/m^3
  TimeStepSettings time_step_settings_;    // core/run/time_step.hpp
  TimeStepClock clock_;
  double largest_deviation_ = 0.0;  // max |rho/rho0 - 1| over the run
  std::size_t ghosts_ = 0;
};

}  // namespace
}  // namespace mps_lab::wcsph

// The wcsph block of a scene: every key with its default (the papers' values) and range.
static std::vector<mps_lab::ParameterSpec> wcsph_parameters() {
  using namespace mps_lab;
  return {
      string_parameter("kernel", "wendland_c2", "SPH kernel (core/kernels/sph_kernels.hpp)")
          .one_of({"cubic_spline", "wendland_c2"}),
      number_parameter("smoothing_length", 1.5, "l0", "h; the kernel support is 2h (<= 3 l0 = the three wall layers)")
          .at_least(1.0)
          .at_most(1.5),
      number_parameter("sound_speed_factor", 10.0, "",
                       "c0 = this x sqrt(2 |g| H), H the fluid blocks' height (10: density within ~1 %)")
          .above(0.0),
      number_parameter("sound_speed", 0.0, "m/s", "c0 given explicitly; 0: from sound_speed_factor").at_least(0.0),
      string_parameter("density_diffusion", "antuono",
                       "delta-term: antuono (renormalised gradients, Antuono et al. 2010), molteni_colagrossi (2009) "
                       "or none")
          .one_of({"antuono", "molteni_colagrossi", "none"}),
      number_parameter("delta", 0.1, "", "delta of the density diffusion delta h c0 (Marrone et al. 2011: 0.1)")
          .at_least(0.0)
          .at_most(1.0),
      string_parameter("viscosity", "artificial",
                       "artificial (Monaghan 1992, alpha) or laminar (Morris et al. 1997, the scene's "
                       "physics.kinematic_viscosity)")
          .one_of({"artificial", "laminar"}),
      number_parameter("artificial_viscosity", 0.02, "", "alpha of the artificial viscosity alpha h c0")
          .at_least(0.0)
          .at_most(1.0),
      boolean_parameter("clamp_negative_wall_pressure", true,
                        "set a negative Adami wall pressure (and wall sample pressure) to 0: a wall never pulls"),
  };
}

void mps_lab_register_method_wcsph(mps_lab::MethodRegistry& registry) {
  using namespace mps_lab;
  MethodInfo info;
  info.name = "wcsph";
  info.description =
      "weakly compressible SPH, delta-SPH density diffusion (Antuono et al. 2010; Marrone et al. 2011), Tait "
      "equation of state, kick-drift-kick, Adami walls: explicit, no linear solve";
  info.parameters = wcsph_parameters();
  info.fields = {
      {"density", "kg/m^3", "density by the continuity equation with the delta-term (walls: Adami's)", true}};
  info.series_columns = {"mean_density_deviation", "max_density_deviation"};
  info.default_wall_treatments = {"adami_wall_particles"};
  // Continuity and momentum also sum over wall samples (the delta-term and the density gradient
  // sum over fluid alone with every boundary model): dummy_layers, mirror_particles, distance_function.
  info.wall_samples = true;
  info.wall_particle_models = {WallParticlePressure::AdamiExtrapolated};  // adami_wall_particles
  info.obstacle_loads = true;         // the reaction of its momentum pairs with wall particles (docs/walls.md)
  info.sample_obstacle_loads = true;  // ... and with wall samples
  // For wall loads: a sound speed of 20 U instead of 10 U (twice the steps); still water then
  // reads within 0.7 % where 10 U reads up to 1.6 % high (docs/validation.md).
  // (sound_speed 0: c0 from the factor, also where a scene gives c0 itself.)
  info.load_setting = {{{"sound_speed_factor", "20"}, {"sound_speed", "0"}},
                       0.01,
                       "measured within 0.7 % (0.999-1.007) with every boundary model over [0.5, 3] s, "
                       "the same in each of 24 realisations, docs/validation.md"};
  info.wall_hooks = wcsph::kWallHooks;
  const auto time_step_specs = time_step_parameters(
      {"cfl", 0.25, 1.0e-7, 1.0e-3, "0.25: a factor 3 below the largest stable 0.8 (docs/methods/wcsph.md)",
       "1e-3 s: never reached with c0 >= 10 sqrt(2 g H)"});
  info.parameters.insert(info.parameters.end(), time_step_specs.begin(), time_step_specs.end());
  info.create = [](const MethodSetup& setup) { return std::make_unique<wcsph::WcsphMethod>(setup); };
  registry.add(std::move(info));
}
