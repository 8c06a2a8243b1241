"""The performance study (analysis/performance.py, analysis/mps_lab/studies/performance.py) on
a tiny real study (--quick: the dam break at l0 = 0.025 for mps and isph, one bench
resolution, scaling at l0 = 0.01 with 1 and 2 threads): the CSV, JSON, tables and figures are
written; the ratio against the reference figure is the measured speed over 0.23 M; the
scaling summary's spread and the speed-ups on synthetic cases with known answers. Run by
CTest; MPS_LAB_BINARY names build/mps_lab."""
from __future__ import annotations

import csv
import json
import os
import subprocess
import sys
import tempfile
import unittest
from pathlib import Path

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
from mps_lab import methods  # noqa: E402
from mps_lab.studies import performance, performance_million, performance_targets, performance_threads  # noqa: E402
from mps_lab.studies.common import SpecError  # noqa: E402

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
            # The threads part: per registered method 6 shared runs (alone and beside the busy
            # process, 3 teams each) and 3 at the one quick size; each ratio is over the
            # one-thread run alone of its group, so that run reads exactly 1.
            threads = performance_threads.load_rows(Path(out))
            self.assertEqual(len(threads), 9 * len(registered))
            for row in threads:
                self.assertEqual(row["status"], "completed")
                if row["team"] == "1" and row["load"] == "alone":
                    self.assertEqual(row["ratio"], 1.0)
            self.assertIn("## Threads", table)
            # Every target of the plan has a row; the million part did not run.
            with open(os.path.join(out, "targets.csv"), newline="") as handle:
                targets = list(csv.DictReader(handle))
            self.assertEqual(len(targets), len(performance.load_plan(performance.DEFAULT_PLAN)["targets"]))
            million = [t for t in targets if "million" in t["name"]]
            self.assertEqual({t["status"] for t in million}, {"not measured"})

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


