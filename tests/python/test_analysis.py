"""Tests of analysis/: the metrics against a known answer, the C++ and Python definitions
against each other, and every figure of the comparison produced from a small real run.

Run by CTest with Debian's python3 (numpy, matplotlib); MPS_LAB_BINARY names build/mps_lab.
"""
from __future__ import annotations

import csv
import json
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
from mps_lab import data  # noqa: E402

BINARY = os.environ.get("MPS_LAB_BINARY", os.path.join(ROOT, "build", "mps_lab"))


class CurveErrorTest(unittest.TestCase):
    def test_offset_and_planted_shift(self):
        exp_t, exp_z = data.martin_moyce_front()
        t = np.linspace(0.0, 4.0, 2001)
        z = np.interp(t, np.r_[0.0, exp_t, 5.0], np.r_[1.0, exp_z, exp_z[-1] + 1.67])
        rms, largest, points = data.curve_error(t, z + 0.1, exp_t, exp_z)
        self.assertEqual(points, 15)
        self.assertAlmostEqual(rms, 0.1, places=9)
        self.assertAlmostEqual(largest, 0.1, places=9)
        # planted lead of 0.15: the search returns it, and the shifted RMS is at the
        # interpolation error of the 0.002-spaced samples (< 0.005)
        ahead = np.interp(t + 0.15, np.r_[0.0, exp_t, 5.0], np.r_[1.0, exp_z, exp_z[-1] + 1.67])
        rms_shifted, _, _, shift = data.best_shift_error(t, ahead, exp_t, exp_z)
        self.assertAlmostEqual(shift, 0.15, delta=0.002)
        self.assertLess(rms_shifted, 0.005)


class ComparisonTest(unittest.TestCase):
    """One real comparison, short (0.3 s of the dam break), all registered methods."""

    @classmethod
    def setUpClass(cls):
        cls.folder = tempfile.mkdtemp(prefix="mps_lab_compare_")
        environment = dict(os.environ, OMP_NUM_THREADS="1")
        result = subprocess.run([BINARY, "compare", os.path.join(ROOT, "scenes", "dambreak.json"), "--out", cls.folder,
                                 "--end-time", "0.3", "--quiet"], capture_output=True, text=True, env=environment)
        cls.result = result

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.folder, ignore_errors=True)

    def test_compare_succeeds_and_writes_every_figure(self):
        self.assertEqual(self.result.returncode, 0, self.result.stderr)
        for name in ["summary.csv", "report.md", "front.png", "height.png", "snapshots.png", "wall_pressure.png",
                     "energy.png"]:
            path = os.path.join(self.folder, name)
            self.assertTrue(os.path.isfile(path), name)
            self.assertGreater(os.path.getsize(path), 1000 if name.endswith(".png") else 100, name)
        animations = [n for n in os.listdir(self.folder) if n.startswith("animation.")]
        self.assertEqual(len(animations), 1)
        with open(os.path.join(self.folder, "report.md")) as handle:
            report = handle.read()
        for figure in ["front.png", "snapshots.png", "wall_pressure.png", "energy.png"]:
            self.assertIn(f"]({figure})", report)
        self.assertIn("| method | status |", report)
        # Each run lists the assignments it was made with (run.json "overrides"): here --end-time.
        self.assertEqual(report.count("; overrides: `time.end_time=0.3`"), self.method_count())

    def method_count(self):
        return len(subprocess.run([BINARY, "methods"], capture_output=True, text=True).stdout.splitlines())

    def test_html_report_is_one_self_contained_file(self):
        """report.html holds every figure of report.md inline (data: URIs) and no link to a file."""
        with open(os.path.join(self.folder, "report.html")) as handle:
            page = handle.read()
        self.assertTrue(page.startswith("<!DOCTYPE html>"))
        with open(os.path.join(self.folder, "report.md")) as handle:
            figures_in_markdown = handle.read().count("![")
        embedded = page.count('src="data:image/png;base64,') + page.count('src="data:image/gif;base64,') + \
            page.count('src="data:video/mp4;base64,')
        self.assertEqual(embedded, figures_in_markdown)
        self.assertNotRegex(page, r'src="(?!data:)')
        self.assertNotRegex(page, r'href="')
        listed = subprocess.run([BINARY, "methods"], capture_output=True, text=True).stdout.splitlines()
        self.assertEqual(page.count("<tr>") - 1, len(listed))  # a row per method under the header

    def test_python_recomputes_the_summary(self):
        """summary.csv (C++) and the same metrics computed by analysis/ agree to round-off."""
        with open(os.path.join(self.folder, "summary.csv"), newline="") as handle:
            rows = {row["method"]: row for row in csv.DictReader(handle)}
        listed = subprocess.run([BINARY, "methods"], capture_output=True, text=True).stdout.splitlines()
        self.assertEqual(set(rows), {line.split()[0] for line in listed})
        exp_t, exp_z = data.martin_moyce_front()
        exp_tau, exp_h = data.martin_moyce_height()
        for method, row in rows.items():
            run = data.load_run(os.path.join(self.folder, method))
            t, z = run.front_curve()
            rms, largest, points = data.curve_error(t, z, exp_t, exp_z)
            shifted = data.best_shift_error(t, z, exp_t, exp_z)
            tau, h = run.height_curve()
            h_rms, _, h_points = data.curve_error(tau, h, exp_tau, exp_h)
            self.assertEqual(int(row["front_points"]), points, method)
            self.assertAlmostEqual(float(row["front_rms"]), rms, places=9, msg=method)
            self.assertAlmostEqual(float(row["front_max"]), largest, places=9, msg=method)
            self.assertAlmostEqual(float(row["front_best_shift"]), shifted[3], places=9, msg=method)
            self.assertAlmostEqual(float(row["front_rms_shifted"]), shifted[0], places=9, msg=method)
            self.assertEqual(int(row["height_points"]), h_points, method)
            self.assertAlmostEqual(float(row["height_rms"]), h_rms, places=9, msg=method)
            with open(os.path.join(self.folder, method, "run.json")) as handle:
                self.assertEqual(row["status"], json.load(handle)["status"])


