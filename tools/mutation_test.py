#!/usr/bin/python3
"""Mutation testing of the MPS specification (issue 18, part 4).

Applies one mutation at a time from tests/mutations/mps_spec.json to the source tree (in
place; the original text is always written back, also on Ctrl-C or a failed build),
rebuilds the test binary incrementally, runs the quick suite and reports per mutation
whether it was killed and by which tests.

The quick suite is the CTest label "spec": every Catch2 test tagged [spec]
(tests/test_mps_spec_*.cpp; tests/CMakeLists.txt gives them the labels unit and spec).
None of them is a regression comparison against stored output (tests/test_regression.cpp
is tagged [regression], not [spec]), so a mutation the suite kills is killed by a test of
the spec item itself. A mutation that does not compile counts as killed by the compiler
("build"); none of the list does (checked).

    tools/mutation_test.py                  # the whole list -> docs/data/mutation_report.csv
    tools/mutation_test.py --only ID [--only ID2]   # updates those rows of the report
    tools/mutation_test.py --check          # every `old` occurs exactly once; no build

A second list, tests/mutations/pressure_schemes.json, mutates the mps pressure schemes (CMPS,
HS, HL, ECS, the mixed source, GC) and the dry-wall rule of mps and isph; its quick suite is
the Catch2 test spec in QUICK_SUITES (the schemes', loads' and isph surface tests, run by the
test binary itself), its report docs/data/mutation_report_pressure_schemes.csv:

    tools/mutation_test.py --list tests/mutations/pressure_schemes.json [--check]

tests/mutations/pressure_sensors.json the wall-pressure sensor (core/run/pressure_sensors.cpp,
core/walls/wall_pressure_extrapolation.hpp), quick suite the [sensor] tests, and
tests/mutations/distance_function_corners.json the distance function's blended corners
(core/walls/distance_function.cpp), quick suite tests/test_distance_function_corners.cpp and the
still-water loads on the submerged box and the plate (tests/test_obstacle_loads.cpp), and
tests/mutations/particle_shifting.json the particle shifting (core/walls/particle_shifting.cpp),
quick suite the [shifting] tests, and tests/mutations/wall_sample_pressure.json the wall samples' fitted
pressure of isph and eisph (core/walls/wall_sample_pressure.hpp, methods/isph/isph_operators.*), quick
suite tests/test_isph_wall_sample_pressure.cpp, and tests/mutations/load_settings.json the methods'
load settings (MethodInfo::load_setting: each entry the issue-14 measurements rest on), quick suite
the load settings' still-water promises and their spec dam breaks, and tests/mutations/eisph_sweeps.json
eisph's `sweeps_per_step` (methods/eisph/eisph_method.cpp), quick suite its test in tests/test_eisph.cpp.

Exit status: 0 when every mutation run was killed, 1 when one survived, 2 on bad input.
"""
import argparse
import csv
import html
import json
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
MUTATIONS = ROOT / "tests" / "mutations" / "mps_spec.json"
REPORT = ROOT / "docs" / "data" / "mutation_report.csv"
# The quick suite of each list other than the spec's: a Catch2 test spec for the test binary.
QUICK_SUITES = {"pressure_schemes.json": "[schemes],[loads],[surface]", "pressure_sensors.json": "[sensor]",
                "distance_function_corners.json": "distance function corners*,obstacle loads: still water*",
                "particle_shifting.json": "[shifting]", "wall_sample_pressure.json": "wall sample pressure*",
                "load_settings.json": "wall pressure: each method's load setting*,*load setting: the spec dam break*",
                "eisph_sweeps.json": "EISPH sweeps_per_step*"}
REQUIRED_KEYS = ("id", "spec", "item", "file", "old", "new")
CTEST_LABEL = "spec"
TEST_TIMEOUT_SECONDS = 120  # per test; a mutation that makes a test hang is killed by the timeout
BUILD_TIMEOUT_SECONDS = 1800


def load_mutations(path):
    """The list from the JSON file; exits with status 2 naming the file and entry on bad input."""
    try:
        mutations = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as error:
        sys.exit(f"{path}: cannot read the mutation list: {error}")
    if not isinstance(mutations, list):
        sys.exit(f"{path}: expected a JSON list of mutations")
    seen = set()
    for index, mutation in enumerate(mutations):
        missing = [key for key in REQUIRED_KEYS if not isinstance(mutation.get(key), str) or not mutation.get(key)]
        if missing:
            sys.exit(f"{path}: entry {index}: expected non-empty strings for {', '.join(missing)}")
        if mutation["id"] in seen:
            sys.exit(f"{path}: entry {index}: id '{mutation['id']}' appears twice")
        if mutation["old"] == mutation["new"]:
            sys.exit(f"{path}: entry {index} ('{mutation['id']}'): old and new are the same text")
        seen.add(mutation["id"])
    return mutations


