// Floating and submerged bodies against theory (issue 15, item 4; docs/bodies.md, "Floating box:
// draft and heave" and "Rising and sinking boxes"): every registered method that can move a body
// (it reports obstacle loads and uses the walls' velocity) floats the box of
// scenes/floating_box_heave.json at its draft within the measured convergence, heaves it
// with the period of the added-mass estimate, and sinks the dense box of scenes/sinking_box.json
// near the drag estimate's terminal speed. Coarse spacings (the study at finer ones:
// analysis/floating_bodies.py).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <utility>
#include <vector>

#include <Eigen/Dense>

#include "core/base/error.hpp"
#include "core/run/driver.hpp"
#include "core/run/stability.hpp"
#include "support.hpp"

using namespace mps_lab;
using namespace mps_lab::testing;

namespace {

constexpr double kPi = 3.141592653589793;

struct BodyTrack {
  std::vector<double> t, y, v;  // s, m (centre of mass height), m/s (its vertical velocity)
  bool completed = true;        // false: the run stopped (diverged)
  std::size_t fluid_particles = 0;
};

// A run of `scene` with `method`, the body's height and vertical velocity after every step.
BodyTrack track_body(const Scene& scene, const MethodInfo& method) {
  BodyTrack track;
  Simulation simulation(scene, method);
  for (std::size_t i = 0; i < simulation.particles().size(); ++i) {
    if (simulation.particles().type[i] == ParticleType::Fluid) ++track.fluid_particles;
  }
  try {
    while (simulation.time() < scene.time.end_time - 1e-9) {
      simulation.advance();
      track.t.push_back(simulation.time());
      track.y.push_back(simulation.bodies().state(0).position.y());
      track.v.push_back(simulation.bodies().state(0).velocity.y());
    }
  } catch (const RunStopped&) {
    track.completed = false;
  }
  return track;
}

// Whether a run of the scene can move its body: the method reports the loads on it and uses the
// walls' velocity (core/run/method.hpp); the others stop at start with a one-line error.
bool moves_bodies(const Scene& scene, const MethodInfo& method) {
  return method.moving_walls && reports_obstacle_loads(scene, method);
}

struct Heave {
  double draft = 0.0;        // the rest level less the bottom's mean height over the first period, m
  double period = 0.0;       // from the release (a turning point) to the second turning point after it, s
  double damping = 0.0;      // zeta from the decay of the first two half swings
  int turns = 0;             // turning points found
  double first_swing = 0.0;  // |y(first turn) - y(release)|, m
};

// Turning points: the release (v = 0) and where v changes sign, at least 0.15 s apart (a quarter
// of the shortest period the estimate allows, 0.66 s: the sign flickers near a turn are merged).
// Only the first period is used: the tank's waves come back from its sides after about 0.6 s
// (docs/bodies.md).
Heave heave_of(const BodyTrack& track, double rest_centre, double draft_theory) {
  std::vector<std::size_t> turns = {0};
  for (std::size_t i = 1; i < track.v.size(); ++i) {
    if ((track.v[i - 1] < 0.0) == (track.v[i] < 0.0)) continue;
    if (track.t[i] - track.t[turns.back()] < 0.15) continue;
    turns.push_back(i);
  }
  Heave heave;
  heave.turns = static_cast<int>(turns.size());
  if (turns.size() >= 2) heave.first_swing = std::fabs(track.y[turns[1]] - track.y[turns[0]]);
  if (turns.size() < 3) return heave;
  heave.period = track.t[turns[2]] - track.t[turns[0]];
  // Half swings h_k = |y(turn k+1) - y(turn k)| decay by exp(-zeta pi / sqrt(1 - zeta^2)) each.
  const double first = std::fabs(track.y[turns[1]] - track.y[turns[0]]);
  const double second = std::fabs(track.y[turns[2]] - track.y[turns[1]]);
  const double per_half = std::log(first / second);
  heave.damping = per_half / std::sqrt(kPi * kPi + per_half * per_half);
  double sum = 0.0;
  for (std::size_t i = turns[0]; i < turns[2]; ++i) sum += track.y[i];
  heave.draft = draft_theory + rest_centre - sum / static_cast<double>(turns[2] - turns[0]);
  return heave;
}

// y = y0 + exp(-decay t) (a sin(omega t) + b cos(omega t)) fitted by least squares to the samples
// with t <= end, as analysis/mps_lab/studies/floating.py's fit_damped_heave (and the linear theory it
// is compared with): a grid over omega (periods 0.3-1.5 s) and the decay (0-20 1/s), linear least
// squares for y0, a, b, refined twice on a grid ten times finer around the best. Every 4th sample
// (the study's series). Returns {damped period 2 pi / omega, zeta = decay / omega_n}.
std::pair<double, double> fit_damped_heave(const BodyTrack& track, double end) {
  std::vector<double> t, y;
  for (std::size_t i = 0; i < track.t.size() && track.t[i] <= end; i += 4) {
    t.push_back(track.t[i]);
    y.push_back(track.y[i]);
  }
  const auto residual = [&](double decay, double omega) {
    Eigen::Matrix3d normal = Eigen::Matrix3d::Zero();
    Eigen::Vector3d right = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < t.size(); ++i) {
      const double e = std::exp(-decay * t[i]);
      const Eigen::Vector3d row(1.0, e * std::sin(omega * t[i]), e * std::cos(omega * t[i]));
      normal += row * row.transpose();
      right += row * y[i];
    }
    const Eigen::Vector3d c = normal.ldlt().solve(right);
    double sum = 0.0;
    for (std::size_t i = 0; i < t.size(); ++i) {
      const double e = std::exp(-decay * t[i]);
      const double r = y[i] - c[0] - e * (c[1] * std::sin(omega * t[i]) + c[2] * std::cos(omega * t[i]));
      sum += r * r;
    }
    return sum;
  };
  double omega_low = 2.0 * kPi / 1.5, omega_high = 2.0 * kPi / 0.3, decay_low = 0.0, decay_high = 20.0;
  int omegas = 200, decays = 101;
  double best_omega = omega_low, best_decay = 0.0;
  for (int round = 0; round < 3; ++round) {
    const double d_omega = (omega_high - omega_low) / (omegas - 1), d_decay = (decay_high - decay_low) / (decays - 1);
    double best = std::numeric_limits<double>::infinity();
    for (int i = 0; i < omegas; ++i) {
      for (int k = 0; k < decays; ++k) {
        const double value = residual(decay_low + k * d_decay, omega_low + i * d_omega);
        if (value < best) best = value, best_omega = omega_low + i * d_omega, best_decay = decay_low + k * d_decay;
      }
    }
    omega_low = best_omega - d_omega, omega_high = best_omega + d_omega;
    decay_low = std::max(best_decay - d_decay, 0.0), decay_high = best_decay + d_decay;
    omegas = decays = 21;
  }
  const double natural = std::hypot(best_omega, best_decay);
  return {2.0 * kPi / best_omega, best_decay / natural};
}

