"""The wall study (analysis/wall_study.py) on a tiny real study: MPS with its default wall and
with dummy layers on the water at rest and the dam break (--quick), wall_study.csv has its
rows and columns, the table and the figure are written and a second call resumes without
running anything; a binary that fails is recorded, not a crash; the metrics on synthetic
data with known answers (noise of a sine plus white noise, the hydrostatic ratios of an
exact and a scaled pressure field). Run by CTest; MPS_LAB_BINARY names build/mps_lab."""
from __future__ import annotations

import csv
import json
import math
import os
import shutil
import stat
import subprocess
import sys
import tempfile
import unittest

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
from mps_lab import methods  # noqa: E402
from mps_lab.studies import wall_study  # noqa: E402

BINARY = os.environ.get("MPS_LAB_BINARY", os.path.join(ROOT, "build", "mps_lab"))
RHO, G = 1000.0, 9.81


def lattice_frame(scale: float = 1.0) -> dict[str, np.ndarray]:
    """The hydrostatic tank's fluid lattice with p = scale rho g (y_top - y), and wall particles
    (type 1) with a pressure that must be ignored."""
    x, y = np.meshgrid(0.025 * np.arange(1, 20), 0.025 * np.arange(1, 12))
    x, y = x.ravel(), y.ravel()
    p = scale * RHO * G * (wall_study.HYDRO_Y_TOP - y)
    wall_x, wall_y = 0.025 * np.arange(20), np.zeros(20)
    return {"x": np.concatenate([x, wall_x]), "y": np.concatenate([y, wall_y]),
            "pressure": np.concatenate([p, np.full(20, 1e6)]), "type": np.concatenate([np.zeros(x.size), np.ones(20)])}


