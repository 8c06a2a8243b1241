"""The mps_lab analysis package: reading run folders, the metrics against Martin & Moyce,
the figures, the comparison report, one case runner and the studies.

    data.py        run folders (run.json, series.csv, frames), the validation data, the metrics
    methods.py     the registered methods, asked from the binary (`mps_lab methods`), and the
                   colour and marker of each one
    runner.py      finds the binary and runs one case (arguments, timeout, threads, one retry)
    figures.py     one function per figure of the comparison
    report.py      the comparison report (what `mps_lab compare` calls through analysis/compare.py)
    studies/       sweep, stability_map, wall_study, performance, cost, pressure_noise

The scripts analysis/*.py only parse their arguments and call into this package.
"""
import os

# The source tree (the folder that holds analysis/, scenes/ and build/).
SOURCE_ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
ANALYSIS_DIR = os.path.join(SOURCE_ROOT, "analysis")
