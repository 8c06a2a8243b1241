"""The floating-bodies study (analysis/floating_bodies.py, analysis/mps_lab/studies/floating.py):
its theory functions against closed forms, the heave fit on a synthetic damped oscillation, and
a tiny run of the script (one method, a short end time) that writes its tables and figure. Run
by CTest; MPS_LAB_BINARY names build/mps_lab."""
from __future__ import annotations

import csv
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
from mps_lab import radiation  # noqa: E402
from mps_lab.studies import floating, heave_theory  # noqa: E402

BINARY = os.environ.get("MPS_LAB_BINARY", os.path.join(ROOT, "build", "mps_lab"))


def scene_geometry(name: str) -> dict:
    with open(os.path.join(ROOT, "scenes", name)) as handle:
        return floating.scene_geometry(json.load(handle))


class TheoryTest(unittest.TestCase):
    def test_lewis_form_of_a_semicircle_and_the_box(self):
        # A semicircle (H0 = 1, sigma = pi/4) is the Lewis form a1 = a3 = 0, C = 1 (a33 = rho pi B^2/8).
        a1, a3 = floating.lewis_coefficients(1.0, math.pi / 4)
        self.assertAlmostEqual(a1, 0.0, places=8)
        self.assertAlmostEqual(a3, 0.0, places=8)
        # The heave scene's box (B/d = 4, sigma = 1): a33(inf) = 19.7 kg/m (docs/bodies.md).
        self.assertAlmostEqual(floating.heave_added_mass_infinite(scene_geometry("floating_box_heave.json")), 19.748,
                               places=2)

    def test_heave_band_and_drag_speed(self):
        theory = floating.heave_theory(scene_geometry("floating_box_heave.json"))
        self.assertAlmostEqual(theory["draft"], 0.05, places=12)
        self.assertAlmostEqual(theory["period_low"], 0.6630, places=3)
        self.assertAlmostEqual(theory["period_high"], 0.7737, places=3)
        rising = scene_geometry("rising_box.json")
        # U = sqrt(2 * 0.5 * 9.81 * 0.06 / 2) = 0.5425 m/s; blockage (6/5)^2 on C_d: U / 1.2.
        self.assertAlmostEqual(floating.drag_speed(rising), math.sqrt(0.2943), places=10)
        self.assertAlmostEqual(floating.drag_speed(rising, floating.blocked_drag_coefficient(rising)),
                               math.sqrt(0.2943) / 1.2, places=10)

    def test_fit_recovers_a_damped_oscillation(self):
        t = np.linspace(0.0, 1.0, 501)
        omega_n, zeta = 2 * math.pi / 0.75, 0.15
        omega_d = omega_n * math.sqrt(1 - zeta * zeta)
        y = 0.29 - 0.02 * np.exp(-zeta * omega_n * t) * np.cos(omega_d * t)
        fit = floating.fit_damped_heave(t, y)
        # The fit's last grid steps: omega 0.0016 rad/s (period 2e-4 s), decay 0.002 1/s (zeta 2.4e-4).
        self.assertAlmostEqual(fit["period"], 2 * math.pi / omega_d, delta=3e-4)
        self.assertAlmostEqual(fit["damping_ratio"], zeta, delta=3e-4)
        self.assertAlmostEqual(fit["y0"], 0.29, places=6)


