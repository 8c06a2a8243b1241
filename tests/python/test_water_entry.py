"""The water-entry study (analysis/mps_lab/studies/water_entry.py): the references' closed forms,
the filter, the measures on a synthetic curve, the large-tank arguments, and one table row from a
real (short, coarse) run of every registered method.

Run by CTest with Debian's python3; MPS_LAB_BINARY names build/mps_lab.
"""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
from mps_lab.methods import registered_methods  # noqa: E402
from mps_lab.studies import water_entry  # noqa: E402

BINARY = os.environ.get("MPS_LAB_BINARY", os.path.join(ROOT, "build", "mps_lab"))
SCENE = os.path.join(ROOT, "scenes", "water_entry.json")


class ClosedFormTest(unittest.TestCase):
    def test_campbell_weynberg_and_its_mean(self):
        # 5.15/2.9 + 0.055 at d/D = 0.1, 5.15/10.5 + 0.275 at 0.5; the closed-form mean against
        # the midpoint rule on 4000 intervals (error ~ 1e-7).
        self.assertAlmostEqual(float(water_entry.campbell_weynberg(0.1)), 5.15 / 2.9 + 0.055, places=12)
        self.assertAlmostEqual(float(water_entry.campbell_weynberg(0.5)), 5.15 / 10.5 + 0.275, places=12)
        x = 0.1 + (np.arange(4000) + 0.5) * 1e-4
        self.assertAlmostEqual(water_entry.fit_mean(0.1, 0.5), float(water_entry.campbell_weynberg(x).mean()), places=6)
        self.assertAlmostEqual(water_entry.fit_mean(), 1.0369, places=4)

    def test_segment_area(self):
        # Half a circle at d = r, the whole at d = 2 r, nothing above the surface.
        r = 0.055
        self.assertAlmostEqual(float(water_entry.segment_area(r, r)), math.pi * r * r / 2.0, places=14)
        self.assertAlmostEqual(float(water_entry.segment_area(2.0 * r, r)), math.pi * r * r, places=14)
        self.assertEqual(float(water_entry.segment_area(-0.01, r)), 0.0)

    def test_moving_mean_is_a_centred_box(self):
        # f = t on t = 0..10: inside, the window's mean is t itself; at t = 0 (window 4) the mean
        # of 0, 1, 2 is 1.
        t = np.arange(11.0)
        mean = water_entry.moving_mean(t, t.copy(), 4.0)
        np.testing.assert_allclose(mean[2:9], t[2:9])
        self.assertAlmostEqual(mean[0], 1.0)

    def test_measures_of_the_fit_itself(self):
        # A curve equal to the fit: ratio 1, RMS 0; its peak at the first row.
        x = np.linspace(0.0, 0.7, 701)
        cs = water_entry.campbell_weynberg(x)
        measures = water_entry.curve_measures(x, cs, cs, np.zeros_like(x))
        self.assertAlmostEqual(measures["mean_ratio"], 1.0, places=5)
        self.assertAlmostEqual(measures["rms_relative"], 0.0, places=12)
        self.assertAlmostEqual(measures["peak_at"], 0.0)

    def test_large_tank_keeps_the_cylinder_over_the_same_water(self):
        # 2 D = 0.22 m on each side and below: domain 1.32 x 0.68, block 1.32 x 0.5505, centre
        # (0.66, 0.615), so the gap between the cylinder and the water is the scene's.
        arguments = water_entry.large_tank_arguments(SCENE)
        sets = dict(a.split("=", 1) for a in arguments[1::2])
        self.assertEqual(json.loads(sets["domain.max"]), [1.32, 0.68])
        self.assertEqual(json.loads(sets["fluid_blocks.0.max"]), [1.32, 0.5505])
        self.assertEqual(json.loads(sets["walls.obstacles.0.circle.centre"]), [0.66, 0.615])


class RealRunTest(unittest.TestCase):
    def test_every_method_gives_a_row(self):
        # D/l0 = 11 to t = 0.012 s (bottom at d/D = 0.15): a method that moves walls and reports
        # loads gets a mean C_s (finite); one that does not is "unsupported" (exit 2) or "no loads".
        methods = registered_methods(BINARY)
        with tempfile.TemporaryDirectory() as out:
            for method in methods:
                folder = os.path.join(out, method)
                arguments = water_entry.case_arguments(SCENE, method, 11, folder, 0.11)
                arguments += ["--set", "time.end_time=0.012"]
                result = subprocess.run([BINARY] + arguments, capture_output=True, text=True,
                                        env=dict(os.environ, OMP_NUM_THREADS="1"))
                row = water_entry.row_of(folder, {"tank": "scene", "method": method, "D_over_l0": 11},
                                         water_entry.DEFAULT_WINDOW, result.returncode)
                self.assertIn(row["status"], ("completed", "unsupported", "no loads"), msg=f"{method}: {row}")
                if row["status"] == "completed":
                    self.assertTrue(math.isfinite(row["mean_cs"]), msg=f"{method}: {row}")
                else:
                    self.assertNotIn("mean_cs", row)


if __name__ == "__main__":
    unittest.main()
