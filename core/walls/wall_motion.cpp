// The motion laws of moving walls (core/walls/wall_motion.hpp).
#include "core/walls/wall_motion.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "core/base/error.hpp"
#include "core/base/parameters.hpp"

namespace mps_lab {

namespace {

constexpr double kTwoPi = 6.283185307179586;

// constant_acceleration: the time after t_s when the speed reaches the cap, s (infinite: no cap).
double cap_time(const WallMotion& m) {
  const double a = m.acceleration.norm();
  if (m.max_speed <= 0.0 || a == 0.0) return std::numeric_limits<double>::infinity();
  return m.max_speed / a;
}

// table: the row interval [k, k+1] holding tau (tau strictly inside the table).
std::size_t table_interval(const WallMotion& m, double tau) {
  const auto upper = std::upper_bound(m.times.begin(), m.times.end(), tau);
  return static_cast<std::size_t>(upper - m.times.begin()) - 1;
}

}  // namespace

Vec2 WallMotion::displacement(double t) const {
  const double tau = t - start_time;
  if (law == MotionLaw::None || tau <= 0.0) return Vec2::Zero();
  switch (law) {
    case MotionLaw::ConstantVelocity:
      return tau * velocity;
    case MotionLaw::ConstantAcceleration: {
      const double tc = cap_time(*this);
      if (tau <= tc) return 0.5 * tau * tau * acceleration;
      return 0.5 * tc * tc * acceleration + (tau - tc) * (max_speed / acceleration.norm()) * acceleration;
    }
    case MotionLaw::Sinusoid:
      return (std::sin(kTwoPi * tau / period + phase) - std::sin(phase)) * amplitude;
    case MotionLaw::Table: {
      if (tau <= times.front()) return Vec2::Zero();
      if (tau >= times.back()) return offsets.back() - offsets.front();
      const std::size_t k = table_interval(*this, tau);
      const double s = (tau - times[k]) / (times[k + 1] - times[k]);
      return (1.0 - s) * offsets[k] + s * offsets[k + 1] - offsets.front();
    }
    case MotionLaw::None:
      break;
  }
  return Vec2::Zero();
}

Vec2 WallMotion::velocity_at(double t) const {
  const double tau = t - start_time;
  if (law == MotionLaw::None || tau < 0.0) return Vec2::Zero();
  switch (law) {
    case MotionLaw::ConstantVelocity:
      return velocity;
    case MotionLaw::ConstantAcceleration:
      return std::min(tau, cap_time(*this)) * acceleration;
    case MotionLaw::Sinusoid:
      return (kTwoPi / period) * std::cos(kTwoPi * tau / period + phase) * amplitude;
    case MotionLaw::Table: {
      if (tau < times.front() || tau >= times.back()) return Vec2::Zero();
      const std::size_t k = table_interval(*this, tau);
      return (offsets[k + 1] - offsets[k]) / (times[k + 1] - times[k]);
    }
    case MotionLaw::None:
      break;
  }
  return Vec2::Zero();
}

Vec2 WallMotion::acceleration_at(double t) const {
  const double tau = t - start_time;
  if (law == MotionLaw::None || tau < 0.0) return Vec2::Zero();
  switch (law) {
    case MotionLaw::ConstantAcceleration:
      return tau < cap_time(*this) ? acceleration : Vec2::Zero();
    case MotionLaw::Sinusoid: {
      const double omega = kTwoPi / period;
      return -omega * omega * std::sin(omega * tau + phase) * amplitude;
    }
    default:
      return Vec2::Zero();  // constant velocity; a table is piecewise linear
  }
}

namespace {

// One CSV row "t,x,y" into three numbers; false if it is not one.
bool parse_row(const std::string& line, double values[3]) {
  std::stringstream stream(line);
  std::string cell;
  int count = 0;
  while (std::getline(stream, cell, ',')) {
    if (count == 3) return false;
    std::size_t used = 0;
    try {
      values[count] = std::stod(cell, &used);
    } catch (const std::exception&) {
      return false;
    }
    if (cell.find_first_not_of(" \t\r", used) != std::string::npos || !std::isfinite(values[count])) return false;
    ++count;
  }
  return count == 3;
}

}  // namespace

void read_motion_table(const std::string& file, const std::string& source, const std::string& key, WallMotion& motion) {
  std::ifstream in(file);
  if (!in) throw_input_error(source, key, "cannot read the motion table '" + file + "'; expected a CSV file t,x,y");
  motion.times.clear();
  motion.offsets.clear();
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (line.find_first_not_of(" \t\r") == std::string::npos || line[line.find_first_not_of(" \t")] == '#') continue;
    double row[3];
    if (!parse_row(line, row)) {
      if (motion.times.empty() && line_number == 1) continue;  // a header line
      throw_input_error(source, key,
                        file + " line " + std::to_string(line_number) + ": expected three numbers t,x,y (s, m, m)");
    }
    if (!motion.times.empty() && !(row[0] > motion.times.back())) {
      throw_input_error(source, key,
                        file + " line " + std::to_string(line_number) + ": t = " + describe_json(row[0]) +
                            " s, expected t strictly increasing (previous row " + describe_json(motion.times.back()) +
                            " s)");
    }
    motion.times.push_back(row[0]);
    motion.offsets.emplace_back(row[1], row[2]);
  }
  if (motion.times.size() < 2) {
    throw_input_error(source, key, file + ": " + std::to_string(motion.times.size()) + " rows, expected at least two");
  }
}

}  // namespace mps_lab
