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
from mps_lab.studies import floating  # noqa: E402

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


if __name__ == "__main__":
    unittest.main()