def check(mutations):
    """Every `old` occurs exactly once in its file. Returns the list of problems."""
    problems = []
    for mutation in mutations:
        source = ROOT / mutation["file"]
        if not source.is_file():
            problems.append(f"{mutation['id']}: file {mutation['file']} does not exist")
            continue
        count = source.read_text(encoding="utf-8").count(mutation["old"])
        if count != 1:
            problems.append(f"{mutation['id']}: `old` occurs {count} times in {mutation['file']}, expected exactly once")
    return problems


class AppliedMutation:
    """Context manager: the mutated file while inside, the original text afterwards, always.

    SIGINT and SIGTERM are turned into KeyboardInterrupt so that the finally clause runs.
    """

    def __init__(self, mutation):
        self.path = ROOT / mutation["file"]
        self.mutation = mutation
        self.original = None

    def __enter__(self):
        self.original = self.path.read_text(encoding="utf-8")
        if self.original.count(self.mutation["old"]) != 1:
            raise RuntimeError(f"{self.mutation['id']}: `old` is not exactly once in {self.mutation['file']}")
        self.path.write_text(self.original.replace(self.mutation["old"], self.mutation["new"]), encoding="utf-8")
        return self

    def __exit__(self, *exc):
        self.path.write_text(self.original, encoding="utf-8")
        return False


def raise_interrupt(signum, frame):
    raise KeyboardInterrupt(f"signal {signum}")


def build(build_dir, jobs):
    """Incremental build of the test binary (and the mps_lab binary it depends on)."""
    command = ["cmake", "--build", str(build_dir), "--target", "mps_lab_tests", "-j", str(jobs)]
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                            timeout=BUILD_TIMEOUT_SECONDS)
    return result.returncode == 0, result.stdout


def run_quick_suite(build_dir, jobs):
    """Runs `ctest -L spec`; returns (all passed, failed test names, count run).

    The failed names come from CTest's Testing/Temporary/LastTestsFailed.log ("index:name"
    per line), which keeps names with parentheses whole.
    """
    failed_log = Path(build_dir) / "Testing" / "Temporary" / "LastTestsFailed.log"
    if failed_log.exists():
        failed_log.unlink()
    command = ["ctest", "--test-dir", str(build_dir), "-L", CTEST_LABEL, "-j", str(jobs),
               "--timeout", str(TEST_TIMEOUT_SECONDS)]
    result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    failed = []
    if failed_log.exists():
        for line in failed_log.read_text(encoding="utf-8").splitlines():
            if ":" in line:
                failed.append(line.split(":", 1)[1].strip())
    total = re.search(r"tests passed, \d+ tests failed out of (\d+)", result.stdout)
    return result.returncode == 0, failed, int(total.group(1)) if total else 0


def run_catch_suite(build_dir, test_spec):
    """Runs the test binary on `test_spec` (one thread, JUnit report); returns (all passed,
    failed test names, count run)."""
    report = Path(build_dir) / "Testing" / "mutation_catch_report.xml"
    report.parent.mkdir(parents=True, exist_ok=True)
    if report.exists():
        report.unlink()  # a crashed binary must not leave the last mutation's report to be read
    command = [str(Path(build_dir) / "tests" / "mps_lab_tests"), test_spec, "-r", "junit", "-o", str(report)]
    environment = dict(os.environ, OMP_NUM_THREADS="1")
    try:
        result = subprocess.run(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=environment,
                                timeout=10 * TEST_TIMEOUT_SECONDS)
    except subprocess.TimeoutExpired:
        return False, ["timeout"], 1
    cases = re.findall(r'<testcase [^>]*name="([^"]*)"[^>]*?(/>|>.*?</testcase>)',
                       report.read_text(encoding="utf-8") if report.is_file() else "", re.S)
    failed = [html.unescape(name) for name, body in cases if "<failure" in body or "<error" in body]
    return result.returncode == 0, failed, len(cases)


