#include "core/run/stability.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/base/parallel.hpp"
#include "core/bodies/rigid_bodies.hpp"
#include "core/io/scene.hpp"
#include "core/run/diagnostics.hpp"
#include "core/run/method.hpp"
#include "core/walls/wall_geometry.hpp"

namespace mps_lab {

namespace {

enum EventKind : std::size_t {
  kNonFinite,
  kCourant,
  kSpeedLimited,
  kEnergyGrowth,
  kDensity,
  kPenetration,
  kEscaped,
  kSolver
};

std::string format(const char* pattern, double a, double b = 0.0, double c = 0.0) {
  char buffer[256];
  std::snprintf(buffer, sizeof buffer, pattern, a, b, c);
  return buffer;
}

}  // namespace

const std::vector<std::string>& stability_event_kinds() {
  static const std::vector<std::string> kinds = {"non_finite", "courant",     "speed_limited", "energy_growth",
                                                 "density",    "penetration", "escaped",       "solver"};  // immutable
  return kinds;
}

std::vector<ParameterSpec> stability_keys() {
  return {
      string_parameter("on_divergence", "stop",
                       "\"stop\": a divergence ends the run with status diverged; \"continue\": record it and go on "
                       "(a non-finite state always stops)")
          .one_of({"stop", "continue"}),
      string_parameter("on_solver_failure", "continue",
                       "\"stop\": a solver at its iteration cap above its tolerance ends the run with status "
                       "solver_failed; \"continue\": record it and go on")
          .one_of({"stop", "continue"}),
      number_parameter("courant_limit", 1.0, "-", "divergence when max |u| dt / l0 over the fluid exceeds this")
          .above(0.0),
      number_parameter("max_speed_limited_fraction", 0.05, "-",
                       "divergence when a wall treatment (the CFL velocity clamp) caps the speed of more than this "
                       "fraction of the fluid in one step: the cap, not the equations, then sets the flow")
          .at_least(0.0)
          .at_most(1.0),
      number_parameter("energy_growth_limit", 0.5, "-",
                       "divergence when the mechanical energy exceeds its initial value by this times E_scale")
          .above(0.0),
      number_parameter("density_error_limit", 0.2, "-",
                       "divergence when the common density error (mean |rho/rho_lattice - 1|) exceeds this")
          .above(0.0),
      integer_parameter("density_check_every_steps", 50, "steps between density checks (it costs a neighbour search)")
          .at_least(1),
      integer_parameter("max_wall_penetrations", 0,
                        "divergence when more fluid particles than this are beyond a wall's first particle line "
                        "(inside the wall or through it)")
          .at_least(0),
      number_parameter("max_escaped_fraction", 0.05, "-",
                       "divergence when more than this fraction of the fluid has left the domain through an open side")
          .at_least(0.0)
          .at_most(1.0),
      integer_parameter("logged_events", 100, "events listed in run.json (all are counted)").at_least(0),
  };
}

StabilitySettings stability_settings(const ParameterValues& values) {
  StabilitySettings settings;
  settings.stop_on_divergence = values.string("on_divergence") == "stop";
  settings.stop_on_solver_failure = values.string("on_solver_failure") == "stop";
  settings.courant_limit = values.number("courant_limit");
  settings.max_speed_limited_fraction = values.number("max_speed_limited_fraction");
  settings.energy_growth_limit = values.number("energy_growth_limit");
  settings.density_error_limit = values.number("density_error_limit");
  settings.density_check_every_steps = values.integer("density_check_every_steps");
  settings.max_wall_penetrations = values.integer("max_wall_penetrations");
  settings.max_escaped_fraction = values.number("max_escaped_fraction");
  settings.logged_events = values.integer("logged_events");
  return settings;
}

double mechanical_energy(const ParticleSet& particles, const Scene& scene) {
  const double mass = scene.physics.density * scene.particle_spacing * scene.particle_spacing;  // kg/m
  const Vec2& g = scene.physics.gravity;
  // The corner of the domain with the lowest potential -g.x, so that E >= 0 inside it.
  const Vec2 low(g.x() > 0.0 ? scene.domain.max.x() : scene.domain.min.x(),
                 g.y() > 0.0 ? scene.domain.max.y() : scene.domain.min.y());
  return deterministic_sum(particles.size(), [&](std::size_t i) {
    if (particles.type[i] != ParticleType::Fluid) return 0.0;
    return mass * (0.5 * particles.velocity[i].squaredNorm() - g.dot(particles.position[i] - low));
  });
}

double bodies_mechanical_energy(const RigidBodies& bodies, const Scene& scene) {
  const Vec2& g = scene.physics.gravity;
  const Vec2 low(g.x() > 0.0 ? scene.domain.max.x() : scene.domain.min.x(),
                 g.y() > 0.0 ? scene.domain.max.y() : scene.domain.min.y());  // as mechanical_energy
  double energy = 0.0;
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const MassProperties& mass = bodies.mass(b);
    const BodyState& state = bodies.state(b);
    energy += 0.5 * mass.mass * state.velocity.squaredNorm() +
              0.5 * mass.inertia * state.angular_velocity * state.angular_velocity -
              mass.mass * g.dot(state.position - low);
  }
  return energy;
}

