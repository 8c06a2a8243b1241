"""Every registered method on scenes/dambreak_buchner.json at l0 = H/40 to T = 3.5 (t = 0.866 s):
the impact at probe P1 and the level after it against Buchner (2002). Label "long" (ctest -L long):
the five runs to t = 0.866 s take about 7 minutes together on one thread (half of the full
runs' 850 s, measured on a loaded machine).

Tolerances (docs/validation.md, "Wall pressure: Buchner 2002", measured at l0 = H/40 with
the full runs, which are the same runs up to T = 3.5):
- impact time: the record's 2.478 (read to +-0.02); the methods at H/40 arrive 0.17 to 0.35
  late (dfsph 2.676, eisph 2.663, isph 2.652, mps 2.757, wcsph 2.829: a spread of 0.18
  between methods). The impact time is also sensitive to perturbations at the pressure solver's
  tolerance: mps at H/40, the same scene with runs that differ only there (AMG hierarchy reuse
  budget 0, 4, 8, 16; CG tolerance 1e-8 or 5e-9; 2026-11-27), crosses at 2.814, 2.817, 2.817,
  2.852, 2.940 and 2.959: the flows part at round-off and the tongue that reaches P1 is chaotic.
  |T_impact - 2.478| <= 0.6 holds the largest of these errors (0.48) with a margin of 0.1 and
  still fails a sensor that never wets or an arrival far off (a front twice too slow arrives
  after T = 4.5; a wrong probe height).
- level: mean p/(rho g H) over T in [3.0, 3.5]; the record reads 0.579 there, the methods
  at H/40 0.127 (wcsph) to 0.454 (dfsph) (eisph 0.166, isph 0.214, mps 0.164: all but dfsph
  still rising after their late impact). The band [0.06, 1.0] is half the smallest and
  about twice the largest measured value: it fails a dry or dead sensor and a pressure off by
  a factor of two (dfsph reads 1.5 times hydrostatic with its default boundary model,
  docs/validation.md, and is inside), not the methods' known bias against the record.
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
EXPERIMENT_IMPACT = 2.478  # T, the record's first crossing of 0.1 (tests/python/test_buchner.py)
IMPACT_TOLERANCE = 0.6
LEVEL_WINDOW = (3.0, 3.5)
LEVEL_BAND = (0.06, 1.0)


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
                    self.assertLessEqual(abs(impact - EXPERIMENT_IMPACT), IMPACT_TOLERANCE, f"impact T = {impact}")
                    self.assertTrue(LEVEL_BAND[0] <= level <= LEVEL_BAND[1], f"level = {level}")


if __name__ == "__main__":
    unittest.main()
