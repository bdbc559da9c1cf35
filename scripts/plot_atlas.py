#!/usr/bin/env python3
"""PNG picture of a `bcassim atlas build` or `bcassim atlas transfer` output folder.

Usage: plot_atlas.py DIR [TITLE]

Reads DIR/surface.obj (template or registered template, m), DIR/mean_curve.csv (x,y,z,sigma),
DIR/band_lower.csv and DIR/band_upper.csv, and when present DIR/curves.csv (the database curves
carried onto the template: curve,x,y,z) and DIR/expert_curve.csv. Writes DIR/atlas.png: the surface
seen from the front and from above, the mean curve (yellow), its ±σ band (violet), the carried
curves (thin green) and the expert curve (black). Needs matplotlib only.
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402


def read_obj(path):
    v, f = [], []
    with open(path) as fh:
        for line in fh:
            p = line.split()
            if not p:
                continue
            if p[0] == "v":
                v.append(tuple(1e3 * float(x) for x in p[1:4]))
            elif p[0] == "f":
                f.append(tuple(int(x.split("/")[0]) - 1 for x in p[1:4]))
    return v, f


def read_xyz(path):
    if not os.path.exists(path):
        return []
    with open(path, newline="") as fh:
        return [(1e3 * float(r["x"]), 1e3 * float(r["y"]), 1e3 * float(r["z"])) for r in csv.DictReader(fh)]


def read_curves(path):
    curves = {}
    if os.path.exists(path):
        with open(path, newline="") as fh:
            for r in csv.DictReader(fh):
                curves.setdefault(r["curve"], []).append(
                    (1e3 * float(r["x"]), 1e3 * float(r["y"]), 1e3 * float(r["z"])))
    return list(curves.values())


def line(ax, pts, **kw):
    if pts:
        ax.plot([p[0] for p in pts], [p[1] for p in pts], [p[2] for p in pts], **kw)


def main():
    if len(sys.argv) < 2:
        print("usage: plot_atlas.py DIR [TITLE]")
        return 1
    d = sys.argv[1]
    title = sys.argv[2] if len(sys.argv) > 2 else d
    surf = os.path.join(d, "surface.obj")
    if not os.path.exists(surf):
        print(f"{surf}: missing (expected the output of bcassim atlas build/transfer)")
        return 1
    v, f = read_obj(surf)
    mean = read_xyz(os.path.join(d, "mean_curve.csv"))
    lo = read_xyz(os.path.join(d, "band_lower.csv"))
    hi = read_xyz(os.path.join(d, "band_upper.csv"))
    expert = read_xyz(os.path.join(d, "expert_curve.csv"))
    curves = read_curves(os.path.join(d, "curves.csv"))
    fig = plt.figure(figsize=(12, 6))
    lo_c = [min(p[i] for p in v) for i in range(3)]
    hi_c = [max(p[i] for p in v) for i in range(3)]
    for k, (elev, azim, name) in enumerate(((0, -90, "front (-y)"), (90, -90, "top (+z)"))):
        ax = fig.add_subplot(1, 2, k + 1, projection="3d")
        ax.add_collection3d(Poly3DCollection([[v[i] for i in t] for t in f], facecolor=(0.85, 0.55, 0.5, 0.25),
                                             edgecolor=(0.5, 0.3, 0.3, 0.08), linewidth=0.2))
        for c in curves:
            line(ax, c, color="tab:green", lw=0.6, alpha=0.6)
        if lo and hi:
            line(ax, lo, color="darkviolet", lw=1.5)
            line(ax, hi, color="darkviolet", lw=1.5)
            for a, b in zip(lo, hi):
                line(ax, [a, b], color="violet", lw=0.8, alpha=0.7)
        line(ax, mean, color="gold", lw=3, marker="o", ms=3, label="mean")
        line(ax, expert, color="black", lw=2, label="expert")
        ax.set_xlim(lo_c[0], hi_c[0])
        ax.set_ylim(lo_c[1], hi_c[1])
        ax.set_zlim(lo_c[2], hi_c[2])
        ax.set_box_aspect([hi_c[i] - lo_c[i] for i in range(3)])
        ax.view_init(elev=elev, azim=azim)
        ax.set_xlabel("x (mm)")
        ax.set_ylabel("y (mm)")
        ax.set_zlabel("z (mm)")
        ax.set_title(name)
    fig.suptitle(title)
    fig.tight_layout()
    out = os.path.join(d, "atlas.png")
    fig.savefig(out, dpi=90)
    return 0


if __name__ == "__main__":
    sys.exit(main())
