"""Linear potential flow around a heaving 2-D section: added mass and radiation damping.

The frequency-domain radiation problem of a body heaving with unit velocity Re{e^{-i w t}} at the
free surface of water of depth h (Wehausen & Laitone 1960, sec. 13; Newman 1977, "Marine
Hydromechanics", ch. 6; Faltinsen 1990, "Sea Loads on Ships and Offshore Structures", ch. 3),
solved by a boundary-element method of constant straight panels with the Rankine source
G = ln(r) / (2 pi) (the "Rankine panel method" of Faltinsen 1990, sec. 3.4, and of Yeung 1982):

    (1/2) phi(p) = integral over the boundary of [phi dG/dn - G dphi/dn] ds      (n out of the water)

on the closed boundary of a truncated domain |x| <= L:
    free surface   y = 0          dphi/dn = (w^2 / g) phi           (linearised, Robin)
                                  or phi = 0 (w -> infinity, `infinite_frequency`: Dirichlet)
    bed            y = -h         dphi/dn = 0
    body (wetted)                 dphi/dn = n_y                     (the body's normal velocity)
    x = +-L                       dphi/dn = i k phi                 (outgoing waves, w^2 = g k tanh k h)
The evanescent modes decay as exp(-k_n |x|), k_n h >= pi, so |x| - B/2 >= 3 h leaves them below
1e-4 at the truncation.

The pressure is p = i w rho phi; the heave force per unit velocity amplitude is
    F = i w rho integral(phi n_y ds) = i w a33 - b33,
so a33 = rho Re(integral phi n_y ds) (kg/m) and b33 = w rho Im(integral phi n_y ds) (kg/(m s)).

`natural_heave` solves T = 2 pi sqrt((m + a33(w)) / (rho g B)) for a floating box with the
added mass at its own frequency (the undamped natural period of the linear equation of heave),
and gives zeta = b33 / (2 (m + a33) w).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

GRAVITY = 9.81  # m/s^2


@dataclass
class Panels:
    """Straight panels: end points a, b (m), the kind of boundary and, on the body, n_y."""

    a: np.ndarray  # (N, 2)
    b: np.ndarray  # (N, 2)
    kind: np.ndarray  # (N,) str: "surface", "bed", "body", "radiation"

    @property
    def middle(self) -> np.ndarray:
        return 0.5 * (self.a + self.b)

    @property
    def length(self) -> np.ndarray:
        return np.linalg.norm(self.b - self.a, axis=1)

    @property
    def normal(self) -> np.ndarray:
        """Unit normal out of the water: the boundary runs counter-clockwise around the water,
        so the outward normal is the tangent turned clockwise."""
        t = (self.b - self.a) / self.length[:, None]
        return np.stack([t[:, 1], -t[:, 0]], axis=1)


def _segment(p0, p1, count, kind):
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    s = np.linspace(0.0, 1.0, count + 1)
    points = p0[None, :] + s[:, None] * (p1 - p0)[None, :]
    return points[:-1], points[1:], [kind] * count


def _graded(p0, p1, count, kind, near_start):
    """Panels refined towards one end (cosine spacing): the free surface near the body."""
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    u = np.linspace(0.0, 1.0, count + 1)
    s = 1.0 - np.cos(0.5 * math.pi * u) if near_start else np.sin(0.5 * math.pi * u)
    points = p0[None, :] + s[:, None] * (p1 - p0)[None, :]
    return points[:-1], points[1:], [kind] * count


def box_section_panels(beam, draft, depth, half_width, per_metre):
    """The boundary of the water around a rectangular section of `beam` x `draft` (m) centred at
    x = 0 in water of `depth`, truncated at |x| = half_width, about `per_metre` panels per metre on
    the body (and proportionally elsewhere), counter-clockwise around the water."""
    n_body = max(4, int(round(per_metre * beam)))
    n_side = max(2, int(round(per_metre * draft)))
    n_surface = max(8, int(round(per_metre * (half_width - beam / 2) / 4)))
    n_bed = max(8, int(round(per_metre * 2 * half_width / 8)))
    n_end = max(4, int(round(per_metre * depth / 4)))
    pieces = [
        _segment((-half_width, -depth), (half_width, -depth), n_bed, "bed"),  # bed, left to right
        _segment((half_width, -depth), (half_width, 0.0), n_end, "radiation"),  # right end, upwards
        _graded((half_width, 0.0), (beam / 2, 0.0), n_surface, "surface", near_start=False),  # towards the body
        _segment((beam / 2, 0.0), (beam / 2, -draft), n_side, "body"),  # the body: right side down,
        _segment((beam / 2, -draft), (-beam / 2, -draft), n_body, "body"),  # bottom right to left,
        _segment((-beam / 2, -draft), (-beam / 2, 0.0), n_side, "body"),  # left side up
        _graded((-beam / 2, 0.0), (-half_width, 0.0), n_surface, "surface", near_start=True),
        _segment((-half_width, 0.0), (-half_width, -depth), n_end, "radiation"),  # left end, downwards
    ]
    return Panels(np.concatenate([p[0] for p in pieces]), np.concatenate([p[1] for p in pieces]),
                  np.array(sum((p[2] for p in pieces), [])))


def semicircle_panels(radius, depth, half_width, count):
    """The water around a half-immersed circular cylinder (the check of the infinite-frequency
    limit): the wetted half circle in `count` panels, counter-clockwise around the water."""
    angles = np.linspace(0.0, -math.pi, count + 1)  # from (r, 0) down round to (-r, 0)
    arc = np.stack([radius * np.cos(angles), radius * np.sin(angles)], axis=1)
    per_metre = count / (math.pi * radius)
    n_surface = max(8, int(round(per_metre * (half_width - radius) / 4)))
    n_bed = max(8, int(round(per_metre * 2 * half_width / 8)))
    n_end = max(4, int(round(per_metre * depth / 4)))
    pieces = [
        _segment((-half_width, -depth), (half_width, -depth), n_bed, "bed"),
        _segment((half_width, -depth), (half_width, 0.0), n_end, "radiation"),
        _graded((half_width, 0.0), (radius, 0.0), n_surface, "surface", near_start=False),
        (arc[:-1], arc[1:], ["body"] * count),
        _graded((-radius, 0.0), (-half_width, 0.0), n_surface, "surface", near_start=True),
        _segment((-half_width, 0.0), (-half_width, -depth), n_end, "radiation"),
    ]
    return Panels(np.concatenate([p[0] for p in pieces]), np.concatenate([p[1] for p in pieces]),
                  np.array(sum((p[2] for p in pieces), [])))


def influence(panels: Panels):
    """H_ij = integral over panel j of dG/dn_q, G_ij = integral over panel j of G, at the middle of
    panel i, G = ln(r) / (2 pi): both in closed form for a straight panel. H is the angle the
    panel subtends at the point over 2 pi (signed: counter-clockwise positive; rows sum to 1/2); the
    integral of ln r along a line is s ln r - s + d atan(s / d) between the panel's ends."""
    p = panels.middle[:, None, :]  # (N, 1, 2)
    a = panels.a[None, :, :] - p  # (N, N, 2): a - p
    b = panels.b[None, :, :] - p
    cross = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    dot = (a * b).sum(axis=-1)
    angle = np.arctan2(cross, dot)
    np.fill_diagonal(angle, 0.0)  # the point on its own straight panel
    H = angle / (2.0 * math.pi)
    length = panels.length[None, :]
    t = (panels.b - panels.a)[None, :, :] / length[..., None]
    s1 = (a * t).sum(axis=-1)  # along the panel from the foot of the point, m
    s2 = s1 + length
    d = np.abs(a[..., 0] * t[..., 1] - a[..., 1] * t[..., 0])  # distance to the panel's line, m

    def primitive(s):
        r2 = s * s + d * d
        with np.errstate(divide="ignore", invalid="ignore"):
            log_term = np.where(r2 > 0.0, 0.5 * s * np.log(np.where(r2 > 0.0, r2, 1.0)), 0.0)
            atan_term = np.where(d > 0.0, d * np.arctan(s / np.where(d > 0.0, d, 1.0)), 0.0)
        return log_term - s + atan_term

    G = (primitive(s2) - primitive(s1)) / (2.0 * math.pi)
    return H, G


