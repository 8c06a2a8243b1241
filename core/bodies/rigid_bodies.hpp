#pragma once
// Rigid bodies (docs/bodies.md): obstacles with a `body` block (walls.obstacles[k].body) that
// move under gravity, the fluid's load (core/walls/obstacle_loads.hpp) and contact.
//
// Dynamics, per body, per unit width:  m du/dt = F_fluid + m g + F_contact,
//                                      I domega/dt = T_fluid + T_contact   (about the centre of mass)
// integrated by the symplectic (semi-implicit) Euler scheme: u += h a, x += h u (the new u),
// omega += h alpha, theta += h omega. The driver calls advance() after the method's step with
// that step's fluid load, so the fluid of step n sees the body where step n-1 left it (a lag of
// one step, O(dt) like the scheme itself; docs/bodies.md, "Order in the step").
//
// Contact (Cundall & Strack 1979, "A discrete numerical model for granular assemblies",
// Geotechnique 29: linear spring and dashpot in the normal direction, a tangential spring
// capped by Coulomb's limit): for an overlap delta >= 0 with normal n (unit, the direction of
// the force on the body) and the relative velocity v of the contact point,
//   F_n = max(0, k_n delta - c_n v.n),                      c_n = 2 zeta sqrt(m_eff k_n)
//   xi += h v.t  (t = e_z x n),  F_t = -k_t xi - c_t v.t,  c_t = 2 zeta sqrt(m_eff k_t)
//   |F_t| > mu F_n: F_t = mu F_n sign(F_t), xi = -(F_t + c_t v.t) / k_t   (sliding; Luding 2008,
//   "Cohesive, frictional powders: contact models for tension", Granular Matter 10, eq. 20)
// m_eff = m for a fixed wall, m_1 m_2 / (m_1 + m_2) between bodies. The tangential spring
// holds a rolling body without slip (static friction), which a regularised Coulomb law cannot.
// A contact's spring xi lives while the contact does (a checkpoint holds it).
//
// Contacts: a body with the fixed wall surfaces (core/walls/wall_geometry.hpp: tank sides and
// fixed obstacles, polygons and slopes included), circle-segment and polygon vertex-segment; and
// between bodies circle-circle, circle-polygon and polygon vertex inside polygon; and a convex
// vertex of the fixed walls (a wedge's apex) inside a polygon body, pushed out along the body's
// nearest edge (a circle meets such a vertex as the closest point of its segments); and an
// obstacle moved by a motion law as a partner of infinite mass at its law's pose (a paddle).
//
// Sub-steps: the body takes n = ceil(dt / h_c) sub-steps per fluid step, h_c = T_c / N with
// T_c = 2 pi sqrt(m_c / k_n) the contact period of the lightest body (m_c = m I / (I + m rho^2),
// rho its farthest surface point from the centre of mass: the smallest effective mass at a
// contact point) and N = contact.steps_per_period; the fluid load is constant over them.
#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "core/bodies/mass_properties.hpp"
#include "core/io/scene.hpp"
#include "core/walls/moving_walls.hpp"
#include "core/walls/obstacle_loads.hpp"
#include "core/walls/wall_geometry.hpp"

