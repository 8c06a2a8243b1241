"""The stability map (analysis/stability_map.py) on a tiny real grid: MPS at l0 = 0.05 m with a
small and a huge time step completes and diverges, stability.csv has its columns, the
summary gives the largest stable Courant number, the figure is written and a second call
resumes without running anything; the largest-stable rule on a synthetic table with known
answers. Run by CTest; MPS_LAB_BINARY names build/mps_lab."""
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

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
from mps_lab.studies import stability_map  # noqa: E402

BINARY = os.environ.get("MPS_LAB_BINARY", os.path.join(ROOT, "build", "mps_lab"))
SPEC = {
    "scene": "scenes/dambreak.json",
    "end_time": 0.5,
    "spacings": [0.05],
    "set": {"stability.on_solver_failure": "stop", "output.formats": ["csv"]},
    "maps": {"mps": {"method": "mps", "courant": [0.05, 3.2]}},
}


def synthetic(statuses: dict[float, str], l0: float = 0.025, name: str = "m") -> list[dict]:
    return [{"map": name, "method": "mps", "rule": "courant", "l0": l0, "courant": c, "dt": c * l0 / 3.13,
             "status": s, "stop_event": "" if s == "completed" else "courant", "front_rms": 0.1}
            for c, s in statuses.items()]


class StabilityMapTest(unittest.TestCase):
    def setUp(self):
        self.folder = tempfile.mkdtemp(prefix="mps_lab_stability_map_")
        self.spec = os.path.join(self.folder, "spec.json")
        with open(self.spec, "w") as handle:
            json.dump(SPEC, handle)
        self.out = os.path.join(self.folder, "out")

    def tearDown(self):
        shutil.rmtree(self.folder, ignore_errors=True)

    def map(self, *extra):
        return subprocess.run([sys.executable, os.path.join(ROOT, "analysis", "stability_map.py"), self.spec,
                               "--out", self.out, "--binary", BINARY, *extra], capture_output=True, text=True)

    def table(self, name):
        with open(os.path.join(self.out, name), newline="") as handle:
            reader = csv.DictReader(handle)
            return reader.fieldnames, list(reader)

    def test_small_step_completes_huge_step_diverges(self):
        result = self.map("--parallel", "2")
        self.assertEqual(result.returncode, 0, result.stderr)
        columns, rows = self.table("stability.csv")
        self.assertEqual(columns, stability_map.COLUMNS)
        by_courant = {float(row["courant"]): row for row in rows}
        self.assertEqual(sorted(by_courant), [0.05, 3.2])
        small, huge = by_courant[0.05], by_courant[3.2]
        self.assertEqual(small["status"], "completed", small["message"])
        self.assertEqual(small["stop_event"], "")
        self.assertAlmostEqual(float(small["dt"]), 0.05 * 0.05 / 3.13, places=12)
        self.assertAlmostEqual(float(small["simulated_time"]), 0.5, places=6)
        self.assertTrue(0.0 < float(small["front_rms"]) < 2.0)
        self.assertEqual(huge["status"], "diverged", huge["message"])
        self.assertIn(huge["stop_event"], ("courant", "speed_limited", "energy_growth", "penetration", "escaped",
                                           "density", "non_finite"))
        self.assertIn("diverged at t = ", huge["message"])
        self.assertLess(float(huge["stop_time"]), 0.5)
        self.assertEqual(huge["front_rms"], "")  # no front error for a run cut short

        columns, limits = self.table("stability_summary.csv")
        self.assertEqual(columns, stability_map.SUMMARY_COLUMNS)
        self.assertEqual(len(limits), 1)
        self.assertEqual(float(limits[0]["largest_stable_courant"]), 0.05)
        self.assertEqual(float(limits[0]["first_unstable_courant"]), 3.2)
        self.assertEqual(limits[0]["first_unstable_status"], "diverged")
        self.assertGreater(os.path.getsize(os.path.join(self.out, "stability.png")), 10000)

        # Both outcomes are final: a second call runs nothing.
        result = self.map()
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("2 finished, running 0", result.stdout)

    def test_largest_stable_courant(self):
        rows = (synthetic({0.01: "completed", 0.1: "completed", 0.4: "completed", 0.8: "diverged",
                           1.6: "completed", 3.2: "diverged"})  # a ragged edge: 1.6 completed again
                + synthetic({0.01: "completed", 0.1: "solver_failed", 0.4: "completed"}, l0=0.0125)
                + synthetic({0.01: "diverged", 0.1: "completed"}, l0=0.05)
                + synthetic({0.2: "completed", 0.1: "completed"}, name="other"))
        limits = {(s["map"], s["l0"]): s for s in stability_map.largest_stable(rows)}
        self.assertEqual(len(limits), 4)
        coarse = limits[("m", 0.025)]
        self.assertEqual(coarse["largest_stable_courant"], 0.4)
        self.assertAlmostEqual(coarse["dt_at_limit"], 0.4 * 0.025 / 3.13)
        self.assertEqual((coarse["first_unstable_courant"], coarse["first_unstable_status"]), (0.8, "diverged"))
        self.assertEqual(coarse["completed_above_limit"], 1)
        fine = limits[("m", 0.0125)]
        self.assertEqual(fine["largest_stable_courant"], 0.01)
        self.assertEqual(fine["first_unstable_status"], "solver_failed")
        low = limits[("m", 0.05)]  # the smallest step fails: nothing is stable from the bottom of the grid ...
        self.assertTrue(math.isnan(low["largest_stable_courant"]))
        self.assertEqual((low["stable_band_from"], low["stable_band_to"]), (0.1, 0.1))  # ... but a band above it
        self.assertEqual((coarse["stable_band_from"], coarse["stable_band_to"]), (0.01, 0.4))
        every = limits[("other", 0.025)]  # every C completed: the limit lies beyond the grid
        self.assertEqual(every["largest_stable_courant"], 0.2)
        self.assertTrue(math.isnan(every["first_unstable_courant"]))
        self.assertEqual(every["first_unstable_status"], "")

    def test_stop_event_from_log_or_message(self):
        event = {"step": 7, "time": 0.1, "kind": "energy_growth", "detail": "..."}
        summary = {"status": "diverged", "message": "diverged at t = 0.1 s (step 7), because the Courant number ...",
                   "stability": {"events": [{**event, "kind": "escaped"}, event], "events_total": 2}}
        self.assertEqual(stability_map.stop_event_of(summary), "energy_growth")
        summary["stability"]["events_total"] = 500  # the log is cut: the reason names the event
        self.assertEqual(stability_map.stop_event_of(summary), "courant")
        summary["status"] = "completed"
        self.assertEqual(stability_map.stop_event_of(summary), "")

    def test_bad_spec_is_one_line(self):
        with open(self.spec, "w") as handle:
            json.dump({**SPEC, "maps": {"mps": {"method": "mps", "courant": [0.1], "cfl_number": [0.4]}}}, handle)
        result = self.map("--collect")
        self.assertEqual(result.returncode, 2)
        self.assertIn("exactly one of courant, cfl_number", result.stderr)
        self.assertEqual(len(result.stderr.strip().splitlines()), 1)


if __name__ == "__main__":
    unittest.main()