def run_one(mutation, build_dir, jobs, catch_spec=None):
    """Applies, builds, tests and restores one mutation; returns its report row."""
    start = time.monotonic()
    with AppliedMutation(mutation):
        built, log = build(build_dir, jobs)
        if not built:
            killers = ["build"]
        else:
            passed, killers, count = (run_catch_suite(build_dir, catch_spec) if catch_spec
                                      else run_quick_suite(build_dir, jobs))
            if count == 0:
                raise RuntimeError("the quick suite ran no test: is the build folder configured with tests?")
            if not passed and not killers:
                killers = ["ctest (unparsed failure)"]
    seconds = time.monotonic() - start
    return {"id": mutation["id"], "spec": mutation["spec"], "item": mutation["item"],
            "result": "killed" if killers else "survived", "killing_tests": "; ".join(killers),
            "seconds": f"{seconds:.1f}"}


def merge_with_existing(rows, path, mutations):
    """With --only: the existing report's rows with this run's rows replacing theirs, in the
    order of the mutation list (rows of mutations no longer listed are dropped)."""
    by_id = {}
    if path.is_file():
        with path.open(newline="", encoding="utf-8") as handle:
            by_id = {row["id"]: row for row in csv.DictReader(handle)}
    by_id.update({row["id"]: row for row in rows})
    return [by_id[m["id"]] for m in mutations if m["id"] in by_id]


def write_report(rows, path):
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("w", newline="", encoding="utf-8") as handle:
        writer = csv.DictWriter(handle, fieldnames=["id", "spec", "item", "result", "killing_tests", "seconds"])
        writer.writeheader()
        writer.writerows(rows)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--only", action="append", metavar="ID", help="run only this mutation (repeatable)")
    parser.add_argument("--check", action="store_true", help="only check that every `old` occurs exactly once")
    parser.add_argument("--build-dir", default=str(ROOT / "build"), help="configured CMake build folder (default build/)")
    parser.add_argument("--jobs", type=int, default=2, help="parallel build and ctest jobs (default 2)")
    parser.add_argument("--list", default=str(MUTATIONS), help="mutation list (default tests/mutations/mps_spec.json)")
    parser.add_argument("--report", help="CSV report (default docs/data/mutation_report.csv for the spec's list, "
                        "docs/data/mutation_report_<list name>.csv for another)")
    args = parser.parse_args()

    mutation_list = Path(args.list)
    catch_spec = None
    if mutation_list.resolve() != MUTATIONS:
        if mutation_list.name not in QUICK_SUITES:
            sys.exit(f"--list {mutation_list}: no quick suite for it (expected one of {', '.join(QUICK_SUITES)})")
        catch_spec = QUICK_SUITES[mutation_list.name]
    if args.report is None:
        args.report = str(REPORT if catch_spec is None else
                          REPORT.with_name(f"mutation_report_{mutation_list.stem}.csv"))
    all_mutations = mutations = load_mutations(mutation_list)
    problems = check(mutations)
    if args.check or problems:
        for problem in problems:
            print(problem, file=sys.stderr)
        print(f"{len(mutations)} mutations, {len(problems)} problems")
        return 2 if problems else 0
    if args.only:
        unknown = sorted(set(args.only) - {m["id"] for m in mutations})
        if unknown:
            sys.exit(f"--only: no mutation called {', '.join(unknown)} in {mutation_list}")
        mutations = [m for m in mutations if m["id"] in args.only]
    build_dir = Path(args.build_dir)
    if not (build_dir / "CMakeCache.txt").is_file():
        sys.exit(f"--build-dir {build_dir}: not a configured CMake build folder (no CMakeCache.txt)")

    signal.signal(signal.SIGTERM, raise_interrupt)
    rows = []
    begin = time.monotonic()
    try:
        for number, mutation in enumerate(mutations, 1):
            row = run_one(mutation, build_dir, args.jobs, catch_spec)
            rows.append(row)
            print(f"[{number}/{len(mutations)}] {row['id']}: {row['result']} ({row['seconds']} s) {row['killing_tests']}",
                  flush=True)
    finally:
        # Leave the build matching the restored sources (ccache makes this quick).
        build(build_dir, args.jobs)
        if rows:
            report = Path(args.report)
            write_report(merge_with_existing(rows, report, all_mutations) if args.only else rows, report)
    survived = [row["id"] for row in rows if row["result"] != "killed"]
    print(f"{len(rows)} mutations in {time.monotonic() - begin:.0f} s: {len(rows) - len(survived)} killed, "
          f"{len(survived)} survived {' '.join(survived)}")
    return 1 if survived else 0


if __name__ == "__main__":
    sys.exit(main())