namespace mps_lab {

class CheckpointWriter;
class CheckpointReader;

// The end points of the fixed wall surfaces where the solid is convex (a wedge's apex, a plate's
// end, an open tank's rim), each once: the partners of a polygon body's edges in contact.
std::vector<Vec2> convex_wall_vertices(const WallGeometry& geometry, double spacing);

struct BodyState {
  Vec2 position = Vec2::Zero();       // centre of mass x_c, m
  double angle = 0.0;                 // theta, rad, counter-clockwise from the scene's orientation
  Vec2 velocity = Vec2::Zero();       // m/s
  double angular_velocity = 0.0;      // rad/s
  Vec2 acceleration = Vec2::Zero();   // of the last sub-step, m/s^2 (the wall particles' a_b)
  double angular_acceleration = 0.0;  // of the last sub-step, rad/s^2
  Vec2 force = Vec2::Zero();          // fluid + contact over the last step (impulse / dt), N/m; no gravity
  double torque = 0.0;                // the same about the centre of mass, N (N m per m)
};

class RigidBodies {
 public:
  explicit RigidBodies(const Scene& scene);
  bool empty() const { return dynamic_count_ == 0; }
  std::size_t size() const { return dynamic_count_; }  // the rigid bodies (not the kinematic partners)
  std::size_t obstacle(std::size_t b) const { return bodies_[b].obstacle; }  // walls.obstacles[k]
  const MassProperties& mass(std::size_t b) const { return bodies_[b].mass; }
  const BodyState& state(std::size_t b) const { return bodies_[b].state; }
  // How many sub-steps a fluid step of dt (s) takes.
  int sub_steps(double dt) const;
  // One fluid step of dt (s) under the fluid's loads (per obstacle; empty: no fluid force).
  void advance(double dt, const ObstacleLoads& fluid);
  // Each body's pose into poses[its obstacle] (core/walls/moving_walls.hpp).
  void set_poses(std::vector<RigidPose>& poses) const;
  // series.csv: body_<k>_x, _y, _theta, _u, _v, _omega, _fx, _fy, _torque per body (k: obstacle).
  static std::vector<std::string> series_columns(const Scene& scene);
  void append_series(std::vector<double>& row) const;
  void save(CheckpointWriter& out) const;
  void restore(CheckpointReader& in);

 private:
  struct Body {
    std::size_t obstacle = 0;
    MassProperties mass;
    double radius = 0.0;          // a circle's, m; 0: a polygon
    Polygon shape;                // a polygon's surface vertices relative to the centre of mass at theta = 0, m
    double reach = 0.0;           // farthest surface point from the centre of mass, m
    Vec2 initial = Vec2::Zero();  // the centre of mass where the scene puts it, m
    BodyState state;
    // A moving obstacle with a motion law (walls.obstacles[k].motion): a contact partner of
    // infinite mass whose state is the law's pose; not integrated, no load of its own.
    bool kinematic = false;
    WallMotion motion;
  };
  // One contact point: the normal force on body `a` is along `normal`, on `b` (-1: a fixed wall) opposite.
  struct Contact {
    int a = 0, b = -1;
    Vec2 point = Vec2::Zero();
    Vec2 normal = Vec2::Zero();
    double overlap = 0.0;               // m
    std::array<std::int64_t, 4> key{};  // identifies the contact from step to step (its spring)
  };
  void sub_step(double h, const std::vector<Vec2>& fluid_force, const std::vector<double>& fluid_torque);
  Body shaped_body(const Scene& scene, std::size_t k, double density) const;
  void add_kinematic_partners(const Scene& scene);
  void follow_laws(double t);
  void find_contacts(std::vector<Contact>& contacts) const;
  void wall_contacts(int a, std::vector<Contact>& contacts) const;
  void body_contacts(int a, int b, std::vector<Contact>& contacts) const;
  Polygon current_shape(const Body& body) const;
  Vec2 point_velocity(int b, const Vec2& x) const;
  void apply_contact(const Contact& c, double h, std::vector<Vec2>& force, std::vector<double>& torque,
                     std::map<std::array<std::int64_t, 4>, double>& springs) const;

  std::vector<Body> bodies_;  // the rigid bodies, then the kinematic partners (from dynamic_count_ on)
  std::size_t dynamic_count_ = 0;
  double time_ = 0.0;               // s, the time of the bodies' state (the motion laws' clock)
  std::vector<WallSegment> walls_;  // the fixed wall surfaces
  std::vector<Vec2> fixed_apexes_;  // their convex vertices (convex_wall_vertices), m
  ContactControl contact_;
  Vec2 gravity_ = Vec2::Zero();
  double contact_step_ = 0.0;                              // h_c, s
  std::map<std::array<std::int64_t, 4>, double> springs_;  // tangential spring xi per contact, m
};

}  // namespace mps_lab
