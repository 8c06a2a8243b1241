#include "core/run/time_step.hpp"

#include <algorithm>
#include <cmath>

#include "core/base/error.hpp"
#include "core/io/checkpoint.hpp"

namespace mps_lab {

std::vector<ParameterSpec> time_step_parameters(const TimeStepDefaults& defaults) {
  const auto cited = [](const std::string& text, const std::string& source) {
    return source.empty() ? text : text + " (" + source + ")";
  };
  return {
      string_parameter("time_step_rule", defaults.rule,
                       "\"cfl\": dt = cfl_number l0 / v_max within [min_time_step, max_time_step]; \"fixed\": "
                       "time.time_step")
          .one_of({"cfl", "fixed"}),
      number_parameter("cfl_number", defaults.cfl_number, "",
                       cited("CFL factor with the particle spacing l0", defaults.cfl_source))
          .above(0.0)
          .at_most(1.0),
      number_parameter("min_time_step", defaults.min_time_step, "s",
                       cited("lower bound of the CFL step", defaults.bounds_source))
          .above(0.0),
      number_parameter("max_time_step", defaults.max_time_step, "s",
                       cited("upper bound of the CFL step", defaults.bounds_source))
          .above(0.0),
  };
}

TimeStepSettings time_step_settings(const ParameterValues& parameters, double fixed_time_step,
                                    const std::string& source) {
  TimeStepSettings settings;
  settings.cfl = parameters.string("time_step_rule") == "cfl";
  settings.fixed_time_step = fixed_time_step;
  settings.cfl_number = parameters.number("cfl_number");
  settings.min_time_step = parameters.number("min_time_step");
  settings.max_time_step = parameters.number("max_time_step");
  if (settings.min_time_step > settings.max_time_step) {
    throw_input_error(source, parameters.block_path() + ".min_time_step",
                      "got " + std::to_string(settings.min_time_step) + ", expected at most max_time_step (" +
                          std::to_string(settings.max_time_step) + ")");
  }
  return settings;
}

double TimeStepClock::next(const TimeStepSettings& settings, double max_speed, double spacing, double end_time) const {
  if (!settings.cfl) return settings.fixed_time_step;
  double dt = max_speed > 0.0 ? settings.cfl_number * spacing / max_speed : settings.max_time_step;
  dt = std::clamp(dt, settings.min_time_step, settings.max_time_step);
  // Even out the end: one step if it fits, else two halves, never a sliver.
  const double remaining = end_time - elapsed_;
  if (remaining > 1e-6 * dt) {
    if (remaining <= dt) return remaining;
    if (remaining < 2.0 * dt) return 0.5 * remaining;
  }
  return dt;
}

void TimeStepClock::advance(double dt) {  // Kahan summation, as the driver's clock
  const double increment = dt - compensation_;
  const double sum = elapsed_ + increment;
  compensation_ = (sum - elapsed_) - increment;
  elapsed_ = sum;
  last_ = dt;
  smallest_ = std::min(smallest_, dt);
  largest_ = std::max(largest_, dt);
  ++steps_;
}

nlohmann::json TimeStepClock::summary(const TimeStepSettings& settings) const {
  return {{"rule", settings.cfl ? "cfl" : "fixed"},
          {"min", steps_ > 0 ? smallest_ : 0.0},
          {"max", largest_},
          {"mean", steps_ > 0 ? elapsed_ / static_cast<double>(steps_) : 0.0}};
}

void TimeStepClock::save(CheckpointWriter& out) const {
  out.write_double(elapsed_);
  out.write_double(compensation_);
  out.write_double(last_);
  out.write_double(smallest_);
  out.write_double(largest_);
  out.write_int(steps_);
}

void TimeStepClock::restore(CheckpointReader& in) {
  elapsed_ = in.read_double();
  compensation_ = in.read_double();
  last_ = in.read_double();
  smallest_ = in.read_double();
  largest_ = in.read_double();
  steps_ = in.read_int();
}

double largest_fluid_speed(const ParticleSet& particles) {
  double max_speed2 = 0.0;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    if (particles.type[i] == ParticleType::Fluid)
      max_speed2 = std::max(max_speed2, particles.velocity[i].squaredNorm());
  }
  return std::sqrt(max_speed2);
}

double largest_speed_with_gravity(const ParticleSet& particles, const Vec2& gravity, const TimeStepClock& clock) {
  const double gained = clock.steps() > 0 ? gravity.norm() * clock.last() : 0.0;  // m/s
  return largest_fluid_speed(particles) + gained;
}

}  // namespace mps_lab
