"""The sweep tool (analysis/sweep.py) on a tiny grid: it runs, writes sweep.csv with cost and
error for every case, resumes after an interruption without re-running finished cases, and
writes a job list. Run by CTest; MPS_LAB_BINARY names build/mps_lab."""
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
from mps_lab.studies import sweep  # noqa: E402

BINARY = os.environ.get("MPS_LAB_BINARY", os.path.join(ROOT, "build", "mps_lab"))
SPEC = {
    "scene": "scenes/dambreak.json",
    "end_time": 0.1,
    "spacings": [0.05, 0.025],
    "methods": {"mps": {"time_step": [{"name": "spec_dt", "set": {"time.time_step": 5e-4}}],
                        "tolerance": [{"name": "tight", "set": {"methods.mps.cg_tolerance": 1e-8}},
                                      {"name": "loose", "set": {"methods.mps.cg_tolerance": 1e-3}}]}},
}


class SweepTest(unittest.TestCase):
    def setUp(self):
        self.folder = tempfile.mkdtemp(prefix="mps_lab_sweep_")
        self.spec = os.path.join(self.folder, "spec.json")
        with open(self.spec, "w") as handle:
            json.dump(SPEC, handle)
        self.out = os.path.join(self.folder, "out")

    def tearDown(self):
        shutil.rmtree(self.folder, ignore_errors=True)

    def sweep(self, *extra):
        return subprocess.run([sys.executable, os.path.join(ROOT, "analysis", "sweep.py"), self.spec, "--out", self.out,
                               "--binary", BINARY, *extra], capture_output=True, text=True)

    def rows(self):
        with open(os.path.join(self.out, "sweep.csv"), newline="") as handle:
            return list(csv.DictReader(handle))

    def test_runs_resumes_and_emits_jobs(self):
        result = self.sweep("--parallel", "2")
        self.assertEqual(result.returncode, 0, result.stderr)
        rows = self.rows()
        self.assertEqual(len(rows), 4)
        for row in rows:
            self.assertEqual(row["status"], "completed", row["name"])
            self.assertGreater(float(row["wall_seconds"]), 0.0)
            self.assertGreater(float(row["mean_solver_iterations"]), 0.0)
        # The loose tolerance costs fewer iterations than the tight one at the same spacing.
        by_name = {row["name"]: row for row in rows}
        tight = by_name[sweep.case_name("mps", 0.025, "spec_dt", "tight")]
        loose = by_name[sweep.case_name("mps", 0.025, "spec_dt", "loose")]
        self.assertLess(float(loose["mean_solver_iterations"]), float(tight["mean_solver_iterations"]))
        # The reference of self-convergence is the finest tight case; it has no self error.
        self.assertEqual(tight["reference"], tight["name"])
        coarse = by_name[sweep.case_name("mps", 0.05, "spec_dt", "tight")]
        self.assertEqual(coarse["reference"], tight["name"])
        self.assertGreater(float(coarse["self_convergence"]), 0.0)
        self.assertTrue(os.path.isfile(os.path.join(self.out, "pareto.png")))
        self.assertTrue(os.path.isfile(os.path.join(self.out, "convergence.png")))

        # Interrupt: one case lost its result (a run killed before it finished leaves
        # run.json with status "running"). Resuming re-runs that case only.
        cases = os.path.join(self.out, "cases")
        killed = os.path.join(cases, coarse["name"], "run.json")
        with open(killed) as handle:
            summary = json.load(handle)
        summary["status"] = "running"
        with open(killed, "w") as handle:
            json.dump(summary, handle)
        untouched = {name: os.path.getmtime(os.path.join(cases, name, "run.json"))
                     for name in os.listdir(cases) if name != coarse["name"]}
        result = self.sweep()
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("3 finished, running 1", result.stdout)
        for name, mtime in untouched.items():
            self.assertEqual(os.path.getmtime(os.path.join(cases, name, "run.json")), mtime, name)
        self.assertEqual({row["status"] for row in self.rows()}, {"completed"})

        # The job list: one command per case, each a complete `mps_lab run`.
        jobs = os.path.join(self.folder, "jobs.txt")
        result = self.sweep("--jobs-file", jobs)
        self.assertEqual(result.returncode, 0, result.stderr)
        with open(jobs) as handle:
            lines = handle.read().splitlines()
        self.assertEqual(len(lines), 4)
        for line in lines:
            self.assertIn(" run --method=mps ", line)
            self.assertIn("--set particle_spacing=", line)

    def test_methods_subset_and_merge(self):
        """--methods runs only the cases of those methods; --merge takes the rows of the cases
        not run here from an earlier sweep.csv, as they were; cpu_seconds is collected."""
        two = {**SPEC, "spacings": [0.05], "methods": {
            "mps": SPEC["methods"]["mps"],
            "isph": {"time_step": [{"name": "spec_dt", "set": {"time.time_step": 5e-4}}]}}}
        with open(self.spec, "w") as handle:
            json.dump(two, handle)
        earlier = os.path.join(self.folder, "earlier.csv")
        columns = ["name", "method", "l0", "time_step_rule", "tolerance", "status", "wall_seconds", "steps",
                   "front_rms", "front_rms_shifted", "self_convergence", "reference"]  # an older sweep: no CPU column
        with open(earlier, "w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow(columns)
            for tolerance in ("tight", "loose"):
                writer.writerow([sweep.case_name("mps", 0.05, "spec_dt", tolerance), "mps", 0.05, "spec_dt", tolerance,
                                 "completed", 123.0, 200, 0.5, 0.25, "nan", "somewhere"])
        result = self.sweep("--methods", "isph", "--merge", earlier, "--parallel", "1")
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("1 cases, 0 finished, running 1", result.stdout)  # 3 in the grid, 1 of isph
        self.assertIn("2 case(s) taken from", result.stdout)
        self.assertEqual(sorted(os.listdir(os.path.join(self.out, "cases"))),
                         [sweep.case_name("isph", 0.05, "spec_dt", "default")])
        rows = {row["name"]: row for row in self.rows()}
        self.assertEqual(len(rows), 3)
        merged = rows[sweep.case_name("mps", 0.05, "spec_dt", "loose")]
        self.assertEqual((merged["status"], float(merged["wall_seconds"]), merged["reference"]),
                         ("completed", 123.0, "somewhere"))
        self.assertEqual(merged["cpu_seconds"], "nan")
        ran = rows[sweep.case_name("isph", 0.05, "spec_dt", "default")]
        self.assertEqual(ran["status"], "completed")
        # CPU seconds are > 0 and at most threads x wall seconds (a thread cannot use more CPU
        # than the time that passed; + 0.05 s for the kernel's accounting granularity).
        threads = sweep.runner.threads_per_case(1)
        self.assertGreater(float(ran["cpu_seconds"]), 0.0)
        self.assertLessEqual(float(ran["cpu_seconds"]), threads * float(ran["wall_seconds"]) + 0.05)
        # The Pareto cost falls back on the wall time of a row without CPU seconds.
        self.assertEqual(sweep.cost_seconds({"cpu_seconds": float("nan"), "wall_seconds": 2.0}), 2.0)
        self.assertEqual(sweep.cost_seconds({"cpu_seconds": 1.5, "wall_seconds": 2.0}), 1.5)
        result = self.sweep("--methods", "dfsph", "--collect")
        self.assertEqual(result.returncode, 2)
        self.assertIn("--methods: dfsph: not a method of", result.stderr)

    def test_bad_spec_is_one_line(self):
        with open(self.spec, "w") as handle:
            json.dump({"scene": "x", "spacings": [0.1], "methods": {}, "colour": 1}, handle)
        result = self.sweep("--collect")
        self.assertEqual(result.returncode, 2)
        self.assertIn("colour: unknown key", result.stderr)
        self.assertEqual(len(result.stderr.strip().splitlines()), 1)

    def test_unregistered_method_is_one_line(self):
        """The spec's methods are checked against `mps_lab methods` before anything runs."""
        with open(self.spec, "w") as handle:
            json.dump({**SPEC, "methods": {"no_such_method": {}}}, handle)
        result = self.sweep()
        self.assertEqual(result.returncode, 2)
        self.assertIn("methods.no_such_method: not a registered method", result.stderr)
        self.assertEqual(len(result.stderr.strip().splitlines()), 1)
        self.assertFalse(os.path.exists(os.path.join(self.out, "cases")))

    def test_read_and_merge_rows(self):
        """common.read_rows and merge_rows (the --merge of sweep.py, stability_map.py and
        wall_study.py): numbers back as numbers (integers as int, so a merged CSV is written
        back unchanged), empty cells NaN; a finished case of this study wins over the earlier row."""
        from mps_lab.studies import common
        path = os.path.join(self.folder, "earlier.csv")
        with open(path, "w", newline="") as handle:
            handle.write("name,status,steps,wall_seconds,front_rms\na,completed,1000,0.25,\nb,completed,2000,0.5,nan\n")
        earlier = common.read_rows(path, {"steps", "wall_seconds", "front_rms"})
        self.assertEqual((earlier[0]["steps"], earlier[0]["wall_seconds"]), (1000, 0.25))
        self.assertIsInstance(earlier[0]["steps"], int)
        self.assertTrue(math.isnan(earlier[0]["front_rms"]) and math.isnan(earlier[1]["front_rms"]))
        rows = [{"name": "a", "status": "missing"}, {"name": "b", "status": "completed", "steps": 7},
                {"name": "c", "status": "missing"}]
        merged, taken = common.merge_rows(rows, earlier)
        self.assertEqual(taken, 1)
        self.assertEqual([r["steps"] if "steps" in r else None for r in merged], [1000, 7, None])

    def test_pareto_front_and_order(self):
        points = [(1.0, 0.5), (2.0, 0.3), (3.0, 0.4), (4.0, 0.1), (5.0, 0.1)]
        self.assertEqual(sweep.pareto_front(points), [0, 1, 3])
        # error = 2 l0^1.5 exactly: the fitted order is 1.5
        l0 = [0.04, 0.02, 0.01]
        self.assertAlmostEqual(sweep.fitted_order(l0, [2 * h ** 1.5 for h in l0]), 1.5, places=12)


if __name__ == "__main__":
    unittest.main()