class WallStudyTest(unittest.TestCase):
    def setUp(self):
        self.folder = tempfile.mkdtemp(prefix="mps_lab_wall_study_")
        self.out = os.path.join(self.folder, "out")

    def tearDown(self):
        shutil.rmtree(self.folder, ignore_errors=True)

    def study(self, *extra, binary=BINARY):
        return subprocess.run([sys.executable, os.path.join(ROOT, "analysis", "wall_study.py"), "--out", self.out,
                               "--binary", binary, "--quick", "--methods", "mps", *extra],
                              capture_output=True, text=True)

    def rows(self):
        with open(os.path.join(self.out, "wall_study.csv"), newline="") as handle:
            reader = csv.DictReader(handle)
            return reader.fieldnames, list(reader)

    def test_quick_study_runs_collects_and_resumes(self):
        arguments = ["--models", "default", "dummy_layers", "--scenes", "hydrostatic", "dambreak"]
        result = self.study(*arguments, "--parallel", "2")
        self.assertEqual(result.returncode, 0, result.stderr)
        columns, rows = self.rows()
        self.assertEqual(columns, wall_study.COLUMNS)
        by_case = {(r["scene"], r["boundary_model"]): r for r in rows}
        self.assertEqual(sorted(by_case), [("dambreak", "dummy_layers"), ("dambreak", "spec_wall_particles"),
                                           ("hydrostatic", "dummy_layers"), ("hydrostatic", "spec_wall_particles")])
        for (scene, model), row in by_case.items():
            self.assertIn(row["status"], wall_study.FINISHED, row["message"])
            self.assertEqual(row["model_in_run"], model)
            self.assertEqual(row["model_reported"], model)
            self.assertEqual(row["default"], str(model == "spec_wall_particles"))
            self.assertGreater(float(row["wall_seconds"]), 0.0)
            self.assertGreater(float(row["particle_steps_per_second"]), 0.0)
            self.assertGreaterEqual(int(row["penetrations"]), 0)
            self.assertNotEqual(row["min_wall_distance_over_l0"], "")
        default = by_case[("hydrostatic", "spec_wall_particles")]
        self.assertEqual(int(default["hydro_frames"]), 3)  # t = 0.5, 0.55, 0.6 of the quick run
        self.assertAlmostEqual(float(default["wall_pressure_ratio"]), 1.0, delta=0.15)
        self.assertAlmostEqual(float(default["dpdy_ratio"]), 1.0, delta=0.15)
        self.assertEqual(default["sensor_noise_kpa"], "")
        dam = by_case[("dambreak", "spec_wall_particles")]
        self.assertEqual(dam["status"], "completed", dam["message"])
        self.assertTrue(0.0 < float(dam["front_rms"]) < 2.0)
        self.assertTrue(float(dam["sensor_peak_kpa"]) > 1.0)  # the surge reaches the right wall by t = 0.4 s
        self.assertTrue(float(dam["sensor_noise_kpa"]) >= 0.0)
        self.assertEqual(dam["wall_pressure_ratio"], "")
        with open(os.path.join(self.out, "wall_study.md")) as handle:
            table = handle.read()
        self.assertIn("| mps | spec_wall_particles (d) | completed |", table)
        self.assertIn("## Water at rest", table)
        self.assertGreater(os.path.getsize(os.path.join(self.out, "wall_study.png")), 10000)

        result = self.study(*arguments)
        self.assertEqual(result.returncode, 0, result.stderr)
        self.assertIn("4 finished, running 0", result.stdout)

    def test_failing_binary_is_recorded(self):
        fake = os.path.join(self.folder, "fake_mps_lab")
        with open(fake, "w") as handle:
            # lists the real methods (the study asks for them), refuses every run
            handle.write(f"#!/bin/sh\nif [ \"$1\" = methods ]; then exec '{os.path.abspath(BINARY)}' \"$@\"; fi\n"
                         "echo 'mps_lab: error: something unsupported' >&2\nexit 2\n")
        os.chmod(fake, os.stat(fake).st_mode | stat.S_IEXEC)
        result = self.study("--models", "mirror_particles", "--scenes", "hydrostatic", binary=fake)
        self.assertEqual(result.returncode, 0, result.stderr)
        _, rows = self.rows()
        self.assertEqual(len(rows), 1)
        self.assertEqual(rows[0]["status"], "error")
        self.assertIn("something unsupported", rows[0]["message"])

    def test_sensor_noise_of_sine_plus_white_noise(self):
        t = np.arange(0.0, 2.0 + 1e-9, 2.5e-4)
        sine = 1000.0 * np.sin(2.0 * math.pi * t)
        self.assertAlmostEqual(wall_study.sensor_noise(t, np.full_like(t, 5.0)), 0.0, places=9)
        self.assertAlmostEqual(wall_study.sensor_noise(t, 3.0 + 40.0 * t), 0.0, places=9)  # a ramp is no noise
        # A 1 Hz sine through a 0.05 s boxcar loses 1 - sinc ~ 0.4 % of its amplitude: RMS ~ 3.
        self.assertLess(wall_study.sensor_noise(t, sine), 4.0)
        noise = np.random.default_rng(1).normal(0.0, 50.0, t.size)
        # White noise minus its 0.05 s mean (200 samples): sigma within the sampling error.
        self.assertAlmostEqual(wall_study.sensor_noise(t, sine + noise) / 50.0, 1.0, delta=0.03)
        # Unevenly sampled (an adaptive step): the same noise level.
        uneven = np.sort(np.random.default_rng(2).uniform(0.0, 2.0, 8000))
        p = 1000.0 * np.sin(2.0 * math.pi * uneven) + np.random.default_rng(3).normal(0.0, 50.0, uneven.size)
        self.assertAlmostEqual(wall_study.sensor_noise(uneven, p) / 50.0, 1.0, delta=0.05)
        # Coarse sampling (every 0.005 s, like series.csv): the 0.05 s average holds the sample
        # itself with weight 1/10 (the window's end samples 1/20): sqrt(0.81 + 8/100 + 2/400) sigma.
        coarse = t[::20]
        self.assertAlmostEqual(wall_study.sensor_noise(coarse, sine[::20] + noise[::20]) / 50.0, math.sqrt(0.895),
                               delta=0.08)
        self.assertTrue(math.isnan(wall_study.sensor_noise(t[:2], sine[:2])))
        self.assertTrue(math.isnan(wall_study.sensor_noise(t[t < 0.2], sine[t < 0.2])))  # nothing in [0.3, 2]
        peak, when = wall_study.sensor_peak(t, sine)
        self.assertAlmostEqual(peak, 1000.0, places=3)
        self.assertAlmostEqual(when, 1.25, places=6)  # the first maximum inside [0.3, 2]

    def test_hydrostatic_ratios(self):
        ratio, slope = wall_study.hydrostatic_frame(lattice_frame(), RHO, G)
        self.assertAlmostEqual(ratio, 1.0, places=12)
        self.assertAlmostEqual(slope, 1.0, places=12)
        ratio, slope = wall_study.hydrostatic_frame(lattice_frame(0.9), RHO, G)
        self.assertAlmostEqual(ratio, 0.9, places=12)
        self.assertAlmostEqual(slope, 0.9, places=12)
        frame = lattice_frame()
        fluid = frame["type"] == 0
        frame["pressure"][fluid & (frame["y"] > wall_study.HYDRO_Y_TOP - wall_study.HYDRO_SURFACE_BAND)] = 0.0
        ratio, slope = wall_study.hydrostatic_frame(frame, RHO, G)  # the surface rows are left out of the fit
        self.assertAlmostEqual(slope, 1.0, places=12)
        frame = lattice_frame()
        frame["pressure"][fluid & (frame["y"] < 0.03) & (frame["x"] < 0.09)] = 0.0
        ratio, slope = wall_study.hydrostatic_frame(frame, RHO, G)  # the bottom-row corners are left out
        self.assertAlmostEqual(ratio, 1.0, places=12)
        frame = lattice_frame()
        frame["pressure"][fluid & (frame["y"] < 0.03)] *= 1.2  # only the bottom row counts in the ratio
        self.assertAlmostEqual(wall_study.hydrostatic_frame(frame, RHO, G)[0], 1.2, places=12)

    def test_level_at_rest_from_the_particle_count(self):
        # The flat tank of scenes/hydrostatic.json: 19 x 11 particles between wall surfaces 0.475 m
        # apart fill 0.275 m above the bed's surface 0.0125 m: the lattice's top + l0/2, 0.2875 m.
        with open(os.path.join(ROOT, "scenes", "hydrostatic.json")) as handle:
            flat = json.load(handle)
        self.assertAlmostEqual(wall_study.rest_level(flat, 19 * 11), 0.2875, places=9)
        # The wedge of scenes/hydrostatic_slope.json (a triangle 0.3375 x 0.157379 m): above its top the
        # water's area is 0.475 (eta - 0.0125) - 0.026558 m^2; N = 159 gives eta = 0.27762 m, not the
        # lattice's 0.2875 m (tests/test_wall_polygons.cpp measures the same 0.2776 m).
        with open(os.path.join(ROOT, "scenes", "hydrostatic_slope.json")) as handle:
            slope = json.load(handle)
        wedge = 0.5 * 0.3375 * (0.169879 - 0.0125)
        expected = 0.0125 + (159 * 0.025 ** 2 + wedge) / 0.475
        self.assertAlmostEqual(wall_study.rest_level(slope, 159), expected, places=7)
        self.assertAlmostEqual(expected, 0.27762, places=5)

    def test_cases_and_commands(self):
        catalogue = methods.method_catalogue(BINARY)
        if not {"mps", "dfsph"} <= set(catalogue):
            self.skipTest("a build without mps or dfsph (MPS_LAB_METHODS)")
        cases = wall_study.cases_of(catalogue, ["mps", "dfsph"], ["default", "mirror_particles"], ["hydrostatic"])
        self.assertEqual([c["name"] for c in cases], ["hydrostatic__mps__spec_wall_particles",
                                                      "hydrostatic__mps__mirror_particles",
                                                      "hydrostatic__dfsph__akinci_boundary",
                                                      "hydrostatic__dfsph__mirror_particles"])
        command = wall_study.arguments_of(cases[1], "/o")
        self.assertIn("methods.mps.wall_treatments.mirror_particles={}", command)
        self.assertIn("stability.on_divergence=\"continue\"", command)
        self.assertIn("output.frame_interval=0.05", command)
        self.assertEqual(command[command.index("--end-time") + 1], "1.0")
        self.assertFalse(any("wall_treatments" in a for a in wall_study.arguments_of(cases[0], "/o")))

    def test_model_variants(self):
        catalogue = methods.method_catalogue(BINARY)
        if "mps" not in catalogue or "distance_function" not in catalogue["mps"].boundary_models:
            self.skipTest("a build without mps or its distance_function")
        cases = wall_study.cases_of(catalogue, ["mps"], ["distance_function", "distance_function:corners=blended"],
                                    ["hydrostatic_slope"])
        self.assertEqual([c["name"] for c in cases], ["hydrostatic_slope__mps__distance_function",
                                                      "hydrostatic_slope__mps__distance_function:corners=blended"])
        self.assertEqual(cases[1]["boundary_model"], "distance_function:corners=blended")
        self.assertFalse(cases[1]["default"])
        command = wall_study.arguments_of(cases[1], "/o")
        self.assertIn('methods.mps.wall_treatments.distance_function={"corners": "blended"}', command)
        self.assertIn("methods.mps.wall_treatments.spec_wall_particles.enabled=false", command)
        # a variant of the method's own model keeps it on and sets its parameters; JSON values parse
        self.assertEqual(wall_study.model_variant("dummy_layers:layers=4,crossing=none"),
                         ("dummy_layers", {"layers": 4, "crossing": "none"}))
        own = wall_study.cases_of(catalogue, ["mps"], ["spec_wall_particles:enabled=true"], ["hydrostatic"])
        self.assertEqual(own[0]["overrides"]["methods.mps.wall_treatments.spec_wall_particles"], {"enabled": True})
        self.assertNotIn("methods.mps.wall_treatments.spec_wall_particles.enabled", own[0]["overrides"])
        with self.assertRaises(ValueError):
            wall_study.model_variant("distance_function:corners")


if __name__ == "__main__":
    unittest.main()
