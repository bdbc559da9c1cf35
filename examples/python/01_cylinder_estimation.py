#!/usr/bin/env python3
"""Tutorial 1: estimate a cylinder's Young's modulus from tracked markers, driven from Python.

The cyl-E-same experiment of thesis §3.4.1 (examples/cyl-E-same): the truth (E = 8 kPa) is
simulated, then ROUKF estimates E from 10 noisy markers starting from 4 kPa. The scene is YAML
text changed from Python; a callback follows each step; the estimate is plotted with its 95 %
band. SI units throughout.

    PYTHONPATH=build/python python3 examples/python/01_cylinder_estimation.py --out out/py-cylinder
"""
import argparse
import os

import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

import bcassim  # noqa: E402


def cylinder(nodes, young_modulus, steps, extra=""):
    return (
        f"mesh: {{generator: cylinder, radius: 0.015, length: 0.18, target_nodes: {nodes}}}\n"
        f"material: {{model: stvk, young_modulus: {young_modulus}, poisson_ratio: 0.45}}\n"
        "damping: {rayleigh_mass: 0.1, rayleigh_stiffness: 0.01}\n"
        f"time: {{dt: 0.01, steps: {steps}}}\n"
        "output: {pvd: false}\n"
        "fixed:\n"
        "  - region: {half_space: {point: [0, 0, 0.0001], normal: [0, 0, -1]}}\n"
        "  - region: {half_space: {point: [0, 0, 0.1799], normal: [0, 0, 1]}}\n"
        "loads:\n"
        "  - region: {surface_patch: {box: {min: [-0.02, -0.02, 0.075], max: [0.02, 0.02, 0.105]},"
        " direction: [0, -1, 0], max_angle_deg: 60}}\n"
        "    total_force: [0, -0.15, 0]\n"
        "    profile: {kind: sine, period: 1.0}\n"
        "markers:\n"
        "  - region: {surface_patch: {box: {min: [-0.02, -0.02, 0.03], max: [0.02, 0.02, 0.15]},"
        " direction: [0, 1, 0], max_angle_deg: 60}}\n"
        "    count: 10\n"
        "validation_points: {nodes: all}\n" + extra)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default="out/py-cylinder", help="output folder")
    parser.add_argument("--small", action="store_true", help="a few seconds' version (tests)")
    args = parser.parse_args()
    nodes, steps = (200, 60) if args.small else (600, 300)
    observed = int(0.75 * steps)
    os.makedirs(args.out, exist_ok=True)

    truth = bcassim.scene.load_string(cylinder(nodes, 8000, steps), "truth.yaml", args.out)
    bcassim.scene.simulate(truth, os.path.join(args.out, "truth"))

    estimation = bcassim.scene.load_string(cylinder(nodes, 4000, steps, (
        "assimilation:\n"
        "  filter: roukf\n"
        "  threads: 2\n"
        "  parameters:\n"
        "    - {name: E, young_modulus: {region: 0}, mean: 4000, stddev: 2000, transform: log,"
        " truth: 8000}\n"
        f"  observations: {{tracks: truth/markers.csv, noise_stddev: 1.0e-4, sigma: 1.0e-4,"
        f" until_step: {observed}}}\n"
        "  validation: {tracks: truth/validation.csv}\n")), "estimate.yaml", args.out)

    def progress(p):
        if p.step % max(1, steps // 6) == 0:
            print(f"step {p.step}/{p.steps}: {p.estimate}{' (free run)' if p.free_run else ''}")

    result = bcassim.scene.assimilate(estimation, os.path.join(args.out, "estimate"), progress)
    (E,) = result.parameters
    print(f"E = {E.mean:.1f} ± {E.stddev:.1f} Pa (truth 8000 Pa, prior 4000 Pa); validation error "
          f"{result.estimated.all.mean_percent:.3f} % (prior {result.initial.all.mean_percent:.3f} %)"
          f"; median step {result.median_step_ms:.1f} ms")

    history = bcassim.io.read_estimates(os.path.join(args.out, "estimate", "estimates.csv"))["E"]
    fig, ax = plt.subplots(figsize=(6, 3.5))
    t, mean, sd = history["time_s"], history["mean"], history["stddev"]
    ax.fill_between(t, mean - 1.96 * sd, mean + 1.96 * sd, alpha=0.3, label="95 % band")
    ax.plot(t, mean, label="ROUKF estimate")
    ax.axhline(8000, color="k", ls="--", label="truth")
    ax.axvline(observed * estimation.dt, color="grey", ls=":", label="observations stop")
    ax.set(xlabel="time (s)", ylabel="Young's modulus E (Pa)", ylim=(0, 12000))
    ax.legend(loc="lower right")
    fig.tight_layout()
    plot = os.path.join(args.out, "young_modulus.png")
    fig.savefig(plot, dpi=120)
    print(f"plot: {plot}")
    if abs(E.mean - 8000) > 0.25 * 4000 or not os.path.getsize(plot):
        raise SystemExit("the estimate did not move towards the truth")


if __name__ == "__main__":
    main()
