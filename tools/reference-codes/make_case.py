#!/usr/bin/python3
"""Input files of the reference codes for the spec dam break (scenes/dambreak_fine.json).

Tank 1.0 x 0.6 m (open top), water column 0.25 x 0.5 m at the left wall, particle spacing l0 (default
0.005 m). Written from this project's geometry only; nothing of the reference codes is copied:

  make_case.py mps-basic SETTINGS_TEMPLATE OUT_DIR --end-time T --threads N [--radii own|spec]
      OUT_DIR/input.csv (MPS-Basic's CSV particle format) and OUT_DIR/settings.yml: MPS-Basic's own
      dam-break settings (SETTINGS_TEMPLATE, its input/dambreak/settings.yml) with the keys listed in
      MPS_BASIC_OVERRIDES replaced.
  make_case.py splishsplash BOX_OBJ OUT_DIR --end-time T --tolerance PERCENT
      OUT_DIR/scene.json: DFSPH in 2-D, the tank as SPlisHSPlasH's unit box (BOX_OBJ) scaled, a fluid block.

Both print the number of fluid particles.
"""
import argparse
import json
import math
import pathlib
import re
import sys

TANK_WIDTH = 1.0  # m, inner width between the wall surfaces
TANK_HEIGHT = 0.6  # m, height of the side walls (open top)
COLUMN_WIDTH = 0.25  # m
COLUMN_HEIGHT = 0.5  # m
GRAVITY = 9.81  # m/s^2, as scenes/dambreak.json
DENSITY = 1000.0  # kg/m^3
KINEMATIC_VISCOSITY = 1.0e-6  # m^2/s

# MPS-Basic particle types (its CSV "type" column).
MPSB_FLUID, MPSB_WALL, MPSB_DUMMY_WALL = 1, 2, 3


def mps_basic_particles(l0):
    """Fluid on this project's lattice (scenes/dambreak_fine.json: the first row l0 from each wall surface,
    4851 particles at l0 = 0.005) and four wall layers outside the surfaces x = 0, x = 1, y = 0: the surface
    and the next layer are MPS-Basic "Wall" (pressure solved), the two outer "DummyWall" (number density
    only). Four layers cover MPS-Basic's own number-density radius, 3.1 l0."""
    particles = []
    nx_fluid = int(round(COLUMN_WIDTH / l0)) - 1
    ny_fluid = int(round(COLUMN_HEIGHT / l0)) - 1
    for i in range(1, nx_fluid + 1):
        for j in range(1, ny_fluid + 1):
            particles.append((MPSB_FLUID, i * l0, j * l0))
    n_fluid = len(particles)
    n_tank = int(round(TANK_WIDTH / l0))
    top = int(round(TANK_HEIGHT / l0)) - 1  # last wall row below the rim, as our lattice (0.595 at 0.005)
    for layer in range(4):
        kind = MPSB_WALL if layer < 2 else MPSB_DUMMY_WALL
        for i in range(-layer, n_tank + layer + 1):  # bottom row of this layer, corners included
            particles.append((kind, i * l0, -layer * l0))
        for j in range(-layer + 1, top + 1):  # side columns above it
            particles.append((kind, -layer * l0, j * l0))
            particles.append((kind, (n_tank + layer) * l0, j * l0))
    return particles, n_fluid


def write_mps_basic_csv(path, particles):
    """MPS-Basic's CSV input: start time, particle count, header, one row per particle (2-D: z = 0)."""
    with open(path, "w") as out:
        out.write("0\n%d\ntype,x,y,z,vx,vy,vz\n" % len(particles))
        for kind, x, y in particles:
            out.write("%d,%.10g,%.10g,0,0,0,0\n" % (kind, x, y))


def mps_basic_overrides(args):
    """The settings this case changes in MPS-Basic's dam-break settings.yml, and why (README.md). Its density
    (1000 kg/m^3) and kinematic viscosity (1e-6 m^2/s) are already ours."""
    values = {
        "particleDistance": repr(args.spacing),
        "dt": repr(args.time_step),  # ours: scenes/dambreak_fine.json time.time_step
        "endTime": repr(args.end_time),
        "outputPeriod": repr(args.output_period),  # ours: output.frame_interval 0.05 s
        "numPhysicalCores": str(args.threads),  # read but unused by MPS-Basic: OMP_NUM_THREADS sets the threads
        "gravity": "[0.0, %r, 0.0]" % -GRAVITY,
        "domainMin": "[-0.1, -0.1, 0.0]",
        "domainMax": "[1.1, 2.0, 0.0]",
        "particlesPath": "./input.csv",
    }
    if args.radii == "spec":  # the spec's radii (scenes/dambreak.json: 2.1 l0 for all three operators)
        values.update({"radiusRatioForNumberDensity": "2.1", "radiusRatioForGradient": "2.1",
                       "radiusRatioForLaplacian": "2.1"})
    return values


def write_mps_basic_settings(template, path, values):
    text = pathlib.Path(template).read_text()
    for key, value in values.items():
        pattern = re.compile(r"^%s:.*$" % re.escape(key), re.MULTILINE)
        if not pattern.search(text):
            sys.exit("make_case.py: %s: no '%s:' line to set" % (template, key))
        text = pattern.sub(lambda _: "%s: %s" % (key, value), text, count=1)
    pathlib.Path(path).write_text(text)


