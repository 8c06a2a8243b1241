"""The one case runner of the analysis: every study runs `mps_lab` through `run_case`.

Finding the binary (`find_binary`), in this order:
  1. the --binary option of the study (an explicit path must exist: no silent fallback);
  2. the MPS_LAB_BINARY environment variable (CTest sets it to the binary it built);
  3. build/mps_lab of this source tree;
  4. the installed binary beside an installed copy of this package (`cmake --install`:
     P/share/mps_lab/analysis/mps_lab/ and P/bin/mps_lab);
  5. an `mps_lab` on PATH.

Running one case (`run_case`): the binary and a list of arguments, never a shell; a timeout;
an environment (OMP_NUM_THREADS, OMP_PROC_BIND on top of the caller's); the result is a
`CaseResult` (exit code, seconds, the tails of stdout and stderr, the run folder).

What is retried (once, after `retry_delay` seconds), and why:
  - a process killed by a signal (exit code < 0 in Python: SIGSEGV, SIGBUS, SIGABRT, or the
    kernel's out-of-memory killer): a crash that is not the run's own outcome and may not
    recur (memory pressure from the other cases of a study);
  - a binary that could not be started (OSError, e.g. "Text file busy" while the binary is
    being rebuilt, or a fork that failed for lack of memory).
What is never retried:
  - exit 0 (done) and 1 (the run failed, diverged or its solver failed: run.json says why);
    these are results;
  - exit 2 (bad input) and 3 (output error): the same input fails the same way;
  - 130 and 143 (mps_lab stopped itself on SIGINT/SIGTERM after writing a checkpoint): someone
    asked it to stop;
  - a timeout: a second try would cost the same time. A case over its timeout gets SIGTERM
    (mps_lab then finishes its step and writes checkpoint.bin and run.json "interrupted", so a
    study resumes it), and SIGKILL after `TERMINATE_GRACE` seconds more.
"""
from __future__ import annotations

import concurrent.futures
import dataclasses
import os
import shlex
import shutil
import signal
import subprocess
import time
from dataclasses import dataclass, field
from typing import Iterable, Iterator

from . import SOURCE_ROOT

ENVIRONMENT_VARIABLE = "MPS_LAB_BINARY"
TERMINATE_GRACE = 30.0  # s between SIGTERM and SIGKILL after a timeout
TAIL_CHARACTERS = 4000  # of stdout and stderr kept in a CaseResult
# Exit codes of mps_lab (README.md): what a run says about itself.
EXIT_DONE, EXIT_FAILED, EXIT_BAD_INPUT, EXIT_OUTPUT_ERROR = 0, 1, 2, 3


class BinaryNotFound(Exception):
    """No mps_lab binary; the message is one line naming where it looked."""


def default_build_binary() -> str:
    return os.path.join(SOURCE_ROOT, "build", "mps_lab")


def installed_binary() -> str | None:
    """P/bin/mps_lab when this package is installed as P/share/mps_lab/analysis/mps_lab/."""
    root = os.path.abspath(SOURCE_ROOT)
    if os.path.basename(root) != "mps_lab" or os.path.basename(os.path.dirname(root)) != "share":
        return None
    return os.path.join(os.path.dirname(os.path.dirname(root)), "bin", "mps_lab")


def is_executable(path: str) -> bool:
    return os.path.isfile(path) and os.access(path, os.X_OK)


def find_binary(explicit: str | None = None, environment: dict | None = None, build_binary: str | None = None) -> str:
    """The mps_lab binary to run, as an absolute path (order in the module's docstring).
    environment and build_binary stand in for os.environ and build/mps_lab (tests)."""
    environment = os.environ if environment is None else environment
    build_binary = default_build_binary() if build_binary is None else build_binary
    if explicit:
        if not is_executable(explicit):
            raise BinaryNotFound(f"{explicit}: --binary: not an executable mps_lab")
        return os.path.abspath(explicit)
    from_environment = environment.get(ENVIRONMENT_VARIABLE, "")
    if from_environment:
        if not is_executable(from_environment):
            raise BinaryNotFound(f"{from_environment}: {ENVIRONMENT_VARIABLE}: not an executable mps_lab")
        return os.path.abspath(from_environment)
    if is_executable(build_binary):
        return os.path.abspath(build_binary)
    beside = installed_binary()
    if beside and is_executable(beside):
        return beside
    on_path = shutil.which("mps_lab", path=environment.get("PATH", os.defpath))
    if on_path:
        return os.path.abspath(on_path)
    raise BinaryNotFound(f"no mps_lab binary: no --binary, no {ENVIRONMENT_VARIABLE}, no {build_binary} "
                         "(build it: tools/build.sh) and none on PATH")


def case_environment(threads: int | None = None, proc_bind: str | None = None, base: dict | None = None) -> dict:
    """The caller's environment with OMP_NUM_THREADS and OMP_PROC_BIND set when given."""
    environment = dict(os.environ if base is None else base)
    if threads is not None:
        environment["OMP_NUM_THREADS"] = str(int(threads))
    if proc_bind is not None:
        environment["OMP_PROC_BIND"] = proc_bind
    return environment