double stability_energy_scale(double initial_energy, double fluid_mass, double particle_spacing, double time_step) {
  const double reference_speed = 0.01 * particle_spacing / time_step;  // m/s
  return initial_energy + 0.5 * fluid_mass * reference_speed * reference_speed;
}

// Past the wall's first particle line: half a spacing beyond the surface (tank sides and
// obstacles, core/walls/wall_geometry.hpp); the same line for every boundary model.
bool StabilityMonitor::beyond_a_wall(const Vec2& x) const {
  return geometry_->depth_inside(x) > geometry_->surface_offset() * (1.0 + 1e-12);
}

StabilityMonitor::StabilityMonitor(const Scene& scene, StabilitySettings settings)
    : scene_(scene),
      geometry_(std::make_shared<const WallGeometry>(scene)),
      settings_(settings),
      density_workspace_(std::make_shared<FlowWorkspace>()) {
  state_.counts.assign(stability_event_kinds().size(), 0);
}

void StabilityMonitor::start(const ParticleSet& particles, double body_energy) {
  state_.initial_fluid = 0;
  state_.ghosts = 0;
  for (const ParticleType type : particles.type) {
    state_.initial_fluid += type == ParticleType::Fluid ? 1 : 0;
    state_.ghosts += type == ParticleType::Ghost ? 1 : 0;
  }
  const double l0 = scene_.particle_spacing;
  const double fluid_mass = scene_.physics.density * l0 * l0 * static_cast<double>(state_.initial_fluid);
  state_.initial_energy = mechanical_energy(particles, scene_) + body_energy;
  state_.last_energy = state_.initial_energy;
  state_.energy_scale = stability_energy_scale(state_.initial_energy, fluid_mass, l0, scene_.time.time_step);
  state_.min_wall_distance = std::numeric_limits<double>::infinity();  // no wall at all: stays infinite
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] != ParticleType::Fluid) continue;
    const double depth = geometry_->depth_inside(particles.position[i]);
    state_.min_wall_distance =
        std::min(state_.min_wall_distance, depth > 0.0 ? -depth : geometry_->distance(particles.position[i]));
  }
}

void StabilityMonitor::record(long long step, double time, std::size_t kind, const std::string& detail) {
  ++state_.events_total;
  ++state_.counts[kind];
  if (static_cast<long long>(state_.log.size()) < settings_.logged_events) {
    state_.log.push_back({step, time, stability_event_kinds()[kind], detail});
  }
}

void StabilityMonitor::stop(const std::string& status, long long step, double time, const std::string& reason) const {
  char prefix[128];
  std::snprintf(prefix, sizeof prefix, "%s at t = %.6g s (step %lld), because ",
                status == "diverged" ? "diverged" : "solver failed", time, step);
  throw RunStopped(status, prefix + reason);
}