def wave_number(omega, depth):
    """k of w^2 = g k tanh(k h), by Newton from the deep-water value (1/m)."""
    k = max(omega * omega / GRAVITY, omega / math.sqrt(GRAVITY * depth))
    for _ in range(100):
        f = GRAVITY * k * math.tanh(k * depth) - omega * omega
        df = GRAVITY * (math.tanh(k * depth) + k * depth / math.cosh(k * depth) ** 2)
        step = f / df
        k -= step
        if abs(step) < 1e-14 * k:
            break
    return k


def solve_radiation(panels: Panels, omega, depth, density=1000.0, infinite_frequency=False):
    """phi on every panel (complex) of the heave radiation problem, and (a33, b33, phi)."""
    H, G = influence(panels)
    n = len(panels.kind)
    normal_y = panels.normal[:, 1]
    robin = np.zeros(n, complex)  # dphi/dn = robin phi + given
    given = np.zeros(n, complex)
    body = panels.kind == "body"
    given[body] = normal_y[body]
    k = wave_number(omega, depth) if not infinite_frequency else 0.0
    robin[panels.kind == "radiation"] = 1j * k
    dirichlet = (panels.kind == "surface") & infinite_frequency
    robin[(panels.kind == "surface") & ~dirichlet] = omega * omega / GRAVITY
    # Unknowns: phi on Robin panels, q = dphi/dn on Dirichlet (phi = 0) ones.
    #   (1/2) phi_i - sum_j H_ij phi_j + sum_j G_ij q_j = 0,  q_j = robin_j phi_j + given_j
    A = np.zeros((n, n), complex)
    rhs = -(G @ given)
    free = ~dirichlet
    A[:, free] = -H[:, free] + G[:, free] * robin[None, free]
    A[np.arange(n), np.arange(n)] += np.where(free, 0.5, 0.0)
    A[:, dirichlet] = G[:, dirichlet]
    u = np.linalg.solve(A, rhs)
    phi = np.where(free, u, 0.0)
    integral = np.sum(phi[body] * normal_y[body] * panels.length[body])
    a33 = density * integral.real
    b33 = omega * density * integral.imag
    return a33, b33, phi


