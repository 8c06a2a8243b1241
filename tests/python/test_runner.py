"""The case runner (analysis/mps_lab/runner.py) and the method list (analysis/mps_lab/methods.py)
against a fake mps_lab, a shell script whose first argument picks what it does: sleep past the
timeout, ignore SIGTERM, exit with a code, crash once (SIGSEGV) then succeed, crash always,
print its environment or its arguments, chatter, list methods. Every invocation appends a line
to a `calls` file beside it, so the tests count the attempts. The real binary's listing is
parsed too. Run by CTest (label analysis); MPS_LAB_BINARY names build/mps_lab."""
from __future__ import annotations

import ast
import glob
import os
import re
import shutil
import stat
import subprocess
import sys
import tempfile
import unittest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
sys.path.insert(0, os.path.join(ROOT, "analysis"))
from mps_lab import methods, runner  # noqa: E402

BINARY = os.environ.get("MPS_LAB_BINARY", os.path.join(ROOT, "build", "mps_lab"))

FAKE = r"""#!/bin/sh
echo "$1" >> "$(dirname "$0")/calls"
case "$1" in
  sleep) exec sleep "$2" ;;
  stubborn) trap '' TERM; exec sleep "$2" ;;
  exit) echo "mps_lab: error: exit $2 on purpose" >&2; exit "$2" ;;
  crash-once) if [ -e "$2" ]; then echo recovered; exit 0; fi; : > "$2"; kill -s SEGV $$ ;;
  crash) kill -s SEGV $$ ;;
  env) echo "${OMP_NUM_THREADS:-unset} ${OMP_PROC_BIND:-unset}" ;;
  args) shift; for a in "$@"; do echo "[$a]"; done ;;
  chatter) i=0; while [ $i -lt 3000 ]; do echo "line $i"; i=$((i+1)); done; echo "the last error" >&2 ;;
  methods) printf 'zeta   the last one\n    methods.zeta.x = 1 m  (> 0) a parameter\n'
           printf '    wall treatment wall_b (boundary model, on by default): b\n'
           printf '    wall treatment wall_a (boundary model, off by default): a\n'
           printf '    wall treatment clamp (measure, on by default): c\n'
           printf 'alpha  the first one\n    wall treatment wall_a (boundary model, on by default): a\n'
           printf 'beta   in between\n' ;;
esac
"""


