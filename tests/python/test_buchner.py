"""The wall-pressure comparison against Buchner (2002): the experimental records, the
definitions of impact time, peak and quasi-static error (analysis/mps_lab/pressure.py), the
sweep's pressure columns, and run.json's "validation" entry from a real (short) run.

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
from mps_lab import data, pressure, report  # noqa: E402
from mps_lab.studies import buchner, sweep_pressure  # noqa: E402

BINARY = os.environ.get("MPS_LAB_BINARY", os.path.join(ROOT, "build", "mps_lab"))
SCENE = os.path.join(ROOT, "scenes", "dambreak_buchner.json")


def synthetic_run(t_star: np.ndarray, p_star: np.ndarray, validation: pressure.Validation) -> data.Run:
    """A run whose P1 reads p_star at T = t_star (row means and peaks alike), rho g H = 1000 g H."""
    g, h = 9.81, validation.length_scale
    summary = {"shared": {"density": 1000.0, "gravity": [0.0, -g]}, "method": "synthetic",
               "validation": {"length_scale": h, "impact_threshold": validation.impact_threshold,
                              "quasi_static": list(validation.quasi_static),
                              "pressure_records": [{"sensor": s, "file": f} for s, f in validation.records.items()]}}
    series = {"time": t_star / math.sqrt(g / h), "pressure_P1": p_star * 1000.0 * g * h,
              "pressure_P1_max": p_star * 1000.0 * g * h}
    return data.Run("synthetic", summary, series)


class ExperimentRecordTest(unittest.TestCase):
    def setUp(self):
        self.validation = pressure.scene_validation(SCENE)

    def test_records_load_with_the_expected_range(self):
        # The digitisation (analysis/validation/buchner_2002_p*.csv): P1 from T = 2.03 to 7.30,
        # 98 points; P2 from 3.07 to 7.52, 47 points; both in -0.03 .. 0.9 rho g H.
        self.assertEqual(sorted(self.validation.records), ["P1", "P2"])
        t1, p1 = pressure.read_record(self.validation.records["P1"])
        t2, p2 = pressure.read_record(self.validation.records["P2"])
        self.assertEqual((len(t1), len(t2)), (98, 47))
        self.assertTrue(np.all(np.diff(t1) > 0) and np.all(np.diff(t2) > 0))
        self.assertAlmostEqual(t1[0], 2.02512, places=5)
        self.assertAlmostEqual(t1[-1], 7.29946, places=5)
        self.assertAlmostEqual(t2[-1], 7.52047, places=5)
        self.assertTrue(-0.03 < p1.min() and p1.max() < 0.9 and -0.03 < p2.min() and p2.max() < 0.25)

    def test_experiment_measures(self):
        # Impact: 0.1 reached between (2.47263, 0.07666) and (2.49148, 0.15352), linearly at
        # 2.47263 + 0.01885 (0.1 - 0.07666) / 0.07686 = 2.47836; peak 0.68698 at T = 2.774;
        # quasi-static mean of the 22 points in [3, 5.5]: 0.5491 (hand sum).
        t, p = pressure.read_record(self.validation.records["P1"])
        measured = pressure.record_measures(t, p, self.validation)
        self.assertAlmostEqual(measured["impact_time"], 2.47836, places=4)
        self.assertAlmostEqual(measured["peak"], 0.68698, places=5)
        row = buchner.experiment_row(self.validation)
        self.assertAlmostEqual(row["P1_quasi_static_level"], 0.5491, places=3)
        self.assertAlmostEqual(row["P2_impact_time"], 4.853, places=3)


class DefinitionsTest(unittest.TestCase):
    def setUp(self):
        self.validation = pressure.scene_validation(SCENE)
        self.exp_t, self.exp_p = pressure.read_record(self.validation.records["P1"])
        self.t = np.arange(0.0, 7.5, 0.004)  # the series' 2 ms rows in T units (0.0081)

    def test_crossing_is_linear_between_samples(self):
        self.assertAlmostEqual(pressure.crossing_time(np.array([0.0, 1.0, 2.0]), np.array([0.0, 0.0, 0.4]), 0.1),
                               1.25, places=12)
        self.assertTrue(math.isnan(pressure.crossing_time(np.array([0.0, 1.0]), np.array([0.0, 0.05]), 0.1)))

    def test_planted_offset_gives_its_rms_and_peak_error(self):
        # The record (zero before it) plus 0.05: the quasi-static RMS and the peak error are
        # 0.05 to the interpolation error of 0.004-spaced samples of a piecewise-linear curve
        # at its own nodes (< 1e-3 here: slopes below 0.25 per 0.004 in the window).
        p = np.interp(self.t, self.exp_t, self.exp_p, left=0.0, right=self.exp_p[-1]) + 0.05
        m = pressure.sensor_measures(synthetic_run(self.t, p, self.validation), "P1", self.validation)
        self.assertAlmostEqual(m["quasi_static_rms"], 0.05, delta=1e-3)
        self.assertAlmostEqual(m["peak_row_error"], 0.05, delta=2e-3)
        self.assertEqual(m["quasi_static_points"], 22)

    def test_planted_delay_gives_its_impact_error(self):
        # The record 0.2 late: impact error 0.2 within one row (0.004) of interpolation.
        p = np.interp(self.t - 0.2, self.exp_t, self.exp_p, left=0.0, right=self.exp_p[-1])
        m = pressure.sensor_measures(synthetic_run(self.t, p, self.validation), "P1", self.validation)
        self.assertAlmostEqual(m["impact_time_error"], 0.2, delta=0.004)

    def test_sweep_columns_match_sensor_names_with_underscores(self):
        self.assertEqual(sweep_pressure.split_key("right_wall_bottom_quasi_static_rms"),
                         ("right_wall_bottom", "quasi_static_rms"))
        self.assertIsNone(sweep_pressure.split_key("front_rms"))
        rows = [{"front_rms": 0.1, "P1_quasi_static_rms": 0.2, "P1_peak_row_error": 0.3}]
        self.assertEqual(sweep_pressure.columns(rows), [f"P1_{m}" for m in sweep_pressure.MEASURES])


class RunJsonTest(unittest.TestCase):
    def test_a_run_writes_the_validation_block_and_the_report_table(self):
        with tempfile.TemporaryDirectory() as folder:
            out = os.path.join(folder, "mps")
            result = subprocess.run([BINARY, "run", SCENE, "--method", "mps", "--out", out, "--quiet",
                                     "--end-time", "0.003", "--set", "output.formats=[\"csv\"]"],
                                    capture_output=True, text=True, timeout=300)
            self.assertEqual(result.returncode, 0, result.stderr)
            with open(os.path.join(out, "run.json")) as handle:
                summary = json.load(handle)
            block = summary["validation"]
            self.assertEqual(block["length_scale"], 0.6)
            self.assertEqual([r["sensor"] for r in block["pressure_records"]], ["P1", "P2"])
            for record in block["pressure_records"]:
                self.assertTrue(os.path.isabs(record["file"]) and os.path.isfile(record["file"]))
            table = report.pressure_table([data.load_run(out)])
            self.assertIn("| mps | P1 |", table)
            self.assertIn("(2.478)", table)  # the experiment's impact time beside the run's (none yet: nan)


if __name__ == "__main__":
    unittest.main()


class SchemesPlanTest(unittest.TestCase):
    """buchner_pressure.py --schemes: the plan's method once per scheme, with the scheme's --set
    assignments, its own folder, and its name in the table."""

    def test_one_case_per_scheme_with_its_assignments(self):
        with open(os.path.join(ROOT, "analysis", "sweeps", "pressure_schemes.json")) as handle:
            plan = json.load(handle)
        cases = list(buchner.requests(SCENE, "OUT", ["ignored"], [40], plan))
        self.assertEqual([c.name for c in cases], [f"H40/mps-{name}" for name in plan["schemes"]])
        for case in cases:
            scheme = case.extra["scheme"]
            self.assertEqual(case.folder, os.path.join("OUT", "H40", f"mps-{scheme}"))
            self.assertEqual(case.arguments[case.arguments.index("--method") + 1], "mps")
            given = [case.arguments[k + 1] for k, a in enumerate(case.arguments) if a == "--set"]
            for assignment in plan["schemes"][scheme]:
                self.assertIn(assignment, given)
        row = dict(cases[1].extra, status="completed")
        self.assertIn("| H/40 | mps (cmps) | completed |", buchner.markdown([row]))

    def test_without_a_plan_each_method_runs_with_its_defaults(self):
        cases = list(buchner.requests(SCENE, "OUT", ["mps", "isph"], [40, 60]))
        self.assertEqual([c.name for c in cases], ["H40/mps", "H40/isph", "H60/mps", "H60/isph"])
        self.assertTrue(all(c.extra["scheme"] == "" for c in cases))