def write_csv(path: str, rows: list[dict]) -> None:
    with open(path, "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)


def threads_row(part, method, load, team, ratio, fluid=171, number=1):
    return dict(round=number, part=part, method=method, load=load, team=team, fluid_particles=fluid, steps=10,
                wall_seconds=ratio, ns_per_particle_step=100.0 * ratio, status="completed", steps_by_team="{}",
                ratio=ratio)


class PerformanceTargetsTest(unittest.TestCase):
    """The targets part on hand-made data whose answers are known."""

    def test_threads_targets_take_the_worst_run(self):
        targets = [dict(name="shared", kind="shared_machine", limit=1.3, direction="at_most"),
                   dict(name="team", kind="measured_team", limit=1.05, direction="at_most")]
        with tempfile.TemporaryDirectory() as out:
            write_csv(os.path.join(out, "threads.csv"), [
                threads_row("shared", "mps", "busy", "measured", 1.16), threads_row("shared", "isph", "busy", "measured", 1.31),
                threads_row("shared", "isph", "busy", "2", 3.2),  # a fixed team: not the target's
                threads_row("sizes", "mps", "alone", "measured", 0.92, fluid=1176),
                threads_row("sizes", "isph", "alone", "measured", 1.04, fluid=3916, number=2)])
            rows = performance_targets.evaluate(targets, Path(out))
        self.assertEqual([(r["measured"], r["status"]) for r in rows], [(1.31, "missed"), (1.04, "met")])
        self.assertAlmostEqual(rows[0]["ratio"], 1.31 / 1.3)
        self.assertIn("isph, 3,916 fluid, round 2", rows[1]["source"])

    def test_side_by_side_is_the_ratio_of_medians(self):
        runs = [dict(repetition=r, pair="mps", code=code, wall_s=wall, particle_steps_per_s=speed)
                for r, code, wall, speed in [(1, "mps-basic", 100.0, 0.14e6), (1, "mps_lab", 9.0, 1.6e6),
                                             (2, "mps-basic", 90.0, 0.15e6), (2, "mps_lab", 8.0, 1.8e6),
                                             (3, "mps-basic", 120.0, 0.12e6), (3, "mps_lab", 10.0, 1.4e6)]]
        targets = [dict(name="steps", kind="side_by_side", pair="mps", measure="particle_steps", limit=10,
                        direction="at_least"),
                   dict(name="seconds", kind="side_by_side", pair="mps", measure="simulated_seconds", limit=12,
                        direction="at_least"),
                   dict(name="other pair", kind="side_by_side", pair="dfsph-0.1", measure="particle_steps", limit=2,
                        direction="at_least")]
        with tempfile.TemporaryDirectory() as out:
            write_csv(os.path.join(out, "side_by_side.csv"), runs)
            rows = performance_targets.evaluate(targets, Path(out))
        self.assertAlmostEqual(rows[0]["measured"], 1.6e6 / 0.14e6)  # medians 1.6 M and 0.14 M
        self.assertEqual(rows[0]["status"], "met")
        self.assertAlmostEqual(rows[1]["measured"], 100.0 / 9.0)
        self.assertEqual(rows[1]["status"], "missed")
        self.assertEqual(rows[2]["status"], "not measured")

    def test_million_minutes_one_row_per_run(self):
        run = dict(method="dfsph", particles=dict(fluid=1006071), steps=1182, wall_seconds=538.0,
                   solver=dict(mean_iterations=7.8), memory=dict(bytes_per_particle=1303.0), status="completed",
                   overrides=[], git_revision="b3a19faae3d8", started_at="2026-11-28T00:14:00Z")
        targets = [dict(name="dfsph", kind="million_minutes", method="dfsph", limit=4, direction="at_most")]
        with tempfile.TemporaryDirectory() as out:
            folders = []
            for name, seconds in (("a", 538.0), ("b", 210.0)):
                folder = Path(out) / name
                folder.mkdir()
                (folder / "run.json").write_text(json.dumps(dict(run, wall_seconds=seconds)))
                folders.append(folder)
            performance_million.write_million(folders, Path(out))
            rows = performance_targets.evaluate(targets, Path(out))
            table = "\n".join(performance_million.million_table(Path(out)))
        self.assertEqual([(round(r["measured"], 3), r["status"]) for r in rows], [(8.967, "missed"), (3.5, "met")])
        self.assertAlmostEqual(rows[0]["ratio"], 538.0 / 60.0 / 4.0)
        self.assertIn("| dfsph | 1,006,071 | 1182 | 9.0 min |", table)

    def test_scaling_targets(self):
        cases = [dict(kind="steps", method="isph", threads=t, status="completed", fluid_particles=n,
                      nanoseconds_per_particle_step=v, seconds=s, memory_bytes_per_particle=b)
                 for t, n, v, s, b in [(2, 1000, 128.0, 1.0, 800.0), (2, 10000, 100.0, 1.2, 900.0),
                                       (2, 1000000, 90.0, 1.0, 954.0), (1, 1000000, 160.0, 1.8, 960.0)]]
        targets = [dict(name="memory", kind="memory", method="isph", limit=1024, direction="at_most"),
                   dict(name="speed-up", kind="speedup", method="isph", limit=1.7, direction="at_least"),
                   dict(name="flat", kind="flat", method="isph", limit=0.3, direction="at_most")]
        with tempfile.TemporaryDirectory() as out:
            Path(out, "scaling.json").write_text(json.dumps(dict(cases=cases)))
            rows = performance_targets.evaluate(targets, Path(out))
        self.assertEqual([r["measured"] for r in rows[:2]], [954.0, 1.8])
        self.assertAlmostEqual(rows[2]["measured"], 0.28)  # 128 against the median 100
        self.assertEqual([r["status"] for r in rows], ["met", "met", "met"])

    def test_bad_targets_are_one_line_errors(self):
        for target, key in [(dict(name="x", kind="speed", limit=1, direction="at_most"), "targets[0].kind"),
                            (dict(name="x", kind="memory", limit=1, direction="at_most"), "targets[0].method"),
                            (dict(name="x", kind="flat", method="mps", limit=1, direction="below"),
                             "targets[0].direction"),
                            (dict(name="x", kind="flat", method="mps", limit=1, direction="at_most", unit="s"),
                             "targets[0].unit")]:
            with self.assertRaises(SpecError) as caught:
                performance_targets.check_targets("plan.json", [target])
            self.assertIn(f"plan.json: {key}", str(caught.exception))
            self.assertNotIn("\n", str(caught.exception))


if __name__ == "__main__":
    unittest.main()