class FakeBinaryTest(unittest.TestCase):
    def setUp(self):
        self.folder = tempfile.mkdtemp(prefix="mps_lab_runner_")
        self.fake = os.path.join(self.folder, "mps_lab")
        with open(self.fake, "w") as handle:
            handle.write(FAKE)
        os.chmod(self.fake, os.stat(self.fake).st_mode | stat.S_IEXEC)

    def tearDown(self):
        shutil.rmtree(self.folder, ignore_errors=True)

    def calls(self) -> int:
        try:
            with open(os.path.join(self.folder, "calls")) as handle:
                return len(handle.read().splitlines())
        except OSError:
            return 0

    def run_fake(self, *arguments, **options):
        options = {"timeout": 30.0, "retry_delay": 0.0, **options}
        return runner.run_case(self.fake, list(arguments), **options)

    def test_success_is_one_attempt(self):
        result = self.run_fake("exit", "0", folder="/some/run")
        self.assertTrue(result.ok)
        self.assertEqual((result.exit_code, result.attempts, self.calls()), (0, 1, 1))
        self.assertEqual(result.folder, "/some/run")
        self.assertEqual(result.command, [self.fake, "exit", "0"])
        self.assertGreaterEqual(result.seconds, 0.0)

    def test_run_failure_and_bad_input_are_not_retried(self):
        for code in (1, 2, 3, 130, 143):  # diverged, bad input, output error, stopped on request
            result = self.run_fake("exit", str(code))
            self.assertEqual((result.exit_code, result.attempts), (code, 1), code)
            self.assertFalse(result.ok)
            self.assertEqual(result.last_error_line(), f"mps_lab: error: exit {code} on purpose")
        self.assertEqual(self.calls(), 5)

    def test_a_crash_is_retried_once(self):
        marker = os.path.join(self.folder, "crashed")
        result = self.run_fake("crash-once", marker)
        self.assertTrue(result.ok, result.describe())
        self.assertEqual((result.attempts, self.calls()), (2, 2))
        self.assertEqual(result.stdout, "recovered\n")
        self.assertIn("2 attempts", result.describe())

    def test_a_crash_every_time_is_reported_after_two_attempts(self):
        result = self.run_fake("crash")
        self.assertEqual((result.exit_code, result.attempts, self.calls()), (-11, 2, 2))
        self.assertTrue(result.killed_by_signal)
        self.assertIn("killed by SIGSEGV", result.describe())

    def test_timeout_stops_the_case_with_sigterm_and_is_not_retried(self):
        # sleep 30 s against a 1 s timeout: SIGTERM ends it at once (exit -15); well under
        # the 30 s it would take, with 10 s of margin for a loaded machine.
        result = self.run_fake("sleep", "30", timeout=1.0, grace=5.0)
        self.assertTrue(result.timed_out)
        self.assertEqual((result.exit_code, result.attempts, self.calls()), (-15, 1, 1))
        self.assertGreaterEqual(result.seconds, 1.0)
        self.assertLess(result.seconds, 11.0)
        self.assertIn("timeout", result.describe())

    def test_timeout_kills_a_case_that_ignores_sigterm(self):
        # SIGTERM ignored: SIGKILL after the 1 s grace (exit -9), at about 2 s of 30.
        result = self.run_fake("stubborn", "30", timeout=1.0, grace=1.0)
        self.assertTrue(result.timed_out)
        self.assertEqual((result.exit_code, result.attempts), (-9, 1))
        self.assertGreaterEqual(result.seconds, 2.0)
        self.assertLess(result.seconds, 12.0)

    def test_a_binary_that_cannot_start_is_retried_then_reported(self):
        os.chmod(self.fake, 0o644)
        result = runner.run_case(self.fake, ["exit", "0"], timeout=5.0, retry_delay=0.0)
        self.assertIsNone(result.exit_code)
        self.assertEqual(result.attempts, 2)
        self.assertIn("not started", result.describe())

    def test_environment_threads_and_binding(self):
        self.assertEqual(self.run_fake("env", threads=3, proc_bind="true").stdout, "3 true\n")
        inherited = runner.case_environment(base={"OMP_NUM_THREADS": "7"})
        self.assertEqual(inherited["OMP_NUM_THREADS"], "7")
        self.assertNotIn("OMP_PROC_BIND", inherited)

    def test_arguments_reach_the_binary_verbatim_without_a_shell(self):
        tricky = ["a b", "$HOME", "x;echo injected", "'quoted'", "methods.mps.wall_treatments.x={}"]
        result = self.run_fake("args", *tricky)
        self.assertEqual(result.stdout.splitlines(), [f"[{a}]" for a in tricky])
        line = runner.command_line(self.fake, ["args", *tricky], threads=2)
        self.assertTrue(line.startswith("OMP_NUM_THREADS=2 "))
        echoed = subprocess.run(["sh", "-c", line], capture_output=True, text=True).stdout
        self.assertEqual(echoed.splitlines(), [f"[{a}]" for a in tricky])  # the job line quotes them right

    def test_output_tails(self):
        result = self.run_fake("chatter")
        self.assertEqual(len(result.stdout), runner.TAIL_CHARACTERS)
        self.assertTrue(result.stdout.endswith("line 2999\n"))
        self.assertEqual(result.last_error_line(), "the last error")
        whole = self.run_fake("chatter", keep=None)
        self.assertTrue(whole.stdout.startswith("line 0\n"))

    def test_run_cases_returns_every_request(self):
        requests = [runner.CaseRequest(f"case{k}", ["exit", str(k)], f"/runs/{k}", {"k": k}) for k in range(3)]
        results = {request.name: (request, result) for request, result in
                   runner.run_cases(self.fake, requests, parallel=2, timeout=30.0, retry_delay=0.0)}
        self.assertEqual(sorted(results), ["case0", "case1", "case2"])
        for name, (request, result) in results.items():
            self.assertEqual(result.exit_code, request.extra["k"], name)
            self.assertEqual(result.folder, request.folder)

    def test_find_binary_order(self):
        other = os.path.join(self.folder, "other")
        shutil.copy(self.fake, other)
        missing = os.path.join(self.folder, "missing")
        empty = {"PATH": ""}
        self.assertEqual(runner.find_binary(self.fake, {runner.ENVIRONMENT_VARIABLE: other}), self.fake)
        self.assertEqual(runner.find_binary(None, {runner.ENVIRONMENT_VARIABLE: other}), other)
        self.assertEqual(runner.find_binary(None, empty, build_binary=other), other)
        self.assertEqual(runner.find_binary(None, {"PATH": self.folder}, build_binary=missing), self.fake)
        with self.assertRaises(runner.BinaryNotFound):
            runner.find_binary(missing)  # an explicit path that is not there: no fallback
        with self.assertRaises(runner.BinaryNotFound):
            runner.find_binary(None, {runner.ENVIRONMENT_VARIABLE: missing}, build_binary=other)
        with self.assertRaisesRegex(runner.BinaryNotFound, "none on PATH"):
            runner.find_binary(None, empty, build_binary=missing)

    def test_methods_from_the_listing(self):
        self.assertEqual(methods.registered_methods(self.fake), ["alpha", "beta", "zeta"])
        catalogue = methods.method_catalogue(self.fake)
        self.assertEqual(list(catalogue), ["zeta", "alpha", "beta"])
        zeta = catalogue["zeta"]
        self.assertEqual((zeta.description, zeta.default_boundary_model), ("the last one", "wall_b"))
        self.assertEqual((zeta.boundary_models, zeta.measures), (["wall_b", "wall_a"], ["clamp"]))
        self.assertEqual(catalogue["alpha"].default_boundary_model, "wall_a")
        self.assertEqual((catalogue["beta"].boundary_models, catalogue["beta"].default_boundary_model), ([], ""))

    def test_method_list_failure_is_one_line(self):
        os.chmod(self.fake, 0o644)
        with self.assertRaises(methods.MethodListError) as raised:
            methods.registered_methods(self.fake)
        self.assertEqual(len(str(raised.exception).splitlines()), 1)


