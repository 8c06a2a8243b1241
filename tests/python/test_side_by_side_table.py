"""tools/reference-codes/side_by_side_table.py on synthetic result lines with known answers: the
ratios of the medians, the paired ratio of each repetition (its two runs back to back) and the
count of pairs that reach the target. Run by CTest."""
from __future__ import annotations

import os
import pathlib
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "tools", "reference-codes"))
import side_by_side_table  # noqa: E402


def line(repetition, code, wall, steps, particles=1000):
    rate = particles * steps / wall
    return (f"repetition={repetition} pair=dfsph-0.1 load1=0.5 code={code} case=c threads=2 end_time=1.0 "
            f"wall_s={wall} particles={particles} steps={steps} particle_steps_per_s={rate}")


class SideBySideTableTest(unittest.TestCase):
    def setUp(self):
        # Repetition 1: ours 2.5x the reference's particle-steps/s; repetition 2: 1.5x.
        self.lines = [line(1, "splishsplash", 10.0, 1000), line(1, "mps_lab", 4.0, 1000),
                      line(2, "mps_lab", 4.0, 1000), line(2, "splishsplash", 6.0, 1000)]

    def test_paired_ratios_are_per_repetition(self):
        runs = [dict(token.split("=", 1) for token in text.split()) for text in self.lines]
        self.assertEqual([round(x, 6) for x in side_by_side_table.paired_ratios("dfsph-0.1", runs)], [2.5, 1.5])

    def test_markdown_row_reports_medians_and_pairs(self):
        with tempfile.TemporaryDirectory() as out:
            lines = pathlib.Path(out) / "lines.txt"
            lines.write_text("\n".join(self.lines) + "\n")
            sys.argv = ["side_by_side_table.py", str(lines), out, "--load-before", "b", "--load-after", "a"]
            side_by_side_table.main()
            table = (pathlib.Path(out) / "reference_codes.md").read_text()
        # Medians: reference 133.3 k particle-steps/s (of 100 k and 166.7 k), ours 250 k: 1.88x per
        # particle-step; walls 8 / 4 s: 2.00x per simulated second; the per-step target is missed.
        self.assertIn("**1.88×** | 1.50–2.50× (1 of 2 ≥ 2×) | **2.00×** | ≥ 2× per particle-step and per simulated "
                      "second: missed |", table)


if __name__ == "__main__":
    unittest.main()
