"""The studies: each runs a grid of `mps_lab` cases through runner.run_cases, resumes what
is unfinished, and collects a CSV, tables and figures.

    sweep          the speed-accuracy grid (method x l0 x time-step rule x tolerance)
    stability_map  where each method breaks (time step x l0)
    wall_study     every method with every boundary model it supports
    performance    speed against the reference codes, bench, scaling to 1e6
    cost           every method's cost per simulated second, side by side (tools/cost-five-methods.sh)
    pressure_noise front, height and pressure-sensor noise of finished dam-break runs
"""