// Largest 0.05 s running mean of |v|, m/s.
double largest_speed(const BodyTrack& track) {
  double best = 0.0;
  std::size_t begin = 0;
  double sum = 0.0;
  for (std::size_t i = 0; i < track.v.size(); ++i) {
    sum += std::fabs(track.v[i]);
    while (track.t[i] - track.t[begin] > 0.05) sum -= std::fabs(track.v[begin++]);
    if (track.t[i] >= 0.05) best = std::max(best, sum / static_cast<double>(i - begin + 1));
  }
  return best;
}

}  // namespace

TEST_CASE("floating box: draft heave period and damping and a sinking box's speed - every method that moves bodies",
          "[bodies][coupling][floating][long]") {
  // scenes/floating_box_heave.json: a box B x H = 0.2 x 0.1 m (polygon: the same surface at every
  // l0), rho_b = 500, draft d = rho_b/rho_w H = 0.05 m, released at rest 12 mm deeper; here at
  // l0 = 0.025 m (d = 2 l0), 1 s. The level at rest: the water is N l0^2 of area over a bed at
  // l0/2 between sides W - l0 apart (the wall surfaces l0/2 inside the first wall particles), so
  // (W - l0)(eta - l0/2) = N l0^2 + B d; the draft is eta less the bottom's mean height.
  // Measured (analysis/floating_bodies.py, mean over 2 s): draft error +11.4 % (isph) and +2.7 %
  // (dfsph) at this l0, +5.8 % and +0.8 % at l0 = 0.0125 (isph: first order); over the first
  // period alone (here) +13.7 % and -2.3 %: asserted within 16 %.
  const double l0 = 0.025, B = 0.2, H = 0.1, d = 0.05, W = 1.2;
  // Heave: linear potential flow in the same tank (analysis/mps_lab/radiation.py, TankDecay: the box
  // released 11.6 mm below rest in water 0.2691 m deep between walls 1.175 m apart, the tank's
  // reflections included; docs/bodies.md "Linear theory"), fitted over the first second as here
  // (fit_damped_heave): T = 0.7830 s, zeta = 0.134. The particle runs lie within -10.3 % (mps here)
  // and +9.3 % (mps at l0 = 0.0125 m) of the theory's period at l0 = 0.025 to 0.00625 m
  // (docs/data/heave_vs_linear_theory.csv; isph and dfsph +3.5 % and +3.9 % at the finest): asserted
  // within 12 % of it. Damping: zeta within (0.5, 2) x 0.134 (measured 0.126-0.204 at this l0).
  const double period_theory = 0.7830, zeta_theory = 0.134;
  // Sinking: scenes/sinking_box.json at l0 = 0.02 m (a = 3 l0), rho_b = 1500: U = sqrt(2 |rho_b -
  // rho_w| g a / (rho_w C_d)) = 0.542 m/s for C_d = 2.0; the tank (6 a wide) blocks the flow,
  // C_d (6/5)^2 = 2.88 gives 0.452 m/s, and the box tilts (a square at 45 deg: C_d about 1.5,
  // 0.63 m/s). Measured 0.327 (dfsph) and 0.429 m/s (isph), rising with resolution to 0.398 and
  // 0.542 m/s at a = 6 l0 (docs/bodies.md): asserted in 0.55-1.15 x 0.542 m/s.
  const double drag_speed = std::sqrt(2.0 * 500.0 * 9.81 * 0.06 / (1000.0 * 2.0));
  const Scene heave_scene = load("floating_box_heave.json", {"time.end_time=1.0"});
  const Scene sinking_scene = load("sinking_box.json", {"particle_spacing=0.02"});
  int floating = 0;
  for (const MethodInfo* method : registries().methods.all()) {
    if (!moves_bodies(heave_scene, *method)) continue;
    const BodyTrack track = track_body(heave_scene, *method);
    const auto lowest = std::min_element(track.y.begin(), track.y.end());
    const double count = static_cast<double>(track.fluid_particles);
    const double level = l0 / 2 + (count * l0 * l0 + B * d) / (W - l0);  // eta, m
    const double rest_centre = level - d + H / 2;
    if (!track.completed || track.y.empty() || *lowest < rest_centre - H) {
      WARN(method->name << " does not float the box (lowest centre " << (track.y.empty() ? 0.0 : *lowest) << " m)");
      continue;
    }
    const Heave heave = heave_of(track, rest_centre, d);
    const auto [period, zeta] = fit_damped_heave(track, 1.0);
    INFO(method->name << ": level at rest " << level << " m, draft " << heave.draft << " m, period " << period
                      << " s, zeta " << zeta << " (fitted), " << heave.turns << " turning points");
    // An under-damped oscillator released A below its rest position swings A (1 + exp(-zeta pi /
    // sqrt(1 - zeta^2))) > A up to its first turn: a first half swing under A/2 is not a heave
    // (mps's wall-pressure load is intermittent at d = 2 l0, docs/bodies.md): reported, and the
    // method is held to floating at its level, the body's mean centre within 0.02 m (0.8 l0) of rest.
    const double release_offset = rest_centre - track.y.front();
    if (heave.turns < 2 || heave.first_swing < 0.5 * release_offset) {
      const double mean = std::accumulate(track.y.begin(), track.y.end(), 0.0) / static_cast<double>(track.y.size());
      WARN(method->name << " floats but does not heave: first half swing " << heave.first_swing << " m after a release "
                        << release_offset << " m below rest; mean centre " << mean << " m, rest " << rest_centre);
      CHECK(std::fabs(mean - rest_centre) < 0.02);
      continue;
    }
    ++floating;
    REQUIRE(heave.turns >= 3);
    CHECK(std::fabs(heave.draft - d) < 0.16 * d);
    CHECK(period == Approx(period_theory).epsilon(0.12));
    CHECK(zeta > 0.5 * zeta_theory);
    CHECK(zeta < 2.0 * zeta_theory);
    const BodyTrack sinking = track_body(sinking_scene, *method);
    INFO(method->name << ": the sinking box's largest speed " << largest_speed(sinking) << " m/s, drag estimate "
                      << drag_speed << " m/s; it went from 0.51 to " << sinking.y.back() << " m");
    CHECK(sinking.completed);
    CHECK(sinking.y.back() < 0.51 - 0.12);  // sank by more than 2 a
    CHECK(largest_speed(sinking) > 0.55 * drag_speed);
    CHECK(largest_speed(sinking) < 1.15 * drag_speed);
  }
  // dfsph, isph and mps heave (mps with its fluid-pressure load; with its wall particles' pressure,
  // obstacle_load wall_pressure, it floats without a heave at d = 2 l0: docs/bodies.md).
  CHECK(floating >= 3);
}