class RadiationTest(unittest.TestCase):
    """analysis/mps_lab/radiation.py, the linear-theory reference of the heave (docs/bodies.md,
    "Linear theory"): each check fails when its formula or sign changes."""

    def test_a_closed_boundary_sees_half_a_turn(self):
        # Gauss: for phi = 1 the boundary equation reads 1/2 = sum_j H_ij at every panel.
        panels = radiation.box_section_panels(0.2, 0.05, 0.3, 1.5, 100)
        H, _ = radiation.influence(panels)
        np.testing.assert_allclose(H.sum(axis=1), 0.5, atol=1e-12)

    def test_infinite_frequency_semicircle_is_half_the_circle(self):
        # phi = 0 on the surface: the half-immersed circle's heave is half of a circle's translation,
        # a33 = rho pi r^2 / 2 (the double-body flow). Measured 0.9992 with 32 panels (the bed and
        # the ends 40 r away add < 0.1 %): 0.5 % allowed.
        panels = radiation.semicircle_panels(0.1, 4.0, 4.0, 32)
        a33, _, _ = radiation.solve_radiation(panels, 10.0, 4.0, infinite_frequency=True)
        self.assertAlmostEqual(a33 / (1000.0 * math.pi * 0.01 / 2), 1.0, delta=0.005)

    def test_radiation_damping_is_the_energy_of_the_waves(self):
        # The power the heave puts in, b33 |V|^2 / 2, leaves as the two waves' energy flux,
        # rho g |A|^2 c_g / 2 each: b33 = rho g c_g (|A_left|^2 + |A_right|^2). Measured 0.2 % apart
        # at 200 panels per metre: 1 % allowed. The added mass at this frequency lies below a33(inf)
        # (the dip of the 2-D heave curves, Vugts 1968): measured 14.1 against 23.1 kg/m.
        depth, omega = 0.288, 8.96
        panels = radiation.box_section_panels(0.2, 0.05, depth, 0.1 + 4 * depth, 200)
        a33, b33, phi = radiation.solve_radiation(panels, omega, depth)
        left, right = radiation.radiated_wave_amplitude(panels, phi, omega)
        flux = 1000.0 * radiation.GRAVITY * radiation.group_velocity(omega, depth) * (left ** 2 + right ** 2)
        self.assertGreater(b33, 0.0)
        self.assertAlmostEqual(b33 / flux, 1.0, delta=0.01)
        self.assertAlmostEqual(left, right, delta=1e-3 * left)  # a symmetric body radiates symmetric waves
        infinite, _, _ = radiation.solve_radiation(panels, 10.0, depth, infinite_frequency=True)
        self.assertLess(a33, 0.8 * infinite)

    def test_natural_period_converges_with_the_panels(self):
        # 100 -> 200 panels per metre change T_n by 0.27 %, 200 -> 400 by 0.06 %: the reference
        # (200) is within 0.1 % of its limit.
        periods = [radiation.natural_heave(0.2, 0.05, 0.288, 10.0, per_metre=n).period for n in (100, 200)]
        self.assertLess(abs(periods[1] / periods[0] - 1.0), 0.005)
        self.assertAlmostEqual(periods[1], 0.6969, delta=0.002)

    def test_time_domain_agrees_with_the_frequency_domain_without_walls(self):
        # In a tank 6 m wide no reflection is back within the 1.5 s fitted: the linear free decay is
        # the open-water one. Fitted as the particle runs are, its natural period is 0.683 s (60
        # panels per metre) against the frequency domain's 0.699 s, zeta 0.156 against 0.171 (0.98
        # and 0.91 of it): one damped sine does not hold the frequency-dependent added mass exactly
        # (the memory of the radiated waves; Cummins 1962). 5 % and 20 % allowed.
        tank = radiation.TankDecay(0.2, 0.05, 0.288, 6.0, 10.0, per_metre=60)
        t, x = tank.run(-0.02, 1.5, 0.003)
        fit = floating.fit_damped_heave(t, x)
        heave = radiation.natural_heave(0.2, 0.05, 0.288, 10.0, per_metre=100)
        self.assertAlmostEqual(fit["natural_period"] / heave.period, 1.0, delta=0.05)
        self.assertAlmostEqual(fit["damping_ratio"] / heave.zeta, 1.0, delta=0.2)

    def test_the_tank_walls_lengthen_the_first_period(self):
        # The spec's tank (6 B) at l0 = 0.025 m: its reflections and its sloshing mode (0.92 s) are
        # inside the first second; the fitted period is 0.783 s against 0.699 s in open water.
        with open(os.path.join(ROOT, "scenes", "floating_box_heave.json")) as handle:
            geometry = floating.scene_geometry(json.load(handle))
        ref = heave_theory.reference(geometry, 0.025, 0.28165, -0.011649)
        self.assertAlmostEqual(ref["tank_period"], 0.7830, delta=0.002)
        self.assertAlmostEqual(ref["open_water_period"], 0.6987, delta=0.002)
        self.assertGreater(ref["tank_period"], 1.1 * ref["open_water_period"])


class ScriptTest(unittest.TestCase):
    def setUp(self):
        self.out = tempfile.mkdtemp(prefix="mps_lab_floating_")

    def tearDown(self):
        shutil.rmtree(self.out, ignore_errors=True)

    def test_a_method_that_cannot_move_a_body_is_listed_with_its_error(self):
        # wcsph does not use the walls' velocity: every case stops at start (exit 2), and the table
        # says so instead of a number.
        result = subprocess.run([sys.executable, os.path.join(ROOT, "analysis", "floating_bodies.py"), "--out", self.out,
                                 "--binary", BINARY, "--methods", "wcsph", "--cases", "heave",
                                 "--heave-spacings", "0.025"], capture_output=True, text=True)
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(os.path.join(self.out, "floating_box_heave.csv"), newline="") as handle:
            rows = list(csv.DictReader(handle))
        self.assertEqual(len(rows), 1)
        self.assertTrue(rows[0]["status"].startswith("cannot run"), rows[0]["status"])
        self.assertIn("walls.obstacles[0].body", rows[0]["status"])
        self.assertTrue(os.path.exists(os.path.join(self.out, "floating_bodies.png")))

    def test_the_linear_theory_script_compares_each_run_with_its_tank(self):
        # One run's row (dfsph at l0 = 0.025 m, as in docs/data/floating_box_heave.csv): the script
        # writes the reference at that spacing and the run's period over it (0.789 / 0.783 s).
        source = os.path.join(self.out, "heave.csv")
        with open(os.path.join(ROOT, "docs", "data", "floating_box_heave.csv"), newline="") as handle:
            rows = list(csv.DictReader(handle))
        with open(source, "w", newline="") as handle:
            writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
            writer.writeheader()
            writer.writerow(next(r for r in rows if r["method"] == "dfsph" and r["l0"] == "0.025"))
        result = subprocess.run([sys.executable, os.path.join(ROOT, "analysis", "heave_linear_theory.py"),
                                 "--heave-csv", source, "--out", self.out], capture_output=True, text=True)
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(os.path.join(self.out, "data", "heave_vs_linear_theory.csv"), newline="") as handle:
            comparison = list(csv.DictReader(handle))
        self.assertEqual(len(comparison), 1)
        self.assertAlmostEqual(float(comparison[0]["tank_period"]), 0.7830, delta=0.002)
        self.assertAlmostEqual(float(comparison[0]["period_ratio"]), 0.789 / 0.783, delta=0.005)
        self.assertTrue(os.path.exists(os.path.join(self.out, "figures", "heave_linear_theory.png")))


if __name__ == "__main__":
    unittest.main()
