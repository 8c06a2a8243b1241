"""The cost study (analysis/cost_per_method.py, tools/cost-five-methods.sh) on a tiny case:
every registered method runs, interleaved, the medians and the ratios are written. Run by
CTest; MPS_LAB_BINARY names build/mps_lab."""
from __future__ import annotations

import csv
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
from mps_lab import methods  # noqa: E402
from mps_lab.studies import cost  # noqa: E402

BINARY = os.environ.get("MPS_LAB_BINARY", os.path.join(ROOT, "build", "mps_lab"))


class CostTest(unittest.TestCase):
    def setUp(self):
        self.out = tempfile.mkdtemp(prefix="mps_lab_cost_")

    def tearDown(self):
        shutil.rmtree(self.out, ignore_errors=True)

    def test_interleaved_order_rotates_the_methods(self):
        order = cost.interleaved_order(["a", "b", "c"], [0.1, 0.05], 2)
        self.assertEqual([m for k, l0, m in order if k == 0 and l0 == 0.1], ["a", "b", "c"])
        self.assertEqual([m for k, l0, m in order if k == 1 and l0 == 0.05], ["b", "c", "a"])
        self.assertEqual(len(order), 12)

    def test_every_method_medians_and_ratios(self):
        result = subprocess.run([sys.executable, os.path.join(ROOT, "analysis", "cost_per_method.py"), "--out", self.out,
                                 "--binary", BINARY, "--spacings", "0.05", "--end-time", "0.02", "--repetitions", "2"],
                                capture_output=True, text=True)
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(os.path.join(self.out, "cost_per_method.csv"), newline="") as handle:
            rows = {row["method"]: row for row in csv.DictReader(handle)}
        registered = methods.registered_methods(BINARY)
        self.assertEqual(sorted(rows), sorted(registered))
        for method, row in rows.items():
            self.assertEqual((row["status"], row["repetitions"]), ("completed", "2"), method)
            # One thread: CPU seconds > 0, and per simulated second 1/0.02 = 50 x the run's.
            self.assertGreater(float(row["cpu_seconds"]), 0.0)
            self.assertAlmostEqual(float(row["cpu_seconds_per_simulated_second"]) * 0.02, float(row["cpu_seconds"]),
                                   delta=1e-9 + 1e-6 * float(row["cpu_seconds"]))
        self.assertEqual(float(rows[registered[0]]["ratio_to_reference"]), 1.0)  # the reference against itself
        with open(os.path.join(self.out, "cost_per_method.md")) as handle:
            table = handle.read()
        self.assertEqual(table.count("\n| 0.05 |"), len(registered))

    def test_unknown_reference_is_one_line(self):
        result = subprocess.run([sys.executable, os.path.join(ROOT, "analysis", "cost_per_method.py"), "--out", self.out,
                                 "--binary", BINARY, "--reference", "no_such_method"], capture_output=True, text=True)
        self.assertEqual(result.returncode, 2)
        self.assertEqual(len(result.stderr.strip().splitlines()), 1)
        self.assertIn("--reference no_such_method: not a registered method", result.stderr)


if __name__ == "__main__":
    unittest.main()