#ifdef MPS_LAB_WITH_DFSPH
TEST_CASE("dfsph bodies: the extrapolated wall pressure and a 2.4 l0 kernel bring the rising box to its drag estimate",
          "[bodies][coupling][dfsph][long]") {
  // scenes/rising_box.json at its l0 = 0.01 m (a = 6 l0), rho_b = 500, 1.2 s, with the step
  // halved twice (1.25e-4 s): the drag estimate U = 0.542 m/s (as the sinking box above), its
  // spread 0.83-1.15 U (blockage to a square at 45 deg; docs/bodies.md). The largest vertical
  // speed (0.05 s running mean) depends on the step at the scene's 5e-4 s, so the test runs
  // where it has settled (docs/bodies.md, "dfsph's slow bodies", the step study), U fractions
  // at 5e-4 / 2.5e-4 / 1.25e-4 / 6.25e-5 s:
  //   mirrored (default), 2 l0:       0.78 / 0.77 / 0.63 / -
  //   extrapolated, 2 l0:             0.95 / 0.77 / 0.76 / diverged at 0.12 s
  //   extrapolated, 2.4 l0:           diverged at step 66 / 1.10 / 0.89 / 0.98
  // (and 3e-4 s: diverged at step 115; 2e-4 s: 0.97; 1.5e-4 s: diverged at 0.089 s; 1e-4 s:
  // 1.01). A body lighter than its added mass is not robust in the step with the explicit
  // coupling (docs/bodies.md): where the run survives, this setting is in the band. Asserted at
  // 1.25e-4 s: the extrapolated wall pressure with the 2.4 l0 kernel in the band, the mirrored
  // default below it (deterministic runs; if either moves, the docs' explanation must be
  // revisited).
  const double drag_speed = std::sqrt(2.0 * 500.0 * 9.81 * 0.06 / (1000.0 * 2.0));
  const MethodInfo& dfsph = *registries().methods.find("dfsph");
  const BodyTrack wide = track_body(
      load("rising_box.json",
           {"methods.dfsph.wall_pressure=extrapolated", "methods.dfsph.kernel_support=2.4", "time.time_step=1.25e-4"}),
      dfsph);
  const BodyTrack mirrored =
      track_body(load("rising_box.json", {"methods.dfsph.wall_pressure=mirrored", "time.time_step=1.25e-4"}), dfsph);
  INFO("largest vertical speed / U: extrapolated with 2.4 l0 " << largest_speed(wide) / drag_speed << ", mirrored "
                                                               << largest_speed(mirrored) / drag_speed);
  REQUIRE(wide.completed);
  REQUIRE(mirrored.completed);
  CHECK(wide.y.back() > wide.y.front() + 0.3);  // rose by 5 a
  CHECK(largest_speed(wide) > 0.83 * drag_speed);
  CHECK(largest_speed(wide) < 1.15 * drag_speed);
  CHECK(largest_speed(mirrored) < 0.83 * drag_speed);
}
#endif
