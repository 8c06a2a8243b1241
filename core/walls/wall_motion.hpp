#pragma once
// Kinematic motion of a wall (docs/walls.md, "Moving walls"): a prescribed law of time that
// gives the displacement of a solid from where the scene puts it, its velocity and its
// acceleration. A law is a small value type: the driver moves the wall particles of an obstacle
// with it every step (core/walls/moving_walls.hpp), and a rigid body (issue 15, item 3) can
// reuse it. Rotation (an angle theta(t)) is not part of a law yet: it comes with the rigid bodies.
//
// Every law is at rest before its start time t_s and starts from zero displacement, so the
// solid is at its scene position (on the lattice) until t_s; tau = t - t_s:
//   constant_velocity      d = V tau                               u = V
//   constant_acceleration  d = a tau^2 / 2 until |u| = max_speed,  u = a tau (capped), then
//                          constant speed (max_speed 0: no cap)
//   sinusoid               d = A [sin(2 pi tau / T + phi) - sin(phi)],  u = A (2 pi / T) cos(...)
//   table                  d = linear interpolation of rows (t_k, x_k, y_k) at tau, minus the
//                          first row's (x, y); u = the slope of the row interval; held at the
//                          last row (u = 0) after the table ends
#include <string>
#include <vector>

#include "core/base/types.hpp"

namespace mps_lab {

enum class MotionLaw { None, ConstantVelocity, ConstantAcceleration, Sinusoid, Table };

struct WallMotion {
  MotionLaw law = MotionLaw::None;   // None: the solid never moves
  double start_time = 0.0;           // t_s, s
  Vec2 velocity = Vec2::Zero();      // constant_velocity: V, m/s
  Vec2 acceleration = Vec2::Zero();  // constant_acceleration: a, m/s^2
  double max_speed = 0.0;            // constant_acceleration: speed cap, m/s (0: none)
  Vec2 amplitude = Vec2::Zero();     // sinusoid: A, m
  double period = 1.0;               // sinusoid: T, s
  double phase = 0.0;                // sinusoid: phi, rad
  std::vector<double> times;         // table: t_k, s (relative to t_s), strictly increasing
  std::vector<Vec2> offsets;         // table: (x_k, y_k), m

  bool moves() const { return law != MotionLaw::None; }
  Vec2 displacement(double t) const;     // d(t), m
  Vec2 velocity_at(double t) const;      // u(t), m/s
  Vec2 acceleration_at(double t) const;  // du/dt, m/s^2 (0 inside a table interval)
};

// Reads a motion table: CSV rows "t,x,y" (s, m, m), an optional header line, '#' comments.
// Throws InputError naming `source` (the scene) and `key` when the file is missing or
// unreadable, a row is malformed, fewer than two rows are given, or t is not strictly
// increasing.
void read_motion_table(const std::string& file, const std::string& source, const std::string& key, WallMotion& motion);

}  // namespace mps_lab
