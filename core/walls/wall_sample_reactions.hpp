#pragma once
// The fluid's reaction on wall samples (core/walls/wall_samples.hpp): the load on obstacles when the
// boundary model has no wall particles (dummy_layers, mirror_particles, distance_function;
// docs/walls.md, "Loads on obstacles").
//
// Each sample w of a fluid particle i exerts the pair force f_iw (N/m) of a method's operator on i;
// -f_iw is the force i puts on the solid the sample stands for (WallSample::obstacle). A method
// adds, right after each operator with wall terms (the samples are rebuilt at every search), the
// reaction of that operator's sample pairs to the per-obstacle totals: the force and its moment
// about the origin, taken at the sample's position x_w (a pressure pair acts along x_i - x_w, so
// this is the moment of the pair's line of action). The pair function is the one the operator
// calls, so the fluid and the obstacle exchange equal and opposite forces by construction.
//
// The per-sample reactions are computed in parallel (each fluid particle writes only its own
// samples' entries) and summed in sample order: the totals are the same bits for any number of
// threads.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/base/particles.hpp"
#include "core/walls/wall_samples.hpp"

namespace mps_lab {

// Per obstacle k (walls.obstacles[k]): the force the fluid put on its wall samples, N/m, and that
// force's moment about the origin, N (N m per m width), counter-clockwise positive; and the force
// on the tank's samples (with those of a corner between two solids, WallSample::obstacle -1), N/m:
// with it the fluid's momentum balance closes (tests/test_sample_loads.cpp).
struct WallSampleLoads {
  std::vector<Vec2> force;
  std::vector<double> moment;
  Vec2 tank_force = Vec2::Zero();

  void reset(std::size_t obstacles) {
    force.assign(obstacles, Vec2::Zero());
    moment.assign(obstacles, 0.0);
    tank_force = Vec2::Zero();
  }
};

// loads += the reaction -pair_force(i, q, sample) of every sample q of every fluid particle i, per
// the sample's obstacle (samples of the tank, obstacle -1, go to tank_force). `pair_force(i, q,
// sample)`: the force the sample (index q in samples.samples) exerts on the fluid, N/m.
// `scratch` holds the per-sample reactions (reused).
template <typename PairForce>
void add_wall_sample_reactions(const ParticleSet& particles, const WallSampleList& samples, PairForce&& pair_force,
                               std::vector<Vec2>& scratch, WallSampleLoads& loads) {
  if (!samples.has_samples()) return;
  scratch.assign(samples.samples.size(), Vec2::Zero());
  const auto n = static_cast<std::ptrdiff_t>(particles.size());
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t i = 0; i < n; ++i) {
    if (particles.type[i] != ParticleType::Fluid) continue;
    const auto row = static_cast<std::size_t>(i);
    for (std::uint32_t s = samples.begin(row); s < samples.end(row); ++s) {
      scratch[s] = -pair_force(row, s, samples.samples[s]);
    }
  }
  for (std::size_t s = 0; s < samples.samples.size(); ++s) {
    const WallSample& sample = samples.samples[s];
    if (sample.obstacle < 0) {
      loads.tank_force += scratch[s];
      continue;
    }
    const auto k = static_cast<std::size_t>(sample.obstacle);
    const Vec2& f = scratch[s];
    loads.force[k] += f;
    loads.moment[k] += sample.position.x() * f.y() - sample.position.y() * f.x();
  }
}

}  // namespace mps_lab