def splishsplash_scene(args):
    """DFSPH (simulationMethod 4) in 2-D with volume-map walls (boundaryHandlingMethod 2), as
    DamBreakModel_2D.json; the tank is the unit box scaled to 1.0 x 1.2 m (taller than our open 0.6 m rim,
    so the closed lid is never reached), bottom-left inner corner at the origin. particleRadius = l0/2."""
    l0 = args.spacing
    radius = 0.5 * l0
    # SPlisHSPlasH fills a block [min, max] (denseMode 0) at min + d (j + 1), j < round((max - min) / d) - 1,
    # d = 2 r = l0: the column [0, 0.25] x [0, 0.5] gives our lattice, x = l0 ... 0.245, y = l0 ... 0.495
    # (49 x 99 = 4851 at l0 = 0.005), the first row l0 from the wall surfaces x = 0 and y = 0.
    n_x = int(round(COLUMN_WIDTH / l0)) - 1
    n_y = int(round(COLUMN_HEIGHT / l0)) - 1
    box_height = 2.0 * TANK_HEIGHT
    cells = int(math.ceil(TANK_WIDTH / (8.0 * l0)))  # volume map: one cell per 8 l0
    dfsph = {"minIterations": 2, "maxIterations": 100, "maxError": args.tolerance, "maxIterationsV": 100,
             "maxErrorV": 0.1, "enableDivergenceSolver": True}
    # The solver's and the viscosity's keys are written twice: flat (SPlisHSPlasH up to 80b7284) and in their
    # namespaces "DFSPH" and "Standard viscosity" (from c5a063d on); each version reads its own, ignores the other.
    return {
        "Configuration": {
            "pause": False,
            "sim2D": True,
            "particleRadius": radius,
            "simulationMethod": 4,
            "gravitation": [0.0, -GRAVITY, 0.0],
            "cflMethod": 1,
            # The same Courant number as ours (methods.dfsph cfl 0.4: dt = 0.4 l0 / v_max): SPlisHSPlasH's
            # rule is dt = cflFactor 0.4 (2 r) / v_max (Simulation.cpp, its CFL step), so cflFactor 1.0.
            # (0.4 there, as at first, is a Courant number of 0.16: 3.1 times our steps, measured.)
            "cflFactor": 1.0,
            "cflMaxTimeStepSize": 0.005,
            "boundaryHandlingMethod": 2,
            "stopAt": args.end_time,
            "enablePartioExport": False,
            "enableVTKExport": False,
            "DFSPH": dfsph,
            **dfsph,
        },
        "Materials": [{
            "id": "Fluid",
            "density0": DENSITY,
            "viscosityMethod": 1,
            "vorticityMethod": 0,
            "viscosity": KINEMATIC_VISCOSITY,
            "Standard viscosity": {"viscosity": KINEMATIC_VISCOSITY},
        }],
        "RigidBodies": [{
            "geometryFile": str(pathlib.Path(args.model).resolve()),
            "translation": [0.5 * TANK_WIDTH, 0.5 * box_height, 0.0],
            "rotationAxis": [1, 0, 0],
            "rotationAngle": 0,
            "scale": [TANK_WIDTH, box_height, 1.0],
            "isDynamic": False,
            "isWall": True,
            "mapInvert": True,
            "mapThickness": 0.0,
            "mapResolution": [cells, int(math.ceil(box_height / (8.0 * l0))), 4],
        }],
        "FluidBlocks": [{
            "denseMode": 0,
            "start": [0.0, 0.0, -1.0],
            "end": [COLUMN_WIDTH, COLUMN_HEIGHT, 1.0],
            "translation": [0.0, 0.0, 0.0],
            "scale": [1, 1, 1],
        }],
    }, n_x * n_y


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("code", choices=["mps-basic", "splishsplash"])
    parser.add_argument("source_file", help="mps-basic: its settings.yml; splishsplash: its UnitBox.obj")
    parser.add_argument("out_dir")
    parser.add_argument("--spacing", type=float, default=0.005, help="l0 [m]")
    parser.add_argument("--end-time", type=float, required=True, help="simulated end time [s]")
    parser.add_argument("--time-step", type=float, default=1.0e-4, help="mps-basic: fixed dt [s]")
    parser.add_argument("--output-period", type=float, default=0.05, help="mps-basic: frame interval [s]")
    parser.add_argument("--threads", type=int, default=1)
    parser.add_argument("--radii", choices=["own", "spec"], default="own",
                        help="mps-basic: its own radii (3.1/2.1/3.1 l0) or the spec's (2.1 l0)")
    parser.add_argument("--tolerance", type=float, default=0.1, help="splishsplash: DFSPH maxError [%%]")
    args = parser.parse_args()
    out = pathlib.Path(args.out_dir)
    out.mkdir(parents=True, exist_ok=True)
    if args.code == "mps-basic":
        particles, n_fluid = mps_basic_particles(args.spacing)
        write_mps_basic_csv(out / "input.csv", particles)
        write_mps_basic_settings(args.source_file, out / "settings.yml", mps_basic_overrides(args))
    else:
        args.model = args.source_file
        scene, n_fluid = splishsplash_scene(args)
        (out / "scene.json").write_text(json.dumps(scene, indent=2) + "\n")
    print(n_fluid)


if __name__ == "__main__":
    main()