class MethodStylesTest(unittest.TestCase):
    def test_colours_follow_the_sorted_list(self):
        styles = methods.method_styles(["zeta", "alpha", "beta"], seen=["old", "alpha"])
        self.assertEqual(styles.methods, ("alpha", "beta", "zeta", "old"))  # registered sorted, then the others
        self.assertEqual([styles.colour(m) for m in ("alpha", "beta", "zeta", "old")], ["C0", "C1", "C2", "C3"])
        self.assertEqual(styles.marker("beta"), methods.MARKERS[1])
        self.assertEqual(methods.method_styles(["beta", "alpha"]).colour("beta"),
                         methods.method_styles(["alpha", "beta"]).colour("beta"))

    def test_real_binary(self):
        """registered_methods parses what `mps_lab methods` prints: its first words, sorted;
        the catalogue gives every method exactly one default boundary model."""
        listing = subprocess.run([BINARY, "methods"], capture_output=True, text=True, check=True).stdout
        first_words = sorted(line.split()[0] for line in listing.splitlines() if line.strip())
        self.assertEqual(methods.registered_methods(BINARY), first_words)
        catalogue = methods.method_catalogue(BINARY)
        self.assertEqual(sorted(catalogue), first_words)
        for name, info in catalogue.items():
            self.assertIn(info.default_boundary_model, info.boundary_models, name)
            self.assertEqual(info.boundary_models.count(info.default_boundary_model), 1, name)
        # Every boundary model the binary lists under a method is in its catalogue entry (the
        # listing's "(boundary model, off by default, acts ...)" form included).
        detailed = subprocess.run([BINARY, "methods", "--parameters"], capture_output=True, text=True,
                                  check=True).stdout
        listed = {}
        current = None
        for line in detailed.splitlines():
            if line and not line[0].isspace():
                current = line.split()[0]
            elif line.strip().startswith("wall treatment ") and "(boundary model" in line and current:
                listed.setdefault(current, []).append(line.split()[2])
        for name, info in catalogue.items():
            self.assertEqual(sorted(info.boundary_models), sorted(listed[name]), name)



class NoMethodNamesInAnalysisTest(unittest.TestCase):
    def test_no_string_literal_names_a_registered_method(self):
        """No string in the code of analysis/ (docstrings, the help texts, are allowed to give
        examples) names a registered method, in any case or inside a key such as
        "methods.<name>.x": the methods come from `mps_lab methods`, so a new one is never
        left out of a study or a figure. Data files (analysis/sweeps/*.json) may name them."""
        registered = methods.registered_methods(BINARY)
        found = []
        for path in sorted(glob.glob(os.path.join(ROOT, "analysis", "**", "*.py"), recursive=True)):
            with open(path) as handle:
                tree = ast.parse(handle.read())
            docstrings = {id(node.body[0].value) for node in ast.walk(tree)
                          if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef)) and node.body
                          and isinstance(node.body[0], ast.Expr) and isinstance(node.body[0].value, ast.Constant)}
            for node in ast.walk(tree):
                if not (isinstance(node, ast.Constant) and isinstance(node.value, str)) or id(node) in docstrings:
                    continue
                for name in registered:
                    if re.search(rf"(?<!\w){re.escape(name)}(?!\w)", node.value, re.IGNORECASE):
                        found.append(f"{os.path.relpath(path, ROOT)}:{node.lineno}: {node.value[:60]!r}")
        self.assertEqual(found, [])


if __name__ == "__main__":
    unittest.main()