def radiated_wave_amplitude(panels: Panels, phi, omega):
    """|eta| of the outgoing wave at each truncation (left, right), m per m/s of heave velocity:
    eta = (i w / g) phi at the free surface, taken at the surface panel next to each end."""
    surface = np.where(panels.kind == "surface")[0]
    x = panels.middle[surface, 0]
    left, right = surface[np.argmin(x)], surface[np.argmax(x)]
    return tuple(abs(1j * omega / GRAVITY * phi[j]) for j in (left, right))


def group_velocity(omega, depth):
    k = wave_number(omega, depth)
    return 0.5 * omega / k * (1.0 + 2.0 * k * depth / math.sinh(2.0 * k * depth))


@dataclass
class Heave:
    period: float  # s, undamped natural period with a33 at its own frequency
    omega: float  # rad/s
    added_mass: float  # kg/m
    damping: float  # kg/(m s)
    zeta: float  # b33 / (2 (m + a33) w)


def natural_heave(beam, draft, depth, mass, density=1000.0, half_width=None, per_metre=200, tolerance=1e-10):
    """The floating box's linear heave: w = sqrt(rho g B / (m + a33(w))), by fixed-point iteration
    from the infinite-frequency added mass (mass in kg/m, lengths in m)."""
    half_width = half_width if half_width is not None else beam / 2 + 4.0 * depth
    panels = box_section_panels(beam, draft, depth, half_width, per_metre)
    stiffness = density * GRAVITY * beam  # N/m per m
    a33, _, _ = solve_radiation(panels, 10.0, depth, density, infinite_frequency=True)
    omega = math.sqrt(stiffness / (mass + a33))
    for _ in range(100):
        a33, b33, _ = solve_radiation(panels, omega, depth, density)
        updated = math.sqrt(stiffness / (mass + a33))
        converged = abs(updated - omega) < tolerance * omega
        omega = updated
        if converged:
            break
    a33, b33, _ = solve_radiation(panels, omega, depth, density)
    return Heave(2.0 * math.pi / omega, omega, a33, b33, b33 / (2.0 * (mass + a33) * omega))


def tank_panels(beam, draft, depth, tank_width, per_metre):
    """The water of a closed tank (vertical walls at x = +-tank_width/2, bed at y = -depth) around a
    rectangular section centred in it, counter-clockwise: bed, right wall, surface, body, surface,
    left wall. The walls are "wall" panels (dphi/dn = 0)."""
    half = tank_width / 2
    n_body = max(4, int(round(per_metre * beam)))
    n_side = max(2, int(round(per_metre * draft)))
    n_surface = max(8, int(round(per_metre * (half - beam / 2) / 2)))
    n_bed = max(8, int(round(per_metre * tank_width / 4)))
    n_wall = max(4, int(round(per_metre * depth / 2)))
    pieces = [
        _segment((-half, -depth), (half, -depth), n_bed, "bed"),
        _segment((half, -depth), (half, 0.0), n_wall, "wall"),
        _segment((half, 0.0), (beam / 2, 0.0), n_surface, "surface"),
        _segment((beam / 2, 0.0), (beam / 2, -draft), n_side, "body"),
        _segment((beam / 2, -draft), (-beam / 2, -draft), n_body, "body"),
        _segment((-beam / 2, -draft), (-beam / 2, 0.0), n_side, "body"),
        _segment((-beam / 2, 0.0), (-half, 0.0), n_surface, "surface"),
        _segment((-half, 0.0), (-half, -depth), n_wall, "wall"),
    ]
    return Panels(np.concatenate([p[0] for p in pieces]), np.concatenate([p[1] for p in pieces]),
                  np.array(sum((p[2] for p in pieces), [])))


