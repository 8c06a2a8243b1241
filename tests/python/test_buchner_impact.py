"""Every registered method on scenes/dambreak_buchner.json at l0 = H/40 to T = 3.5 (t = 0.866 s):
the impact at probe P1 and the level after it against Buchner (2002). Label "long" (ctest -L long):
the five runs take about IMPACT_RUN_SECONDS together on one thread of a quiet machine.

Tolerances (docs/validation.md, "Wall pressure: Buchner 2002", the table at l0 = H/40):
- impact time: the experiment's 2.478; measured at H/40 the methods lie in TOLERANCE_NOTE. The
  band [2.35, 2.95] holds them with margin and is what the experiment can tell apart: the
  digitised record has a point every 0.02-0.06 in T around the impact, the release of the
  column takes time (the gate), and the methods' own spread at H/40 is 0.3.
- level over T in [3.0, 3.5]: the experiment reads 0.54-0.64 there; the methods at H/40 read
  LEVEL_NOTE (row means). The band [0.15, 1.2] holds them with margin: it catches a sensor
  that reads 0 or a pressure off by a factor (DFSPH's 1.5 times hydrostatic with its default
  boundary model is inside it; docs/validation.md says why), not the methods' known bias.
"""
from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import unittest

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
from mps_lab import data, pressure  # noqa: E402
from mps_lab.methods import registered_methods  # noqa: E402
from mps_lab.studies import buchner  # noqa: E402

BINARY = os.environ.get("MPS_LAB_BINARY", os.path.join(ROOT, "build", "mps_lab"))
SCENE = os.path.join(ROOT, buchner.SCENE)
END_T = 3.5  # T = t sqrt(g/H)
IMPACT_BAND = (2.35, 2.95)
LEVEL_WINDOW = (3.0, 3.5)
LEVEL_BAND = (0.15, 1.2)


class BuchnerImpactTest(unittest.TestCase):
    def test_every_method_hits_p1_in_time_and_reads_a_level(self):
        validation = pressure.scene_validation(SCENE)
        end_time = END_T / np.sqrt(9.81 / buchner.HEIGHT)
        with tempfile.TemporaryDirectory() as folder:
            for method in registered_methods(BINARY):
                with self.subTest(method=method):
                    out = os.path.join(folder, method)
                    arguments = buchner.case_arguments(SCENE, method, 40, out) + ["--end-time", f"{end_time:.6f}"]
                    result = subprocess.run([BINARY, *arguments], capture_output=True, text=True, timeout=1500)
                    self.assertEqual(result.returncode, 0, result.stderr[-2000:])
                    run = data.load_run(out)
                    t, mean, _ = pressure.run_curves(run, "P1", validation)
                    impact = pressure.crossing_time(t, mean, validation.impact_threshold)
                    window = (t >= LEVEL_WINDOW[0]) & (t <= LEVEL_WINDOW[1])
                    level = float(np.mean(mean[window]))
                    print(f"{method}: P1 impact T = {impact:.3f}, level over T in [3, 3.5] = {level:.3f}")
                    self.assertTrue(IMPACT_BAND[0] <= impact <= IMPACT_BAND[1], f"impact T = {impact}")
                    self.assertTrue(LEVEL_BAND[0] <= level <= LEVEL_BAND[1], f"level = {level}")


if __name__ == "__main__":
    unittest.main()
