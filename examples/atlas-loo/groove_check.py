#!/usr/bin/python3
"""Does the experts' falciform curve follow a groove that the liver's surface shows?

    examples/atlas-loo/groove_check.py [LIVERS_DIR] [--radius R ...]

If it did, a transferred atlas curve could be moved onto the nearest groove of the patient's own
surface. For every annotated liver (an .obj in mm and its .eseg: label 2 = falciform), each
vertex's height over the mean of the surface vertices within R mm, along its normal (negative in
a groove, positive on a ridge), and for each vertex of the curve the fraction of the surface
vertices within 25 mm that lie lower than it (0: the lowest around, 0.5: as a random vertex).
Prints per liver the median of that fraction over its curve, and over the livers the median and
the share of livers below 0.3. Needs numpy and scipy (/usr/bin/python3 has them); ~1 min per
radius for the 55 livers.
"""
import argparse
import glob
import os
import sys

import numpy as np
from scipy.spatial import cKDTree


def read_obj(path):
    V, F = [], []
    with open(path) as f:
        for line in f:
            p = line.split()
            if not p:
                continue
            if p[0] == "v":
                V.append([float(x) for x in p[1:4]])
            elif p[0] == "f":
                F.append([int(x.split("/")[0]) - 1 for x in p[1:4]])
    return np.array(V), np.array(F)


def eseg_edges(F):
    """The edges in .eseg order: each face's (0,1), (1,2), (2,0), first appearance kept."""
    seen, edges = set(), []
    for f in F:
        for k in range(3):
            a, b = int(f[k]), int(f[(k + 1) % 3])
            key = (min(a, b), max(a, b))
            if key not in seen:
                seen.add(key)
                edges.append((a, b))
    return np.array(edges)


def vertex_normals(V, F):
    n = np.zeros_like(V)
    face = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    for k in range(3):
        np.add.at(n, F[:, k], face)
    return n / np.linalg.norm(n, axis=1)[:, None]


def curve_rank(V, F, curve, radius, around=25.0):
    """Median over the curve's vertices of the fraction of vertices within `around` mm lower
    (by the height over their neighbourhood of `radius` mm) than it."""
    tree = cKDTree(V)
    N = vertex_normals(V, F)
    height = np.array([np.dot(V[i] - V[nb].mean(axis=0), N[i])
                       for i, nb in enumerate(tree.query_ball_point(V, radius))])
    ranks = [(height[nb] < height[i]).mean()
             for i, nb in zip(curve, tree.query_ball_point(V[curve], around))]
    return float(np.median(ranks))


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("livers", nargs="?",
                        default=os.path.join(here, "..", "..", "..", "shared", "data", "livers"))
    parser.add_argument("--radius", type=float, nargs="+", default=[6.0, 15.0, 30.0],
                        help="neighbourhood radii of the height, mm")
    a = parser.parse_args()
    names = sorted(os.path.basename(p)[:-5] for p in glob.glob(os.path.join(a.livers, "*.eseg")))
    if not names:
        sys.exit(f"{a.livers}: no .eseg files (expected a folder of annotated livers)")
    for radius in a.radius:
        medians = []
        for name in names:
            V, F = read_obj(os.path.join(a.livers, name + ".obj"))
            edges = eseg_edges(F)
            labels = np.loadtxt(os.path.join(a.livers, name + ".eseg"), dtype=int)
            if len(labels) != len(edges):
                print(f"{name}: {len(labels)} labels for {len(edges)} edges, skipped")
                continue
            curve = np.unique(edges[labels == 2].ravel())
            medians.append(curve_rank(V, F, curve, radius))
            print(f"R {radius:g} mm  {name:14s} curve vertices {len(curve):3d}  "
                  f"median rank {medians[-1]:.2f}", flush=True)
        m = np.array(medians)
        print(f"R {radius:g} mm: {len(m)} livers, median rank {np.median(m):.2f}, mean "
              f"{m.mean():.2f}, livers below 0.3: {(m < 0.3).sum()}", flush=True)


if __name__ == "__main__":
    main()
