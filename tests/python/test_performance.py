"""The performance study (analysis/performance.py, analysis/mps_lab/studies/performance.py) on
a tiny real study (--quick: the dam break at l0 = 0.025 for mps and isph, one bench
resolution, scaling at l0 = 0.01 with 1 and 2 threads): the CSV, JSON, tables and figures are
written; the ratio against the reference figure is the measured speed over 0.23 M; the
scaling summary's spread and the speed-ups on synthetic cases with known answers. Run by
CTest; MPS_LAB_BINARY names build/mps_lab."""
from __future__ import annotations

import csv
import os
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
from mps_lab import methods  # noqa: E402
from mps_lab.studies import performance  # noqa: E402

BINARY = os.environ.get("MPS_LAB_BINARY", os.path.join(ROOT, "build", "mps_lab"))


class PerformanceStudyTest(unittest.TestCase):
    def test_quick_study_writes_tables_and_figures(self):
        with tempfile.TemporaryDirectory() as out:
            subprocess.run([sys.executable, os.path.join(ROOT, "analysis", "performance.py"), "--out", out, "--quick",
                            "--binary", BINARY], check=True, capture_output=True)
            with open(os.path.join(out, "reference.csv"), newline="") as handle:
                rows = list(csv.DictReader(handle))
            # The quick plan's runs whose method this build registers (a subset build may lack isph).
            registered = set(methods.registered_methods(BINARY))
            expected = [(m, 0.025) for m in ("mps", "isph") if m in registered]
            self.assertEqual([(r["method"], float(r["particle_spacing"])) for r in rows], expected)
            for row in rows:
                self.assertEqual(row["status"], "completed")
                self.assertEqual(int(row["steps"]), 40)  # 0.02 s at 5e-4 s
                self.assertGreater(float(row["ms_pressure_solve"]), 0.0)
            with open(os.path.join(out, "performance.md")) as handle:
                table = handle.read()
            speed = float(rows[0]["particle_steps_per_second"])
            self.assertIn(f"{speed / 0.23e6:.2f}x", table)
            self.assertIn("## Scaling", table)
            self.assertIn("Speed-up from 1 to 2 threads", table)
            for name in ["resolutions.json", "scaling.json", "performance_scaling.png", "performance_phases.png"]:
                self.assertTrue(os.path.getsize(os.path.join(out, name)) > 0, name)

    def test_scaling_summary_and_speedups(self):
        cases = [dict(kind="steps", method="mps", threads=t, status="completed", fluid_particles=n,
                      nanoseconds_per_particle_step=v, seconds=s)
                 for t, n, v, s in [(2, 1000, 100.0, 1.0), (2, 10000, 120.0, 1.2), (2, 100000, 150.0, 1.5),
                                    (1, 100000, 270.0, 2.7)]]
        rows = performance.scaling_summary(cases)
        two = next(r for r in rows if r["threads"] == 2)
        self.assertEqual(two["median"], 120.0)
        self.assertAlmostEqual(two["low"], 100.0 / 120.0 - 1.0)
        self.assertAlmostEqual(two["high"], 150.0 / 120.0 - 1.0)
        self.assertEqual(performance.speedups(cases), [("mps", 100000, 2.7 / 1.5)])

    def test_plan_follows_the_registered_methods(self):
        """The plan (analysis/sweeps/performance.json) is data: a run or a bench key of a
        method the binary does not register is left out (a subset build)."""
        plan = performance.load_plan(performance.DEFAULT_PLAN)
        self.assertEqual(len(performance.reference_cases(plan, ["mps", "isph", "dfsph"], quick=False)), 9)
        only = performance.reference_cases(plan, ["isph"], quick=False)
        self.assertEqual([(c["method"], c["particle_spacing"]) for c in only],
                         [("isph", 0.025), ("isph", 0.0125), ("isph", 0.005)])
        quick = performance.reference_cases(plan, ["mps", "isph", "dfsph"], quick=True)
        self.assertEqual([(c["method"], c["end_time"]) for c in quick], [("mps", 0.02), ("isph", 0.02)])
        self.assertEqual(performance.bench_per_spacing(plan, ["mps", "isph", "dfsph"]),
                         ["methods.dfsph.max_time_step=1.0"])
        self.assertEqual(performance.bench_per_spacing(plan, ["mps", "isph"]), [])
        figure = performance.reference_figure(plan, "dfsph", 0.005, 1e-4)
        self.assertEqual((figure["code"], figure["particle_steps_per_second"]), ("SPlisHSPlasH DFSPH", 0.5e6))
        self.assertIsNone(performance.reference_figure(plan, "isph", 0.025, None))

    def test_fluid_counts_of_the_scaling_spacings(self):
        self.assertEqual(performance.fluid_count(0.05 / 5), 24 * 49)
        self.assertEqual(performance.fluid_count(0.05 / 142), 709 * 1419)  # 1,006,071


if __name__ == "__main__":
    unittest.main()