// One parallel pass (exact reductions only: max, min, counts; the same result for any
// thread count): finiteness (ghosts too: a NaN position makes a particle a ghost), the
// largest speed, fluid beyond a wall's first particle line, the closest approach to a wall
// and the ghosts.
StabilityMonitor::ParticleScan StabilityMonitor::scan_particles(const ParticleSet& particles) const {
  double max_speed2 = 0.0;
  std::size_t ghosts = 0;
  std::size_t beyond_walls = 0;
  double min_wall_distance = state_.min_wall_distance;
  const auto count = static_cast<std::ptrdiff_t>(particles.size());
  std::ptrdiff_t first_non_finite = count;
  const double beyond_depth = geometry_->surface_offset() * (1.0 + 1e-12);  // as beyond_a_wall()
#pragma omp parallel for schedule(static) reduction(max : max_speed2) reduction(+ : ghosts, beyond_walls) \
    reduction(min : min_wall_distance, first_non_finite)
  for (std::ptrdiff_t i = 0; i < count; ++i) {
    if (particles.type[i] == ParticleType::Wall) continue;
    const Vec2& x = particles.position[i];
    const Vec2& u = particles.velocity[i];
    if (!(std::isfinite(x.x()) && std::isfinite(x.y()) && std::isfinite(u.x()) && std::isfinite(u.y()) &&
          std::isfinite(particles.pressure[i]))) {
      first_non_finite = std::min(first_non_finite, i);
      continue;
    }
    if (particles.type[i] == ParticleType::Ghost) {
      ++ghosts;
      continue;
    }
    max_speed2 = std::max(max_speed2, u.squaredNorm());
    const double depth = geometry_->depth_inside(x);
    beyond_walls += depth > beyond_depth ? 1 : 0;
    min_wall_distance = std::min(min_wall_distance, depth > 0.0 ? -depth : geometry_->distance(x));
  }
  return {max_speed2, ghosts, beyond_walls, min_wall_distance, first_non_finite < count ? first_non_finite : -1};
}

// Energy from nowhere: (E - E0) / E_scale beyond the limit.
void StabilityMonitor::check_energy(const ParticleSet& particles, double body_energy, long long step, double time) {
  const bool stop_divergence = settings_.stop_on_divergence;
  state_.last_energy = mechanical_energy(particles, scene_) + body_energy;
  const double growth = (state_.last_energy - state_.initial_energy) / state_.energy_scale;
  if (growth > settings_.energy_growth_limit) {
    const std::string reason =
        format("the mechanical energy grew from %.4g to %.4g J/m (by %.3g E_scale", state_.initial_energy,
               state_.last_energy, growth) +
        format(", beyond stability.energy_growth_limit = %.3g) with no energy source in the scene",
               settings_.energy_growth_limit);
    record(step, time, kEnergyGrowth, reason);
    if (stop_divergence) stop("diverged", step, time, reason);
  }
}

// New ghosts: through a wall (penetration) or through an open side (escaped). Ghosts keep
// the position at which they left, so the totals only grow.
void StabilityMonitor::check_ghosts(const ParticleSet& particles, std::size_t ghosts, long long step, double time) {
  const bool stop_divergence = settings_.stop_on_divergence;
  if (ghosts > state_.ghosts) {
    std::size_t through_walls = 0;
    for (std::size_t i = 0; i < particles.size(); ++i) {
      const Vec2& x = particles.position[i];
      if (particles.type[i] == ParticleType::Ghost && (beyond_a_wall(x) || geometry_->behind_walled_side(x))) {
        ++through_walls;
      }
    }
    const std::size_t new_through_walls = through_walls - state_.ghosts_through_walls;
    const std::size_t new_open = ghosts - state_.ghosts - new_through_walls;
    state_.ghosts = ghosts;
    state_.ghosts_through_walls = through_walls;
    const std::size_t escaped = ghosts - through_walls;
    if (new_open > 0) {
      const double fraction =
          static_cast<double>(escaped) / static_cast<double>(std::max<std::size_t>(state_.initial_fluid, 1));
      const std::string reason = std::to_string(new_open) +
                                 " fluid particle(s) left the domain through an open side (" + std::to_string(escaped) +
                                 format(" in all, %.3g %% of the fluid)", 100.0 * fraction);
      record(step, time, kEscaped, reason);
      if (fraction > settings_.max_escaped_fraction && stop_divergence) {
        stop("diverged", step, time,
             reason + format(", beyond stability.max_escaped_fraction = %.3g", settings_.max_escaped_fraction));
      }
    }
  }
}

