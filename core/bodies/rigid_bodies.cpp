// Rigid bodies: mass properties, symplectic Euler, spring-dashpot contact (core/bodies/rigid_bodies.hpp).
#include "core/bodies/rigid_bodies.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/io/checkpoint.hpp"

namespace mps_lab {

namespace {

constexpr double kTwoPi = 6.283185307179586;

double cross(const Vec2& u, const Vec2& v) { return u.x() * v.y() - u.y() * v.x(); }
Vec2 across(const Vec2& r) { return Vec2(-r.y(), r.x()); }  // e_z x r
Vec2 rotate(const Vec2& r, double angle) {
  const double c = std::cos(angle), s = std::sin(angle);
  return Vec2(c * r.x() - s * r.y(), s * r.x() + c * r.y());
}

// The closest point to x on segment [a, b].
Vec2 closest_on_segment(const Vec2& x, const Vec2& a, const Vec2& b) {
  const Vec2 along = b - a;
  const double length2 = along.squaredNorm();
  const double t = length2 > 0.0 ? std::clamp((x - a).dot(along) / length2, 0.0, 1.0) : 0.0;
  return a + t * along;
}

// A box obstacle's surface: the box grown by l0/2 (core/walls/wall_geometry.hpp), counter-clockwise.
Polygon box_surface(const Box& box, double l0) {
  const Vec2 lo = box.min - Vec2(0.5 * l0, 0.5 * l0), hi = box.max + Vec2(0.5 * l0, 0.5 * l0);
  return {lo, Vec2(hi.x(), lo.y()), hi, Vec2(lo.x(), hi.y())};
}

}  // namespace

RigidBodies::RigidBodies(const Scene& scene) : contact_(scene.contact), gravity_(scene.physics.gravity) {
  const TankWalls& walls = scene.walls;
  double lightest = std::numeric_limits<double>::infinity();  // m I / (I + m rho^2), kg/m
  for (std::size_t k = 0; k < walls.obstacles.size(); ++k) {
    if (!walls.is_body(k)) continue;
    Body body = shaped_body(scene, k, walls.bodies[k].density);
    body.state.velocity = walls.bodies[k].velocity;
    body.state.angular_velocity = walls.bodies[k].angular_velocity;
    const MassProperties& p = body.mass;
    lightest = std::min(lightest, p.mass * p.inertia / (p.inertia + p.mass * body.reach * body.reach));
    bodies_.push_back(body);
  }
  dynamic_count_ = bodies_.size();
  if (bodies_.empty()) return;
  const WallGeometry geometry(scene);  // moving obstacles and bodies are not part of it
  walls_ = geometry.segments();
  fixed_apexes_ = convex_wall_vertices(geometry, scene.particle_spacing);
  add_kinematic_partners(scene);
  contact_step_ = kTwoPi * std::sqrt(lightest / contact_.stiffness) / contact_.steps_per_period;
}

// Obstacle k as a body of `density` (kg/m^3) at rest where the scene puts it: a circle, or a
// polygon (a box's surface is the box grown by l0/2) relative to its centre of mass.
RigidBodies::Body RigidBodies::shaped_body(const Scene& scene, std::size_t k, double density) const {
  const TankWalls& walls = scene.walls;
  Body body;
  body.obstacle = k;
  if (walls.is_circle(k)) {
    body.radius = walls.circles[k].radius;
    body.mass = circle_mass_properties(walls.circles[k].centre, body.radius, density);
    body.reach = body.radius;
  } else {
    const Polygon surface =
        walls.is_polygon(k) ? walls.polygons[k] : box_surface(walls.obstacles[k], scene.particle_spacing);
    body.mass = polygon_mass_properties(surface, density);
    for (const Vec2& vertex : surface) {
      body.shape.push_back(vertex - body.mass.centroid);
      body.reach = std::max(body.reach, body.shape.back().norm());
    }
  }
  body.initial = body.mass.centroid;
  body.state.position = body.mass.centroid;
  return body;
}

// The obstacles moved by a motion law, after the bodies: contact partners of infinite mass
// (a paddle pushing a box). Their reference point is the surface's area centroid, as the
// laws' (core/walls/moving_walls.hpp).
void RigidBodies::add_kinematic_partners(const Scene& scene) {
  const TankWalls& walls = scene.walls;
  for (std::size_t k = 0; k < walls.obstacles.size(); ++k) {
    if (walls.is_body(k) || k >= walls.motions.size() || !walls.motions[k].moves()) continue;
    Body partner = shaped_body(scene, k, 1.0);  // the density only scales the unused mass
    partner.kinematic = true;
    partner.motion = walls.motions[k];
    bodies_.push_back(partner);
  }
  follow_laws(time_);
}

// The kinematic partners to their laws' poses at time t (s): a translation, theta = 0.
void RigidBodies::follow_laws(double t) {
  for (std::size_t b = dynamic_count_; b < bodies_.size(); ++b) {
    Body& partner = bodies_[b];
    const RigidPose pose = law_pose(partner.motion, t);
    partner.state.position = partner.initial + pose.displacement;
    partner.state.velocity = pose.velocity;
    partner.state.acceleration = pose.acceleration;
  }
}

int RigidBodies::sub_steps(double dt) const {
  if (bodies_.empty()) return 0;
  return std::max(1, static_cast<int>(std::ceil(dt / contact_step_ - 1e-9)));
}

void RigidBodies::advance(double dt, const ObstacleLoads& fluid) {
  if (bodies_.empty()) return;
  std::vector<Vec2> fluid_force(bodies_.size(), Vec2::Zero());
  std::vector<double> fluid_torque(bodies_.size(), 0.0);
  for (std::size_t b = 0; b < dynamic_count_; ++b) {
    const std::size_t k = bodies_[b].obstacle;
    if (k >= fluid.size()) continue;
    fluid_force[b] = fluid.force[k];
    // The load's torque is about reference[k]; about the centre of mass: T + (ref - x_c) x F.
    const Vec2 reference = k < fluid.reference.size() ? fluid.reference[k] : bodies_[b].state.position;
    fluid_torque[b] = fluid.torque[k] + cross(reference - bodies_[b].state.position, fluid.force[k]);
  }
  for (Body& body : bodies_) {
    body.state.force = Vec2::Zero();
    body.state.torque = 0.0;
  }
  const int n = sub_steps(dt);
  const double h = dt / n;
  for (int s = 0; s < n; ++s) {
    follow_laws(time_ + s * h);
    sub_step(h, fluid_force, fluid_torque);
  }
  time_ += dt;
  follow_laws(time_);
  for (Body& body : bodies_) {  // the sub-steps summed h F: the mean over the step
    body.state.force /= static_cast<double>(n);
    body.state.torque /= static_cast<double>(n);
  }
}

// One symplectic Euler sub-step of h (s): contact forces at the current state, then u, omega,
// then x, theta with the new velocities.
void RigidBodies::sub_step(double h, const std::vector<Vec2>& fluid_force, const std::vector<double>& fluid_torque) {
  std::vector<Contact> contacts;
  find_contacts(contacts);
  std::vector<Vec2> force = fluid_force;
  std::vector<double> torque = fluid_torque;
  std::map<std::array<std::int64_t, 4>, double> springs;  // the contacts of this sub-step only
  for (const Contact& c : contacts) apply_contact(c, h, force, torque, springs);
  springs_ = std::move(springs);
  for (std::size_t b = 0; b < dynamic_count_; ++b) {
    BodyState& s = bodies_[b].state;
    s.acceleration = force[b] / bodies_[b].mass.mass + gravity_;
    s.angular_acceleration = torque[b] / bodies_[b].mass.inertia;
    s.velocity += h * s.acceleration;
    s.angular_velocity += h * s.angular_acceleration;
    s.position += h * s.velocity;
    s.angle += h * s.angular_velocity;
    s.force += force[b];  // summed over the sub-steps, divided by their number in advance()
    s.torque += torque[b];
  }
}

Polygon RigidBodies::current_shape(const Body& body) const {
  Polygon shape;
  for (const Vec2& r : body.shape) shape.push_back(body.state.position + rotate(r, body.state.angle));
  return shape;
}

Vec2 RigidBodies::point_velocity(int b, const Vec2& x) const {
  if (b < 0) return Vec2::Zero();
  const BodyState& s = bodies_[b].state;
  return s.velocity + s.angular_velocity * across(x - s.position);
}

void RigidBodies::find_contacts(std::vector<Contact>& contacts) const {
  for (std::size_t a = 0; a < dynamic_count_; ++a) {  // the kinematic partners come last
    wall_contacts(static_cast<int>(a), contacts);
    for (std::size_t b = a + 1; b < bodies_.size(); ++b)
      body_contacts(static_cast<int>(a), static_cast<int>(b), contacts);
  }
}

// The end points of the fixed wall surfaces where the solid is convex (a wedge's apex, a
// plate's end, an open tank's rim): probed on a circle of radius 1e-3 l0 around the point,
// fewer than half of 16 probes lie inside a solid (core/walls/wall_geometry.hpp, inside_solid).
// A concave corner (the tank's, an obstacle standing on the bed) has more than half.
std::vector<Vec2> convex_wall_vertices(const WallGeometry& geometry, double spacing) {
  constexpr int kProbes = 16;
  std::vector<Vec2> apexes;
  for (const WallSegment& segment : geometry.segments()) {
    for (const Vec2& p : {segment.a, segment.b}) {
      const bool known =
          std::any_of(apexes.begin(), apexes.end(), [&](const Vec2& q) { return (q - p).norm() <= 1e-9 * spacing; });
      int solid = 0;
      for (int k = 0; k < kProbes; ++k) {
        const double angle = kTwoPi * (k + 0.5) / kProbes;  // never along an axis-aligned edge
        solid += geometry.inside_solid(p + 1e-3 * spacing * Vec2(std::cos(angle), std::sin(angle))) ? 1 : 0;
      }
      if (!known && 2 * solid < kProbes) apexes.push_back(p);
    }
  }
  return apexes;
}

// Body a against the fixed wall surfaces: a circle against each segment (its closest point),
// a polygon's vertices behind a segment (less than half the body's reach behind it: deeper
// points are on the far side of a thin wall) and within its length; then the fixed convex vertices inside a
// polygon body.
void RigidBodies::wall_contacts(int a, std::vector<Contact>& contacts) const {
  const Body& body = bodies_[a];
  const Polygon shape = body.radius > 0.0 ? Polygon{} : current_shape(body);
  for (std::size_t s = 0; s < walls_.size(); ++s) {
    const WallSegment& wall = walls_[s];
    if (body.radius > 0.0) {
      const Vec2 q = closest_on_segment(body.state.position, wall.a, wall.b);
      const Vec2 d = body.state.position - q;
      const double distance = d.norm();
      if (distance >= body.radius || distance <= 1e-12 * body.radius) continue;
      contacts.push_back({a, -1, q, d / distance, body.radius - distance, {a, -1, static_cast<std::int64_t>(s), 0}});
      continue;
    }
    const Vec2 along = wall.b - wall.a;
    for (std::size_t v = 0; v < shape.size(); ++v) {
      const double behind = -(shape[v] - wall.a).dot(wall.normal);
      const double t = (shape[v] - wall.a).dot(along) / along.squaredNorm();
      if (behind <= 0.0 || behind > 0.5 * body.reach || t < 0.0 || t > 1.0) continue;
      contacts.push_back(
          {a, -1, shape[v], wall.normal, behind, {a, -1, static_cast<std::int64_t>(s), static_cast<std::int64_t>(v)}});
    }
  }
  if (body.radius > 0.0) return;
  // A fixed convex vertex inside the polygon: pushed out along the body's nearest edge.
  for (std::size_t k = 0; k < fixed_apexes_.size(); ++k) {
    const Vec2& apex = fixed_apexes_[k];
    if ((apex - body.state.position).norm() >= body.reach || !inside_polygon(apex, shape)) continue;
    std::size_t edge = 0;
    const double depth = distance_to_polygon(apex, shape, &edge);
    contacts.push_back({a,
                        -1,
                        apex,
                        -outward_normal(shape, edge),
                        depth,
                        {a, -2, static_cast<std::int64_t>(k), static_cast<std::int64_t>(edge)}});
  }
}

// Bodies a and b: circle-circle by the centres; a circle against a polygon by the closest
// point of its edges (pushed out along the nearest edge's normal if the centre is inside);
// polygons by each one's vertices inside the other (out along the nearest edge's normal).
void RigidBodies::body_contacts(int a, int b, std::vector<Contact>& contacts) const {
  const Body &A = bodies_[a], &B = bodies_[b];
  if (A.radius > 0.0 && B.radius > 0.0) {
    const Vec2 d = A.state.position - B.state.position;
    const double distance = d.norm(), overlap = A.radius + B.radius - distance;
    if (overlap <= 0.0 || distance <= 0.0) return;
    const Vec2 n = d / distance;
    contacts.push_back({a, b, B.state.position + (B.radius - 0.5 * overlap) * n, n, overlap, {a, b, 0, 0}});
    return;
  }
  if (A.radius > 0.0 || B.radius > 0.0) {
    const bool a_circle = A.radius > 0.0;
    const Body& circle = a_circle ? A : B;
    const Polygon polygon = current_shape(a_circle ? B : A);
    std::size_t edge = 0;
    const double distance = distance_to_polygon(circle.state.position, polygon, &edge);
    const bool inside = inside_polygon(circle.state.position, polygon);
    if (!inside && distance >= circle.radius) return;
    const Vec2 q = closest_on_segment(circle.state.position, polygon[edge], polygon[(edge + 1) % polygon.size()]);
    const Vec2 out = inside || distance <= 0.0 ? outward_normal(polygon, edge) : (circle.state.position - q) / distance;
    const double overlap = inside ? circle.radius + distance : circle.radius - distance;
    contacts.push_back({a, b, q, a_circle ? out : Vec2(-out), overlap, {a, b, static_cast<std::int64_t>(edge), 1}});
    return;
  }
  const Polygon pa = current_shape(A), pb = current_shape(B);
  for (int side = 0; side < 2; ++side) {
    const Polygon &from = side == 0 ? pa : pb, &into = side == 0 ? pb : pa;
    for (std::size_t v = 0; v < from.size(); ++v) {
      if (!inside_polygon(from[v], into)) continue;
      std::size_t edge = 0;
      const double depth = distance_to_polygon(from[v], into, &edge);
      const Vec2 out = outward_normal(into, edge);  // pushes the vertex's body out of the other
      contacts.push_back(
          {a, b, from[v], side == 0 ? out : Vec2(-out), depth, {a, b, static_cast<std::int64_t>(v), 2 + side}});
    }
  }
}

// The spring-dashpot force of one contact (Cundall & Strack 1979; the header's formulas) on
// body a at the contact point, and the opposite on body b.
void RigidBodies::apply_contact(const Contact& c, double h, std::vector<Vec2>& force, std::vector<double>& torque,
                                std::map<std::array<std::int64_t, 4>, double>& springs) const {
  const double ma = bodies_[c.a].mass.mass;
  const bool partner_moves_freely = c.b >= 0 && !bodies_[c.b].kinematic;  // else a wall or a law
  const double m_eff = partner_moves_freely ? ma * bodies_[c.b].mass.mass / (ma + bodies_[c.b].mass.mass) : ma;
  const double k_n = contact_.stiffness, k_t = contact_.tangential_stiffness * k_n;
  const double c_n = 2.0 * contact_.damping_ratio * std::sqrt(m_eff * k_n);
  const double c_t = 2.0 * contact_.damping_ratio * std::sqrt(m_eff * k_t);
  const Vec2 v = point_velocity(c.a, c.point) - point_velocity(c.b, c.point);
  const Vec2 t = across(c.normal);
  const double v_n = v.dot(c.normal), v_t = v.dot(t);
  const double f_n = std::max(0.0, k_n * c.overlap - c_n * v_n);
  const auto previous = springs_.find(c.key);
  double xi = (previous == springs_.end() ? 0.0 : previous->second) + h * v_t;
  double f_t = -k_t * xi - c_t * v_t;
  const double limit = contact_.friction * f_n;
  if (std::fabs(f_t) > limit) {  // sliding: Coulomb's limit, the spring where it gives that force
    f_t = std::copysign(limit, f_t);
    xi = -(f_t + c_t * v_t) / k_t;
  }
  springs[c.key] = xi;
  const Vec2 f = f_n * c.normal + f_t * t;
  force[c.a] += f;
  torque[c.a] += cross(c.point - bodies_[c.a].state.position, f);
  if (partner_moves_freely) {
    force[c.b] -= f;
    torque[c.b] -= cross(c.point - bodies_[c.b].state.position, f);
  }
}

void RigidBodies::set_poses(std::vector<RigidPose>& poses) const {
  for (std::size_t b = 0; b < dynamic_count_; ++b) {  // the kinematic partners follow their laws
    const Body& body = bodies_[b];
    RigidPose& pose = poses[body.obstacle];
    pose.displacement = body.state.position - body.initial;
    pose.angle = body.state.angle;
    pose.velocity = body.state.velocity;
    pose.angular_velocity = body.state.angular_velocity;
    pose.acceleration = body.state.acceleration;
    pose.angular_acceleration = body.state.angular_acceleration;
  }
}

std::vector<std::string> RigidBodies::series_columns(const Scene& scene) {
  std::vector<std::string> columns;
  for (std::size_t k = 0; k < scene.walls.obstacles.size(); ++k) {
    if (!scene.walls.is_body(k)) continue;
    for (const char* name : {"x", "y", "theta", "u", "v", "omega", "fx", "fy", "torque"}) {
      columns.push_back("body_" + std::to_string(k) + "_" + name);
    }
  }
  return columns;
}

void RigidBodies::append_series(std::vector<double>& row) const {
  for (std::size_t b = 0; b < dynamic_count_; ++b) {  // the kinematic partners follow their laws
    const Body& body = bodies_[b];
    const BodyState& s = body.state;
    row.insert(row.end(), {s.position.x(), s.position.y(), s.angle, s.velocity.x(), s.velocity.y(), s.angular_velocity,
                           s.force.x(), s.force.y(), s.torque});
  }
}

void RigidBodies::save(CheckpointWriter& out) const {
  out.write_double(time_);
  out.write_size(dynamic_count_);
  for (std::size_t b = 0; b < dynamic_count_; ++b) {  // the kinematic partners follow their laws
    const Body& body = bodies_[b];
    const BodyState& s = body.state;
    out.write_vec2s({s.position, s.velocity, s.acceleration, s.force});
    out.write_doubles({s.angle, s.angular_velocity, s.angular_acceleration, s.torque});
  }
  out.write_size(springs_.size());
  for (const auto& [key, xi] : springs_) {
    for (const std::int64_t part : key) out.write_int(part);
    out.write_double(xi);
  }
}

void RigidBodies::restore(CheckpointReader& in) {
  time_ = in.read_double();
  follow_laws(time_);
  if (in.read_size() != dynamic_count_) in.fail("a checkpoint with another number of rigid bodies than the scene's");
  for (std::size_t b = 0; b < dynamic_count_; ++b) {
    Body& body = bodies_[b];
    BodyState& s = body.state;
    const std::vector<Vec2> vectors = in.read_vec2s();
    const std::vector<double> scalars = in.read_doubles();
    if (vectors.size() != 4 || scalars.size() != 4) in.fail("a rigid body's state of the wrong size");
    s.position = vectors[0], s.velocity = vectors[1], s.acceleration = vectors[2], s.force = vectors[3];
    s.angle = scalars[0], s.angular_velocity = scalars[1], s.angular_acceleration = scalars[2], s.torque = scalars[3];
  }
  springs_.clear();
  const std::size_t count = in.read_size();
  for (std::size_t i = 0; i < count; ++i) {
    std::array<std::int64_t, 4> key{};
    for (std::int64_t& part : key) part = in.read_int();
    springs_[key] = in.read_double();
  }
}

}  // namespace mps_lab