def command_line(binary: str, arguments: list[str], threads: int | None = None, proc_bind: str | None = None) -> str:
    """The case as one shell line (for a job list: GNU parallel, a Slurm array); never run here."""
    prefix = ""
    if threads is not None:
        prefix += f"OMP_NUM_THREADS={int(threads)} "
    if proc_bind is not None:
        prefix += f"OMP_PROC_BIND={shlex.quote(proc_bind)} "
    return prefix + shlex.join([binary, *arguments])


def tail(text: str, characters: int | None) -> str:
    return text if characters is None or len(text) <= characters else text[-characters:]


@dataclass(frozen=True)
class CaseResult:
    """What one case did. exit_code is None when the process never started; negative when a
    signal killed it (Python's convention)."""
    command: list[str]
    exit_code: int | None
    seconds: float  # wall time of the last attempt
    stdout: str  # its tail (TAIL_CHARACTERS unless asked otherwise)
    stderr: str
    folder: str | None = None  # the run folder of the case, when it has one
    attempts: int = 1
    timed_out: bool = False
    start_error: str = ""  # why the process could not be started

    @property
    def killed_by_signal(self) -> bool:
        return self.exit_code is not None and self.exit_code < 0 and not self.timed_out

    @property
    def ok(self) -> bool:
        return self.exit_code == EXIT_DONE and not self.timed_out

    def describe(self) -> str:
        """One phrase: "exit 0", "killed by SIGSEGV", "timeout after 60 s", "not started: ..."."""
        if self.start_error:
            text = f"not started: {self.start_error}"
        elif self.timed_out:
            text = f"timeout after {self.seconds:.0f} s (exit {self.exit_code})"
        elif self.killed_by_signal:
            text = f"killed by {signal_name(-self.exit_code)}"
        else:
            text = f"exit {self.exit_code}"
        return text + (f", {self.attempts} attempts" if self.attempts > 1 else "")

    def last_error_line(self) -> str:
        lines = [line.strip() for line in self.stderr.splitlines() if line.strip()]
        return lines[-1] if lines else ""


def signal_name(number: int) -> str:
    try:
        return signal.Signals(number).name
    except ValueError:
        return f"signal {number}"


def should_retry(result: CaseResult) -> bool:
    """A crash that is not the run's own outcome (see the module's docstring)."""
    return bool(result.start_error) or result.killed_by_signal


def stop(process: subprocess.Popen, grace: float) -> tuple[str, str]:
    """SIGTERM (mps_lab checkpoints and exits 143), then SIGKILL after `grace` seconds; the
    output read so far, or nothing when a child of the case still holds its pipes open."""
    process.send_signal(signal.SIGTERM)
    try:
        return process.communicate(timeout=grace)
    except subprocess.TimeoutExpired:
        process.kill()
    try:
        return process.communicate(timeout=grace)
    except subprocess.TimeoutExpired:
        process.wait()
        return "", ""


def run_once(command: list[str], environment: dict, timeout: float, grace: float, keep: int | None,
             folder: str | None) -> CaseResult:
    start = time.monotonic()
    try:
        process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                   errors="replace", env=environment)
    except OSError as error:
        return CaseResult(command, None, time.monotonic() - start, "", "", folder, start_error=str(error))
    timed_out = False
    try:
        stdout, stderr = process.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        timed_out = True
        stdout, stderr = stop(process, grace)
    return CaseResult(command, process.returncode, time.monotonic() - start, tail(stdout, keep), tail(stderr, keep),
                      folder, timed_out=timed_out)


def run_case(binary: str, arguments: list[str], *, timeout: float, threads: int | None = None,
             proc_bind: str | None = None, folder: str | None = None, retry_delay: float = 3.0,
             grace: float = TERMINATE_GRACE, keep: int | None = TAIL_CHARACTERS) -> CaseResult:
    """Run `binary arguments...` (no shell) at most twice: once more only after a crash that
    is not the run's own outcome (should_retry). `keep`: characters of stdout/stderr kept
    (None: all). `folder` is only recorded in the result."""
    command = [binary, *[str(argument) for argument in arguments]]
    environment = case_environment(threads, proc_bind)
    result = run_once(command, environment, timeout, grace, keep, folder)
    if should_retry(result):
        time.sleep(retry_delay)
        second = run_once(command, environment, timeout, grace, keep, folder)
        result = dataclasses.replace(second, attempts=2)
    return result


@dataclass(frozen=True)
class CaseRequest:
    """One case of a study: its name, the arguments after the binary, its run folder."""
    name: str
    arguments: list[str]
    folder: str | None = None
    extra: dict = field(default_factory=dict)  # what the study wants back with the result


def run_cases(binary: str, requests: Iterable[CaseRequest], *, parallel: int, timeout: float,
              threads: int | None = None, proc_bind: str | None = None,
              retry_delay: float = 3.0) -> Iterator[tuple[CaseRequest, CaseResult]]:
    """Run the requests `parallel` at a time, in the order given; yield each with its result
    as it finishes."""
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, parallel)) as pool:
        futures = {pool.submit(run_case, binary, request.arguments, timeout=timeout, threads=threads,
                               proc_bind=proc_bind, folder=request.folder, retry_delay=retry_delay): request
                   for request in requests}
        for future in concurrent.futures.as_completed(futures):
            yield futures[future], future.result()


def threads_per_case(parallel: int) -> int:
    """OpenMP threads of each of `parallel` concurrent cases: the cores shared out, at least 1."""
    return max(1, (os.cpu_count() or 1) // max(1, parallel))