// Fluid inside a wall or through it, beyond the allowed number.
void StabilityMonitor::check_penetrations(std::size_t beyond_walls, long long step, double time) {
  const bool stop_divergence = settings_.stop_on_divergence;
  const std::size_t penetrations = beyond_walls + state_.ghosts_through_walls;
  if (beyond_walls > 0 || penetrations > state_.last_penetrations) {
    const std::string reason = std::to_string(penetrations) +
                               " fluid particle(s) beyond a wall's first particle line (" +
                               std::to_string(beyond_walls) + " inside the wall, " +
                               std::to_string(state_.ghosts_through_walls) + " through it)";
    record(step, time, kPenetration, reason);
    if (static_cast<long long>(penetrations) > settings_.max_wall_penetrations && stop_divergence) {
      stop("diverged", step, time,
           reason + ", beyond stability.max_wall_penetrations = " + std::to_string(settings_.max_wall_penetrations));
    }
  }
  state_.last_penetrations = penetrations;
}

// The speed capped by a wall treatment (a time step beyond what the flow allows), and the
// Courant number.
void StabilityMonitor::check_speed(const StepReport& report, double max_speed2, long long step, double time,
                                   double dt) {
  const double l0 = scene_.particle_spacing;
  const bool stop_divergence = settings_.stop_on_divergence;
  state_.last_courant = std::sqrt(max_speed2) * dt / l0;
  if (state_.last_courant > settings_.courant_limit) {
    const std::string reason = format(
        "the Courant number max|u| dt/l0 = %.3g exceeds stability.courant_limit = %.3g "
        "(max |u| = %.3g m/s)",
        state_.last_courant, settings_.courant_limit, std::sqrt(max_speed2));
    record(step, time, kCourant, reason);
    if (stop_divergence) stop("diverged", step, time, reason);
  }

  if (report.speed_limited_particles > 0) {
    const double fraction = static_cast<double>(report.speed_limited_particles) /
                            static_cast<double>(std::max<std::size_t>(state_.initial_fluid, 1));
    const std::string reason =
        "a wall treatment capped the speed of " + std::to_string(report.speed_limited_particles) +
        format(" fluid particles (%.3g %% of the fluid): the time step is beyond what the flow allows",
               100.0 * fraction);
    record(step, time, kSpeedLimited, reason);
    if (fraction > settings_.max_speed_limited_fraction && stop_divergence) {
      stop("diverged", step, time,
           reason + format(" (stability.max_speed_limited_fraction = %.3g)", settings_.max_speed_limited_fraction));
    }
  }
}

// Every density_check_every_steps: the common density error; and the solver's convergence.
void StabilityMonitor::check_density_and_solver(const ParticleSet& particles, const StepReport& report, long long step,
                                                double time) {
  const bool stop_divergence = settings_.stop_on_divergence;
  if (step % settings_.density_check_every_steps == 0) {
    state_.last_density_error = common_density_error(particles, scene_, *density_workspace_);
    if (state_.last_density_error > settings_.density_error_limit) {
      const std::string reason = format("the density error %.3g exceeds stability.density_error_limit = %.3g",
                                        state_.last_density_error, settings_.density_error_limit);
      record(step, time, kDensity, reason);
      if (stop_divergence) stop("diverged", step, time, reason);
    }
  }

  if (!report.solver_converged) {
    const std::string reason = "the pressure solver did not converge" +
                               (report.solver_note.empty() ? std::string() : ": " + report.solver_note);
    record(step, time, kSolver, reason);
    if (settings_.stop_on_solver_failure) stop("solver_failed", step, time, reason);
  }
}

