#!/usr/bin/env python3
"""What a real sensor's frames do: dense ones (point_cloud.max_points), a background (keep_fraction).

Takes a registration scene written by run_mestdagh.py (OUT/register/<law>-<s>/register.yaml) and
its first FRAMES point clouds. By default grows each to POINTS points (every point repeated, each
copy moved by 0.5 mm of Gaussian noise: the density of an RGB-D frame, the same surface) and runs
`bcassim assimilate` with every point (max_points above POINTS) and with the default max_points
(voxel-grid thinning). With --table, adds instead a table: a plane 3 cm below the cloud's lowest
point, 5 cm wider on every side, with as many points as the organ's, and runs the scene as it is,
with keep_fraction 0.5 and with max_distance 0.015 m. Prints the median and slowest frame after
the first (ms), the interior error line and the last frame's estimate of each run.

    examples/mestdagh-liver/dense_clouds.py build out/mestdagh/register/neohookean-s1/register.yaml \
        out/dense [--frames 10] [--points 100000] [--table]
"""
import argparse
import csv
import glob
import os
import re
import statistics
import subprocess
import sys

import numpy as np


def natural_key(path):
    return [int(t) if t.isdigit() else t for t in re.split(r"(\d+)", os.path.basename(path))]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("build", help="build folder holding the bcassim executable")
    ap.add_argument("scene", help="a register.yaml written by run_mestdagh.py")
    ap.add_argument("out", help="output folder (created)")
    ap.add_argument("--frames", type=int, default=10, help="frames run (default 10)")
    ap.add_argument("--points", type=int, default=100000, help="points a frame (default 100000)")
    ap.add_argument("--table", action="store_true", help="add a table under the organ instead")
    args = ap.parse_args()
    text = open(args.scene).read()
    match = re.search(r'files: "([^"]+)"', text)
    if not match:
        sys.exit(f"{args.scene}: no point_cloud files line; expected a run_mestdagh.py scene")
    sources = sorted(glob.glob(match.group(1)), key=natural_key)[: args.frames]
    if len(sources) < args.frames:
        sys.exit(f"{match.group(1)}: {len(sources)} frames; expected at least {args.frames}")
    clouds = os.path.join(args.out, "pc")
    os.makedirs(clouds, exist_ok=True)
    rng = np.random.default_rng(1)
    for k, path in enumerate(sources):
        p = np.loadtxt(path)
        if args.table:
            lo, hi, n = p.min(axis=0), p.max(axis=0), len(p)
            table = np.column_stack([rng.uniform(lo[0] - 0.05, hi[0] + 0.05, n),
                                     rng.uniform(lo[1] - 0.05, hi[1] + 0.05, n),
                                     np.full(n, lo[2] - 0.03)])
            np.save(os.path.join(clouds, f"pc{k}.npy"), np.vstack([p, table]))
            continue
        copies = -(-args.points // len(p))
        dense = np.repeat(p, copies, axis=0)[: args.points]
        dense = dense + rng.normal(0.0, 5e-4, dense.shape)
        np.save(os.path.join(clouds, f"pc{k}.npy"), dense)
    text = text.replace(match.group(0), f'files: "{os.path.abspath(clouds)}/pc*.npy"')
    text = re.sub(r"time: \{dt: ([^,]+), steps: \d+\}", rf"time: {{dt: \1, steps: {args.frames}}}",
                  text)
    exe = os.path.join(args.build, "bcassim")
    variants = ((("as-is", None), ("keep-half", "keep_fraction: 0.5"),
                 ("max-15mm", "max_distance: 0.015")) if args.table else
                (("every-point", f"max_points: {args.points + 1}"), ("thinned", None)))
    for name, extra in variants:
        scene_text = text
        if extra:
            scene_text = re.sub(r"(\n(\s+)point_cloud:\n)", rf"\1\2  {extra}\n", text, count=1)
        scene = os.path.join(args.out, f"{name}.yaml")
        with open(scene, "w") as f:
            f.write(scene_text)
        run = os.path.join(args.out, name)
        done = subprocess.run([exe, "assimilate", scene, "--out", run, "-q", "--no-plots"],
                              check=True, capture_output=True, text=True)
        lines = done.stdout.splitlines()
        error = next((lines[i + 1].strip() for i, line in enumerate(lines)
                      if line.startswith("validation error") and i + 1 < len(lines)), "")
        with open(os.path.join(run, "timing.csv")) as f:
            frames = [float(r["total_ms"]) for r in csv.DictReader(f)][1:]
        with open(os.path.join(run, "estimates.csv")) as f:
            rows = list(csv.DictReader(f))
        last = {r["parameter"]: float(r["mean"]) for r in rows if r["step"] == rows[-1]["step"]}
        notices = open(os.path.join(run, "notices.txt")).read().strip().splitlines()
        thinning = next((n for n in notices if n.startswith("point_cloud:")), "not thinned")
        print(f"{name}: frames 2-{args.frames} median {statistics.median(frames):.1f} ms, "
              f"slowest {max(frames):.1f} ms; last estimate "
              + ", ".join(f"{k} {v:.4g}" for k, v in last.items()) + f"; {thinning}; {error}")


if __name__ == "__main__":
    main()