class AnimationFallbackTest(unittest.TestCase):
    """The animation is an MP4 with Debian's ffmpeg (tools/install-dependencies.sh installs it) and a
    GIF without it; both from the same two-frame run folder."""

    @classmethod
    def setUpClass(cls):
        cls.folder = tempfile.mkdtemp(prefix="mps_lab_animation_")
        environment = dict(os.environ, OMP_NUM_THREADS="1")
        cls.result = subprocess.run([BINARY, "run", "--method", "mps", os.path.join(ROOT, "scenes", "dambreak.json"),
                                     "--out", os.path.join(cls.folder, "run"), "--end-time", "0.1", "--quiet"],
                                    capture_output=True, text=True, env=environment)

    @classmethod
    def tearDownClass(cls):
        shutil.rmtree(cls.folder, ignore_errors=True)

    def animate(self, ffmpeg: bool) -> str:
        from unittest import mock
        from mps_lab import figures
        self.assertEqual(self.result.returncode, 0, self.result.stderr)
        run = data.load_run(os.path.join(self.folder, "run"))
        with mock.patch.object(figures, "ffmpeg_available", return_value=ffmpeg):
            return figures.make_animation([run], os.path.join(self.folder, "mp4" if ffmpeg else "gif"))

    def test_gif_without_ffmpeg(self):
        path = self.animate(False)
        self.assertTrue(path.endswith(".gif"))
        with open(path, "rb") as handle:
            self.assertEqual(handle.read(6), b"GIF89a")

    def test_mp4_with_ffmpeg(self):
        from mps_lab import figures
        if not shutil.which("ffmpeg"):
            self.fail("ffmpeg is missing: tools/install-dependencies.sh installs it")
        self.assertTrue(figures.ffmpeg_available())
        path = self.animate(True)
        self.assertTrue(path.endswith(".mp4"))
        with open(path, "rb") as handle:
            self.assertEqual(handle.read(12)[4:8], b"ftyp")  # an ISO media file


if __name__ == "__main__":
    unittest.main()