void StabilityMonitor::check_step(const ParticleSet& particles, const StepReport& report, long long step, double time,
                                  double dt, double body_energy) {
  const ParticleScan scan = scan_particles(particles);
  if (scan.first_non_finite >= 0) {
    const std::string reason =
        "particle " + std::to_string(scan.first_non_finite) + " has a non-finite position, velocity or pressure";
    record(step, time, kNonFinite, reason);
    stop("diverged", step, time, reason);  // always: there is nothing to continue from
  }
  state_.min_wall_distance = scan.min_wall_distance;
  check_speed(report, scan.max_speed2, step, time, dt);
  check_energy(particles, body_energy, step, time);
  check_ghosts(particles, scan.ghosts, step, time);
  check_penetrations(scan.beyond_walls, step, time);
  check_density_and_solver(particles, report, step, time);
}

void StabilityMonitor::check_blow_up(const ParticleSet& particles, long long step, double time,
                                     const std::string& what) {
  const Box& d = scene_.domain;
  const double reach = 1e6 * std::max(d.max.x() - d.min.x(), d.max.y() - d.min.y());  // m
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] == ParticleType::Wall) continue;
    const Vec2& x = particles.position[i];
    const Vec2& u = particles.velocity[i];
    const bool finite = std::isfinite(x.x()) && std::isfinite(x.y()) && std::isfinite(u.x()) && std::isfinite(u.y()) &&
                        std::isfinite(particles.pressure[i]);
    if (!finite || (x - d.min).norm() > reach) {
      const std::string reason = "particle " + std::to_string(i) +
                                 (finite ? " is more than 1e6 domain sizes away" : " has a non-finite state") +
                                 " and the step stopped (" + what + ")";
      record(step, time, kNonFinite, reason);
      stop("diverged", step, time, reason);
    }
  }
}

long long StabilityMonitor::count(const std::string& kind) const {
  const auto& kinds = stability_event_kinds();
  const auto found = std::find(kinds.begin(), kinds.end(), kind);
  if (found == kinds.end()) throw std::logic_error("unknown stability event kind '" + kind + "'");
  return state_.counts[static_cast<std::size_t>(found - kinds.begin())];
}

nlohmann::json StabilityMonitor::summary() const {
  nlohmann::json counts = nlohmann::json::object();
  nlohmann::json first = nlohmann::json::object();
  for (std::size_t k = 0; k < stability_event_kinds().size(); ++k) {
    counts[stability_event_kinds()[k]] = state_.counts[k];
  }
  nlohmann::json log = nlohmann::json::array();
  for (const auto& event : state_.log) {
    log.push_back({{"step", event.step}, {"time", event.time}, {"kind", event.kind}, {"detail", event.detail}});
    if (!first.contains(event.kind)) first[event.kind] = log.back();
  }
  return {{"settings",
           {{"on_divergence", settings_.stop_on_divergence ? "stop" : "continue"},
            {"on_solver_failure", settings_.stop_on_solver_failure ? "stop" : "continue"},
            {"courant_limit", settings_.courant_limit},
            {"max_speed_limited_fraction", settings_.max_speed_limited_fraction},
            {"energy_growth_limit", settings_.energy_growth_limit},
            {"density_error_limit", settings_.density_error_limit},
            {"density_check_every_steps", settings_.density_check_every_steps},
            {"max_wall_penetrations", settings_.max_wall_penetrations},
            {"max_escaped_fraction", settings_.max_escaped_fraction}}},
          {"initial_energy", state_.initial_energy},
          {"energy_scale", state_.energy_scale},
          {"final_energy", state_.last_energy},
          {"events_total", state_.events_total},
          {"min_wall_distance_over_l0", state_.min_wall_distance / scene_.particle_spacing},
          {"counts", counts},
          {"first_event", first},
          {"events", log}};
}

}  // namespace mps_lab
