"""The still-water study (analysis/still_water.py): the window mean and the ratios on synthetic
runs with known answers, the promise read from the binary's listing, a short real study of one
method with every boundary model it supports, and bad input. Run by CTest; MPS_LAB_BINARY names
build/mps_lab."""
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
from mps_lab import methods, runner  # noqa: E402
from mps_lab.studies import still_water  # noqa: E402

BINARY = os.environ.get("MPS_LAB_BINARY", os.path.join(ROOT, "build", "mps_lab"))
RHO, G, L0 = 1000.0, 9.81, 0.025
TOP_ROW = 0.275  # m, the tank's top row of particle centres; the lattice's top edge is 0.2875 m


def write_case(folder: str, scale: float, times: list[float]) -> None:
    """A finished case: run.json's shared values, a first frame whose top fluid row is TOP_ROW (a
    wall particle higher up must be ignored) and series rows with p = scale rho g h at each
    sensor and 0 at the dry one."""
    os.makedirs(folder)
    with open(os.path.join(folder, "run.json"), "w") as handle:
        json.dump({"status": "completed",
                   "shared": {"density": RHO, "gravity": [0.0, -G], "particle_spacing": L0}}, handle)
    with open(os.path.join(folder, "output_000000.csv"), "w") as handle:
        handle.write("x,y,vx,vy,pressure,type\n0.025,0.025,0,0,0,0\n0.025,0.275,0,0,0,0\n0,0.5,0,0,0,1\n")
    surface = TOP_ROW + 0.5 * L0
    with open(os.path.join(folder, "series.csv"), "w", newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(["time", "pressure_s0", "pressure_s1", "pressure_s2", "pressure_dry"])
        for t in times:
            writer.writerow([t] + [scale * RHO * G * (surface - y) for y in still_water.SENSOR_HEIGHTS] + [0.0])


class StillWaterTest(unittest.TestCase):
    def setUp(self):
        self.folder = tempfile.mkdtemp(prefix="mps_lab_still_water_")

    def tearDown(self):
        shutil.rmtree(self.folder, ignore_errors=True)

    def test_window_mean_weights_each_row_by_its_overlap(self):
        # Rows at t = 0, 1, 2, 3 holding the means 10 (0, 1], 20 (1, 2], 40 (2, 3]: over [0.5, 2.5]
        # 0.5 of 10, 1 of 20 and 0.5 of 40, i.e. (5 + 20 + 20) / 2 = 22.5.
        self.assertAlmostEqual(still_water.window_mean([0, 1, 2, 3], [0, 10, 20, 40], 0.5, 2.5), 22.5, places=12)
        self.assertAlmostEqual(still_water.window_mean([0, 1, 2, 3], [0, 10, 20, 40], 0.0, 3.0), 70 / 3, places=12)
        self.assertTrue(math.isnan(still_water.window_mean([0, 1], [0, 5], 2.0, 3.0)))  # no row in the window

    def test_ratios_of_an_exact_and_a_scaled_hydrostatic_field(self):
        # Depths below the lattice's top edge 0.2875 m: 0.225, 0.15, 0.075 m. The exact field reads
        # 1 to round-off at every sensor (3 within 1 %), a field 0.98 of it reads 0.98 (none within).
        for scale, within in ((1.0, 3), (0.98, 0)):
            folder = os.path.join(self.folder, f"case_{scale}")
            write_case(folder, scale, [0.0, 0.25, 0.5, 1.0, 2.0, 3.0])
            ratios = still_water.sensor_ratios(folder, 0.5, 3.0)
            for column in still_water.RATIOS:
                self.assertAlmostEqual(ratios[column], scale, places=12)
            self.assertEqual(ratios["dry"], 0.0)
            self.assertEqual(ratios["within_1pct"], within)
            self.assertAlmostEqual(ratios["worst"], abs(scale - 1.0), places=12)

    def test_expected_reading_and_its_verdict(self):
        # Two readings a and b: mean (a + b) / 2, sample deviation |a - b| / sqrt(2), standard error
        # |a - b| / 2. The verdict compares |mean - 1| with 1 % two standard errors apart.
        cases = (([1.0, 1.004], 1.002, 0.002, "within"),      # 0.002 + 0.004 < 0.01
                 ([1.0, 1.012], 1.006, 0.006, "undecided"),   # 0.006 + 0.012 > 0.01 > 0.006 - 0.012
                 ([0.985, 0.987], 0.986, 0.001, "outside"),   # 0.014 - 0.002 > 0.01
                 ([0.985, 0.995], 0.990, 0.005, "undecided"),  # 0.010 - 0.010 < 0.01
                 ([1.004, 1.004, 1.004], 1.004, 0.0, "within"),  # a deterministic method: no spread
                 ([1.011, 1.011], 1.011, 0.0, "outside"))
        for values, mean, error, verdict in cases:
            got = still_water.expected_reading(values)
            self.assertAlmostEqual(got[0], mean, places=12, msg=values)
            self.assertAlmostEqual(got[1], error, places=12, msg=values)
            self.assertEqual(got[2], verdict, values)

    def test_one_run_chance_of_the_target(self):
        # A normal reading: mean 1, sd 1 % -> Phi(1) - Phi(-1) = 0.682689; mean 0.99, sd 1 % ->
        # Phi(2) - Phi(0) = 0.477250; a deterministic reading is in or out.
        self.assertAlmostEqual(still_water.one_run_within(1.0, 0.01), 0.682689, places=6)
        self.assertAlmostEqual(still_water.one_run_within(0.99, 0.01), 0.477250, places=6)
        self.assertEqual(still_water.one_run_within(1.004, 0.0), 1.0)
        self.assertEqual(still_water.one_run_within(0.989, 0.0), 0.0)
        # Two realisations 0.99 and 1.01 per sensor: mean 1, sd 0.014142; each sensor 0.521,
        # the three together 0.521^3 = 0.1410 (as noise alone: the mean is exact).
        rows = [dict({"method": "mps", "boundary_model": "walls", "realisation": k, "status": "completed"},
                     **{column: value for column in still_water.RATIOS}) for k, value in enumerate((0.99, 1.01))]
        entries = still_water.expectations(rows)
        self.assertAlmostEqual(entries[0]["sd_ratio_h0075"], 0.0141421, places=6)
        self.assertAlmostEqual(entries[0]["one_run_ratio_h0075"], 0.520500, places=5)
        self.assertAlmostEqual(entries[0]["noise_only_ratio_h0075"], entries[0]["one_run_ratio_h0075"], places=12)
        self.assertAlmostEqual(still_water.all_within(entries, "one_run"), 0.520500 ** 3, places=5)
        self.assertIn("- mps: 0.14 (noise alone: 0.14); the single runs' standard deviations 0.0141–0.0141",
                      still_water.expectation_table(entries))

    def test_expectations_group_completed_realisations(self):
        # isph/walls: two completed realisations and a failed one (left out); isph/lone: one
        # realisation, no expectation.
        def row(model, realisation, status, value):
            return dict({"method": "isph", "boundary_model": model, "realisation": realisation, "status": status},
                        **{column: value for column in still_water.RATIOS})
        rows = [row("walls", 0, "completed", 0.985), row("walls", 1, "stopped", 0.5),
                row("walls", 2, "completed", 0.987), row("lone", 0, "completed", 1.0)]
        entries = still_water.expectations(rows)
        self.assertEqual([(e["boundary_model"], e["realisations"]) for e in entries], [("walls", 2)])
        for column in still_water.RATIOS:
            self.assertAlmostEqual(entries[0][f"mean_{column}"], 0.986, places=12)
            self.assertEqual(entries[0][f"verdict_{column}"], "outside")
        self.assertIn("**0 within, 3 outside, 0 undecided**", still_water.expectation_table(entries))

    def test_spacing_scales_the_step_and_keeps_the_sensors_on_the_wall_surface(self):
        # The scene: l0 = 0.025 m, dt = 5e-4 s, fluid from x = l0, wall's first line at x = 0, so
        # the wall surface is x = l0/2. At l0 = 0.0125 m: dt 2.5e-4 s and the sensors at x = 6.25 mm.
        finer = still_water.case_arguments("mps", "dummy_layers", 0, "out", 3.0, True, [], 0.0125, 2e-3)
        self.assertIn("particle_spacing=0.0125", finer)
        self.assertIn("methods.mps.max_time_step=0.001", finer)  # the method's step bound, halved too
        step = [item for item in finer if item.startswith("time.time_step=")]
        self.assertEqual(len(step), 1)
        self.assertAlmostEqual(float(step[0].split("=")[1]), 2.5e-4, places=15)
        self.assertIn('"position": [0.00625, 0.0625]', " ".join(finer))
        scene = still_water.case_arguments("mps", "dummy_layers", 0, "out", 3.0, True, [])
        self.assertFalse(any(item.startswith(("particle_spacing=", "time.time_step=", "methods.mps.max_time_step"))
                             for item in scene))
        self.assertIn('"position": [0.0125, 0.0625]', " ".join(scene))
        # A later --set still wins: it comes after the spacing's overrides.
        override = still_water.case_arguments("mps", "dummy_layers", 0, "out", 3.0, True, ["time.time_step=1e-4"],
                                              0.0125, 2e-3)
        self.assertGreater(override.index("time.time_step=1e-4"), finer.index(step[0]))

    def test_models_and_their_options(self):
        # --models keeps the models named; --model-set puts an option in that model's block only.
        catalogue = {"mps": methods.MethodInfo("mps", "", boundary_models=["distance_function", "dummy_layers"])}
        options = still_water.parse_model_options(['distance_function.velocity="free_slip"',
                                                   "distance_function.quadrature_points=2"])
        self.assertEqual(options, {"distance_function": {"velocity": "free_slip", "quadrature_points": 2}})
        chosen = list(still_water.requests("out", catalogue, ["mps"], 1, 3.0, True, [], None, ["distance_function"],
                                           options))
        self.assertEqual([request.name for request in chosen], ["mps__distance_function__r0"])
        self.assertIn('methods.mps.wall_treatments={"distance_function":{"velocity":"free_slip",'
                      '"quadrature_points":2}}', chosen[0].arguments)
        every = list(still_water.requests("out", catalogue, ["mps"], 1, 3.0, True, [], None, None, options))
        self.assertIn('methods.mps.wall_treatments={"dummy_layers":{}}', every[1].arguments)  # its defaults
        for bad, expected in (("velocity=1", "expected MODEL.KEY=VALUE"), ("distance_function.velocity=free_slip",
                                                                           "VALUE is not JSON")):
            with self.assertRaises(still_water.SpecError) as raised:
                still_water.parse_model_options([bad])
            self.assertIn(expected, str(raised.exception))
        with self.assertRaises(still_water.SpecError) as raised:
            still_water.check_models(catalogue, ["mps"], ["akinci_boundary"], None)
        self.assertIn("--models.akinci_boundary: not a boundary model of mps", str(raised.exception))

    def test_step_bound_is_the_scene_s_else_the_declared_default(self):
        # scenes/hydrostatic.json sets eisph's bound (2e-3 s); wcsph's comes from the listing.
        info = methods.MethodInfo("x", "", parameter_defaults={"max_time_step": "0.001"})
        self.assertEqual(still_water.step_bound(info, "eisph"), 2e-3)
        self.assertEqual(still_water.step_bound(info, "wcsph"), 1e-3)
        self.assertIsNone(still_water.step_bound(methods.MethodInfo("x", ""), "wcsph"))

    def test_requests_per_spacing_and_the_resolution_table(self):
        catalogue = {"isph": methods.MethodInfo("isph", "", boundary_models=["dummy_layers"],
                                                parameter_defaults={"max_time_step": "0.002"})}
        names = [(request.name, request.extra["particle_spacing"])
                 for request in still_water.requests("out", catalogue, ["isph"], 1, 3.0, True, [], [0.025, 0.0125])]
        self.assertEqual(names, [("isph__dummy_layers__r0__l0_0.025", 0.025),
                                 ("isph__dummy_layers__r0__l0_0.0125", 0.0125)])
        scene = [request.name for request in still_water.requests("out", catalogue, ["isph"], 1, 3.0, True, [])]
        self.assertEqual(scene, ["isph__dummy_layers__r0"])
        # One completed case at l0 = 0.025 m (1.0, 0.995, 0.98: two within 1 %), one failed at 0.0125 m.
        rows = [dict({"method": "isph", "boundary_model": "dummy_layers", "realisation": 0, "status": "completed",
                      "particle_spacing": 0.025, "within_1pct": 2},
                     **dict(zip(still_water.RATIOS, (1.0, 0.995, 0.98)))),
                {"method": "isph", "boundary_model": "dummy_layers", "realisation": 0, "status": "diverged",
                 "particle_spacing": 0.0125}]
        text = still_water.resolution_table(rows, [0.025, 0.0125], {"isph": 0.02}, True)
        self.assertIn("| isph | 0.980–1.000, 2 of 3 | – (1 not completed) | promise 2 % |", text)
        path = os.path.join(self.folder, "resolution.png")
        still_water.plot_resolution(rows, [0.025, 0.0125], path)  # the failed case is left out
        with open(path, "rb") as handle:
            self.assertEqual(handle.read(8), b"\x89PNG\r\n\x1a\n")

    def test_a_failed_case_says_why(self):
        # No run.json: the status is the exit and the binary's last error line.
        result = runner.CaseResult(["mps_lab"], 2, 0.1, "", "starting\nmps_lab: error: scene.json: key: expected x\n")
        self.assertEqual(still_water.failure(result), "exit 2: mps_lab: error: scene.json: key: expected x")
        self.assertEqual(still_water.failure(runner.CaseResult(["mps_lab"], 2, 0.1, "", "")), "exit 2")

    def test_promise_read_from_the_listing(self):
        listing = ("isph   incompressible SPH\n"
                   "    load setting (--load-setting): --set methods.isph.x=1; promise: still water within 2 % of "
                   "rho g h (measured within 1.6 %)\n"
                   "    methods.isph.max_time_step = 0.002 s  (a number > 0) upper bound of the CFL step\n"
                   "    wall treatment adami_wall_particles (boundary model, on by default): walls\n"
                   "nopromise   a method without a load setting\n")
        catalogue = methods.parse_catalogue(listing)
        self.assertAlmostEqual(catalogue["isph"].still_water_promise, 0.02, places=15)
        self.assertEqual(catalogue["isph"].boundary_models, ["adami_wall_particles"])
        self.assertIsNone(catalogue["nopromise"].still_water_promise)
        self.assertEqual(catalogue["isph"].parameter_defaults, {"max_time_step": "0.002"})

    def test_short_study_of_one_method_with_every_boundary_model(self):
        # wcsph to 0.6 s, its sensors over [0.3, 0.6] s: one row per boundary model it supports,
        # each completed, within the still-water test's guard band [0.75, 1.7] rho g h (a broken
        # sensor or a lost gravity term falls outside: tests/test_pressure_sensors.cpp), the dry
        # sensor exactly 0, and the markdown's summary line with the declared promise. Two
        # realisations: wcsph's water comes to rest, so they agree (standard error below 1e-6).
        out = os.path.join(self.folder, "study")
        result = subprocess.run([sys.executable, os.path.join(ROOT, "analysis", "still_water.py"), "--out", out,
                                 "--binary", BINARY, "--methods", "wcsph", "--end-time", "0.6", "--window", "0.3",
                                 "0.6", "--parallel", "2", "--realisations", "2"], capture_output=True, text=True)
        self.assertEqual(result.returncode, 0, result.stderr)
        catalogue = methods.method_catalogue(BINARY)
        with open(os.path.join(out, "still_water.csv"), newline="") as handle:
            rows = list(csv.DictReader(handle))
        self.assertEqual(sorted(row["boundary_model"] for row in rows),
                         sorted(2 * catalogue["wcsph"].boundary_models))
        for row in rows:
            self.assertEqual(row["status"], "completed")
            self.assertEqual(float(row["dry"]), 0.0)
            for column in still_water.RATIOS:
                self.assertTrue(0.75 < float(row[column]) < 1.7, row)
        promise = f"promise {100 * catalogue['wcsph'].still_water_promise:g} %"
        self.assertIn(promise, result.stdout)
        self.assertIn(f"of {3 * len(rows)}**", result.stdout)
        with open(os.path.join(out, "still_water_expected.csv"), newline="") as handle:
            expected = list(csv.DictReader(handle))
        self.assertEqual(sorted(row["boundary_model"] for row in expected), sorted(catalogue["wcsph"].boundary_models))
        for row in expected:
            self.assertEqual(row["realisations"], "2")
            for column in still_water.RATIOS:
                self.assertLess(float(row[f"se_{column}"]), 1e-6, row)
                self.assertIn(row[f"verdict_{column}"], ("within", "outside"), row)
        self.assertIn("Expected reading over the realisations", result.stdout)
        with open(os.path.join(out, "still_water_expected.png"), "rb") as handle:
            self.assertEqual(handle.read(8), b"\x89PNG\r\n\x1a\n")  # the figure, a PNG

    def test_bad_input_is_one_line_and_exit_2(self):
        result = subprocess.run([sys.executable, os.path.join(ROOT, "analysis", "still_water.py"), "--out",
                                 os.path.join(self.folder, "bad"), "--binary", BINARY, "--methods", "nosuch"],
                                capture_output=True, text=True)
        self.assertEqual(result.returncode, 2)
        self.assertEqual(len(result.stderr.strip().splitlines()), 1, result.stderr)
        self.assertIn("--methods.nosuch: not a registered method", result.stderr)


if __name__ == "__main__":
    unittest.main()