class TankDecay:
    """The linear free decay of a floating box in a closed tank, in the time domain: the same
    boundary integral equation at every instant with phi given on the free surface (Dirichlet) and
    dphi/dn on the rest (Neumann), the linearised free-surface conditions
        d eta / dt = dphi/dn,   d phi / dt = -g eta          (on y = 0)
    and the body's heave equation with the acceleration potential split as phi_t = psi0 + a psi1
    (psi1: unit body acceleration, phi = 0 on the surface; psi0: phi_t = -g eta there, the body at
    rest; Tanizawa 1995's and Cummins 1962's decomposition):
        (m + a33_inf) a = -rho g B x - rho integral(psi0 n_y ds).
    The geometry is the mean one (linear theory: small motions); RK4 in time. The tank's walls
    reflect the radiated waves as the particle runs' walls do."""

    def __init__(self, beam, draft, depth, tank_width, mass, density=1000.0, per_metre=200):
        self.panels = tank_panels(beam, draft, depth, tank_width, per_metre)
        self.beam, self.mass, self.density = beam, mass, density
        H, G = influence(self.panels)
        kind = self.panels.kind
        self.surface = kind == "surface"
        self.body = kind == "body"
        self.normal_y = self.panels.normal[:, 1]
        n = len(kind)
        neumann = ~self.surface
        A = np.zeros((n, n))
        A[:, neumann] = -H[:, neumann]
        A[np.arange(n), np.arange(n)] += np.where(neumann, 0.5, 0.0)
        A[:, self.surface] = G[:, self.surface]
        self.inverse = np.linalg.inv(A)
        self.H, self.G, self.neumann = H, G, neumann
        psi1 = self._solve(np.zeros(self.surface.sum()), np.where(self.body, self.normal_y, 0.0))
        self.added_mass_infinite = density * self._body_integral(psi1[0])

    def _solve(self, surface_phi, normal_derivative):
        """(phi on every panel, dphi/dn on every panel) with phi given on the surface and dphi/dn
        on the others: (1/2) phi_i - sum H_ij phi_j + sum G_ij q_j = 0."""
        f = np.zeros(len(self.panels.kind))
        f[self.surface] = surface_phi
        g = np.where(self.neumann, normal_derivative, 0.0)
        rhs = self.H[:, self.surface] @ f[self.surface] - np.where(self.surface, 0.5 * f, 0.0) - self.G[:, self.neumann] @ g[self.neumann]
        u = self.inverse @ rhs
        phi = np.where(self.surface, f, u)
        q = np.where(self.surface, u, g)
        return phi, q

    def _body_integral(self, phi):
        return float(np.sum(phi[self.body] * self.normal_y[self.body] * self.panels.length[self.body]))

    def _rates(self, state):
        eta, phi_s, x, v = state
        _, q = self._solve(phi_s, np.where(self.body, v * self.normal_y, 0.0))
        psi0, _ = self._solve(-GRAVITY * eta, np.zeros(len(self.panels.kind)))
        force = -self.density * GRAVITY * self.beam * x - self.density * self._body_integral(psi0)
        acceleration = force / (self.mass + self.added_mass_infinite)
        return (q[self.surface], -GRAVITY * eta, v, acceleration)

    def run(self, release_offset, end_time, time_step):
        """Times (s) and the body's displacement from rest (m), released at rest `release_offset`
        (m, negative: below its rest position) with the water at rest."""
        n_surface = int(self.surface.sum())
        state = (np.zeros(n_surface), np.zeros(n_surface), float(release_offset), 0.0)
        times, heave = [0.0], [float(release_offset)]
        steps = int(round(end_time / time_step))
        for step in range(steps):
            k1 = self._rates(state)
            k2 = self._rates(tuple(s + 0.5 * time_step * k for s, k in zip(state, k1)))
            k3 = self._rates(tuple(s + 0.5 * time_step * k for s, k in zip(state, k2)))
            k4 = self._rates(tuple(s + time_step * k for s, k in zip(state, k3)))
            state = tuple(s + time_step / 6.0 * (a + 2 * b + 2 * c + d) for s, a, b, c, d in zip(state, k1, k2, k3, k4))
            times.append((step + 1) * time_step)
            heave.append(state[2])
        return np.array(times), np.array(heave)
