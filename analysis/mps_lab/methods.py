"""The registered methods, as the binary lists them, and how each is drawn.

No method is named here: `registered_methods` asks `mps_lab methods` (app/commands.cpp,
`methods_command`: one line per method, its name padded, two spaces, its description), and
`method_catalogue` asks `mps_lab methods --parameters` (indented below each method: its
parameters, "methods.<name>.<key> = ...", and its wall treatments,
"wall treatment <name> (boundary model|measure, on|off by default[, acts ...]): ..."). A method added
to the C++ registry appears in every study and figure without an edit here.

Colours and markers come from the position of a method in the sorted list, so one method
has one colour in every figure of one build.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Iterable

from . import runner

LISTING_TIMEOUT = 60.0  # s; `mps_lab methods` prints a table and exits
MARKERS = ["o", "s", "^", "D", "v", "P", "X", "*", "h", "<", ">", "p"]
WALL_TREATMENT_LINE = re.compile(r"^\s+wall treatment (\S+) \((boundary model|measure), (on|off) by default[,)]")
# The load setting's line (app/commands.cpp): "load setting (--load-setting): --set ...; promise: still
# water within 2 % of rho g h (...)".
PROMISE_LINE = re.compile(r"^\s+load setting \(--load-setting\):.*; promise: still water within ([0-9.]+) % of rho g h")
# A declared parameter's line (app/commands.cpp): "methods.<method>.<key> = <default> [unit]  (...)".
PARAMETER_LINE = re.compile(r"^\s+methods\.[A-Za-z0-9_]+\.([A-Za-z0-9_]+) = (\S+)")


class MethodListError(Exception):
    """`mps_lab methods` failed or listed nothing; the message is one line."""


def list_methods_output(binary: str, *arguments: str) -> str:
    result = runner.run_case(binary, ["methods", *arguments], timeout=LISTING_TIMEOUT, keep=None, retry_delay=0.5)
    if not result.ok:
        detail = result.last_error_line()
        raise MethodListError(f"{binary} methods {' '.join(arguments)}: {result.describe()}"
                              + (f": {detail}" if detail else ""))
    return result.stdout


def parse_method_names(listing: str) -> list[str]:
    """The first word of every line that is not indented (the others are a method's details)."""
    return [line.split()[0] for line in listing.splitlines() if line.strip() and not line[0].isspace()]


def registered_methods(binary: str) -> list[str]:
    """The names of the methods the binary registers, sorted."""
    names = parse_method_names(list_methods_output(binary))
    if not names:
        raise MethodListError(f"{binary} methods: listed no method")
    return sorted(names)


@dataclass
class MethodInfo:
    name: str
    description: str
    boundary_models: list[str] = field(default_factory=list)  # the boundary models it supports, listed order
    default_boundary_model: str = ""  # the one on by default ("" when none is)
    measures: list[str] = field(default_factory=list)  # the wall measures it supports
    still_water_promise: float | None = None  # its load setting's still-water tolerance (0.02: 2 %), if declared
    parameter_defaults: dict[str, str] = field(default_factory=dict)  # key -> its listed default, as text


def parse_catalogue(listing: str) -> dict[str, MethodInfo]:
    """`mps_lab methods --parameters` as MethodInfo by name."""
    catalogue: dict[str, MethodInfo] = {}
    current = None
    for line in listing.splitlines():
        if not line.strip():
            continue
        if not line[0].isspace():
            name, _, description = line.strip().partition(" ")
            current = catalogue.setdefault(name, MethodInfo(name, description.strip()))
            continue
        promise = PROMISE_LINE.match(line)
        if current is not None and promise is not None:
            current.still_water_promise = float(promise.group(1)) / 100.0
            continue
        parameter = PARAMETER_LINE.match(line)
        if current is not None and parameter is not None:
            current.parameter_defaults[parameter.group(1)] = parameter.group(2)
            continue
        treatment = WALL_TREATMENT_LINE.match(line)
        if current is None or treatment is None:
            continue
        wall, role, default = treatment.groups()
        if role == "measure":
            current.measures.append(wall)
            continue
        current.boundary_models.append(wall)
        if default == "on":
            current.default_boundary_model = wall
    return catalogue


def method_catalogue(binary: str) -> dict[str, MethodInfo]:
    """Every registered method with the boundary models and measures it supports."""
    catalogue = parse_catalogue(list_methods_output(binary, "--parameters"))
    if not catalogue:
        raise MethodListError(f"{binary} methods --parameters: listed no method")
    return catalogue


@dataclass(frozen=True)
class MethodStyles:
    """Colour and marker of each method: by its place in `methods` (sorted registered names,
    then any other method met in the runs, sorted)."""
    methods: tuple[str, ...]

    def index(self, method: str) -> int:
        return self.methods.index(method) if method in self.methods else len(self.methods)

    def colour(self, method: str) -> str:
        return f"C{self.index(method) % 10}"

    def marker(self, method: str) -> str:
        return MARKERS[self.index(method) % len(MARKERS)]


def method_styles(registered: Iterable[str], seen: Iterable[str] = ()) -> MethodStyles:
    names = sorted(set(registered))
    return MethodStyles(tuple(names + sorted(set(seen) - set(names))))


def styles_for(seen: Iterable[str], binary: str | None = None) -> MethodStyles:
    """The styles of the registered methods of the binary (runner.find_binary's order), the
    methods `seen` in the runs added; without a binary (figures of runs copied elsewhere), of
    the methods seen alone."""
    seen = list(seen)
    try:
        return method_styles(registered_methods(runner.find_binary(binary)), seen)
    except (runner.BinaryNotFound, MethodListError):
        return method_styles(seen)
