"""The floating box's heave by linear potential flow (analysis/heave_linear_theory.py; docs/bodies.md,
"Linear theory"): the reference the particle runs of scenes/floating_box_heave.json are compared
with, at the water depth, tank width and release offset each run has.

Two references, both from analysis/mps_lab/radiation.py:
  open water  the undamped natural period with the added mass at its own frequency in water of the
              run's depth (no tank walls): T_n, a33(w_n), zeta = b33 / (2 (m + a33) w_n);
  tank        the linear free decay in the run's tank (its walls reflect the radiated waves),
              released from rest at the run's offset, fitted over the first second exactly as the
              particle runs are (floating.fit_damped_heave): the damped period and zeta.
"""
from __future__ import annotations

import csv


from .. import radiation
from . import floating
from .common import formatted

COLUMNS = ["l0", "depth", "tank_width", "release_offset", "added_mass_infinite", "open_water_period",
           "open_water_added_mass", "open_water_zeta", "frequency_number", "tank_added_mass_infinite", "tank_period",
           "tank_zeta"]
COMPARISON_COLUMNS = ["method", "l0", "period", "tank_period", "period_ratio", "damping_ratio", "tank_zeta"]
PANELS_PER_METRE = 200  # the box's natural period changes by < 0.1 % from 100 to 400 (tests/python)
TIME_STEP = 0.002  # s, as the runs' series (every 4 steps of 5e-4 s); 1e-3 s changes T by < 0.02 %


def reference(geometry: dict, l0: float, rest_level: float, release_offset: float) -> dict:
    """Both references for a run at spacing l0 whose water rests at `rest_level` (m; the bed's
    surface is l0/2 above the domain's floor, the walls' surfaces l0/2 inside the domain)."""
    depth = rest_level - l0 / 2
    tank_width = geometry["tank_width"] - l0
    draft = geometry["rho_b"] / geometry["rho_w"] * geometry["height"]
    mass = geometry["rho_b"] * geometry["width"] * geometry["height"]
    beam = geometry["width"]
    open_water = radiation.natural_heave(beam, draft, depth, mass, geometry["rho_w"], per_metre=PANELS_PER_METRE)
    panels = radiation.box_section_panels(beam, draft, depth, beam / 2 + 4 * depth, PANELS_PER_METRE)
    a_inf, _, _ = radiation.solve_radiation(panels, 10.0, depth, geometry["rho_w"], infinite_frequency=True)
    tank = radiation.TankDecay(beam, draft, depth, tank_width, mass, geometry["rho_w"], PANELS_PER_METRE)
    t, x = tank.run(release_offset, floating.HEAVE_FIT_END, TIME_STEP)
    fit = floating.fit_damped_heave(t, x)
    return {"l0": l0, "depth": depth, "tank_width": tank_width, "release_offset": release_offset,
            "added_mass_infinite": a_inf, "open_water_period": open_water.period,
            "open_water_added_mass": open_water.added_mass, "open_water_zeta": open_water.zeta,
            "frequency_number": open_water.omega ** 2 * beam / (2 * geometry["g"]),
            "tank_added_mass_infinite": tank.added_mass_infinite, "tank_period": fit["period"],
            "tank_zeta": fit["damping_ratio"]}


def read_heave_rows(path: str) -> list[dict]:
    """The completed rows of a floating study's floating_box_heave.csv."""
    with open(path, newline="") as handle:
        return [row for row in csv.DictReader(handle) if row["status"] == "completed" and row["period"]]


def compare(geometry: dict, heave_rows: list[dict]) -> tuple[list[dict], list[dict]]:
    """The references at every spacing of the study (from its first row there) and each run's
    period and damping against the tank's."""
    references = {}
    for row in heave_rows:
        l0 = float(row["l0"])
        if l0 not in references:
            references[l0] = reference(geometry, l0, float(row["rest_level"]), float(row["release_offset"]))
    comparison = []
    for row in heave_rows:
        ref = references[float(row["l0"])]
        period = float(row["period"])
        comparison.append({"method": row["method"], "l0": float(row["l0"]), "period": period,
                           "tank_period": ref["tank_period"], "period_ratio": period / ref["tank_period"],
                           "damping_ratio": float(row["damping_ratio"]), "tank_zeta": ref["tank_zeta"]})
    return [references[l0] for l0 in sorted(references, reverse=True)], comparison


def markdown(references: list[dict], comparison: list[dict]) -> str:
    lines = ["| l0, m | depth, m | open water: T_n, s | a33(w_n), kg/m | zeta | a33(inf), kg/m | "
             "tank: T (first second), s | zeta |", "|---|---|---|---|---|---|---|---|"]
    for r in references:
        lines.append(f"| {r['l0']:g} | {r['depth']:.4f} | {r['open_water_period']:.4f} | "
                     f"{r['open_water_added_mass']:.2f} | {r['open_water_zeta']:.3f} | {r['added_mass_infinite']:.2f} | "
                     f"{r['tank_period']:.4f} | {r['tank_zeta']:.3f} |")
    lines += ["", "| method | l0, m | period, s | tank theory, s | ratio | zeta | tank theory zeta |",
              "|---|---|---|---|---|---|---|"]
    for c in comparison:
        lines.append(f"| {c['method']} | {c['l0']:g} | {formatted(c['period'], 3)} | {formatted(c['tank_period'], 3)} | "
                     f"{formatted(c['period_ratio'], 3)} | {formatted(c['damping_ratio'], 3)} | "
                     f"{formatted(c['tank_zeta'], 3)} |")
    return "\n".join(lines) + "\n"


def decay_curves(geometry: dict, references: list[dict]) -> dict:
    """The tank's linear decay x(t) (m) at each spacing, for the figure."""
    curves = {}
    draft = geometry["rho_b"] / geometry["rho_w"] * geometry["height"]
    mass = geometry["rho_b"] * geometry["width"] * geometry["height"]
    for r in references:
        tank = radiation.TankDecay(geometry["width"], draft, r["depth"], r["tank_width"], mass, geometry["rho_w"],
                                   PANELS_PER_METRE)
        curves[r["l0"]] = tank.run(r["release_offset"], 2.0, TIME_STEP)
    return curves

