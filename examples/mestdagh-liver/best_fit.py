#!/usr/bin/python3
"""The best tool force the linear sequences allow on mesh-remeshed, found without bcassim.

    examples/mestdagh-liver/best_fit.py OUT_DIR [--data DIR] [--only SEQ ...] [--shares NAME ...]

A check of the registration's force error (run_mestdagh.py), independent of bcassim's code: a
P1 linear-elasticity model of mesh-remeshed written here with NumPy/SciPy (E 20 kPa, nu 0.45, the
data's fixed vertices: what register.yaml gives bcassim), loaded by a unit force in x, y or z
shared over the mesh in one of three ways, and for every frame on its own (no prior, no noise
model, nothing carried between frames but the start of the iterations) the three force components
that fit best:

  clouds:          point-to-plane ICP against the frame's point cloud, as an estimator sees it
                   (no correspondences; each point to its closest point on the deformed matching
                   surface, its residual along that triangle's normal;
                   points beyond max(3 x median, 5 mm) left out, as register.yaml's cutoff does);
  correspondences: the true displacements of mesh-default's matching vertices (known
                   correspondences, no noise): what the model itself can fit at best.

The shares of the force over the mesh:

  surface: a uniform traction on the zone's faces (register.yaml's default, --distribution surface);
  nodes:   an even split over the zone's vertices (--distribution nodes);
  tool:    the true tool vertices of mesh-default given to mesh-remeshed by barycentric weights, a
           footprint no estimator is given (run_mestdagh.py --floor uses the same).

Per sequence and share: the force error |F - F_true| / |F_true| averaged over the 50 frames, and
from frame 10 on the mean magnitude error and angle (register.csv's columns), and the mean
interior error at mesh-default's interior nodes. Linear sequences only (the Neo-Hookean ones need
a nonlinear model). Writes OUT_DIR/best_fit.csv and prints the table. Needs numpy and scipy
(/usr/bin/python3 has them); ~1 min per sequence.
"""
import argparse
import csv
import glob
import os
import sys

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spl
from scipy.spatial import cKDTree

import run_mestdagh as rm

YOUNG, POISSON = 20e3, 0.45  # Pa, -: rm.material_of's linear law
FIRST_LATE_FRAME = 9  # 0-based: "from frame 10 on", as register.csv
CANDIDATES = 12  # triangles, by centroid, searched for each cloud point's closest point


def stiffness(X, T):
    """P1 linear-elasticity stiffness (N/m), 3 dofs per node, node-major."""
    lam = YOUNG * POISSON / ((1 + POISSON) * (1 - 2 * POISSON))
    mu = YOUNG / (2 * (1 + POISSON))
    C = np.zeros((6, 6))
    C[:3, :3] = lam
    C[range(3), range(3)] += 2 * mu
    C[range(3, 6), range(3, 6)] = mu
    M = np.ones((len(T), 4, 4))
    M[:, :, 1:] = X[T]
    volume = np.abs(np.linalg.det(M)) / 6
    G = np.linalg.inv(M)[:, 1:, :]  # d(shape a)/d(x_i): m x 3 x 4
    B = np.zeros((len(T), 6, 12))
    for a in range(4):
        gx, gy, gz = G[:, 0, a], G[:, 1, a], G[:, 2, a]
        B[:, 0, 3 * a], B[:, 1, 3 * a + 1], B[:, 2, 3 * a + 2] = gx, gy, gz
        B[:, 3, 3 * a], B[:, 3, 3 * a + 1] = gy, gx
        B[:, 4, 3 * a + 1], B[:, 4, 3 * a + 2] = gz, gy
        B[:, 5, 3 * a], B[:, 5, 3 * a + 2] = gz, gx
    Ke = volume[:, None, None] * np.einsum("mki,kl,mlj->mij", B, C, B)
    dof = (3 * T[:, :, None] + np.arange(3)).reshape(len(T), 12)
    rows = np.repeat(dof, 12, axis=1).ravel()
    cols = np.tile(dof, (1, 12)).ravel()
    n = 3 * len(X)
    return sp.csc_matrix((Ke.ravel(), (rows, cols)), shape=(n, n))


def locate(W, T, points):
    """Tet and barycentric weights (clipped to >= 0, summing to 1) of each point in mesh (W, T):
    the tet among the 40 nearest by centroid whose smallest weight is largest."""
    tree = cKDTree(W[T].mean(axis=1))
    _, candidates = tree.query(points, k=40)
    tets = np.empty(len(points), dtype=int)
    weights = np.empty((len(points), 4))
    for i, (p, cand) in enumerate(zip(points, candidates)):
        M = np.ones((len(cand), 4, 4))
        M[:, :, 1:] = W[T[cand]]
        rhs = np.broadcast_to(np.r_[1.0, p], (len(cand), 4))
        b = np.linalg.solve(np.transpose(M, (0, 2, 1)), rhs)
        best = int(np.argmax(b.min(axis=1)))
        w = np.clip(b[best], 0, None)
        tets[i], weights[i] = cand[best], w / w.sum()
    return tets, weights


def shares_of(name, data, seq, W, T):
    """Nodal shares (sum 1) of a unit total force on mesh-remeshed."""
    shares = np.zeros(len(W))
    if name == "tool":
        for node, share in rm.tool_shares(data, seq).items():
            shares[node] += share
        return shares
    zone = np.load(os.path.join(data, "sequences", seq, "forces-vertices-remeshed.npy")).ravel()
    if name == "nodes":
        shares[zone] = 1.0
        return shares / shares.sum()
    listed = np.zeros(len(W), dtype=bool)
    listed[zone] = True
    faces = rm.boundary_faces(T)
    faces = faces[listed[faces].all(axis=1)]
    area = 0.5 * np.linalg.norm(np.cross(W[faces[:, 1]] - W[faces[:, 0]],
                                         W[faces[:, 2]] - W[faces[:, 0]]), axis=1)
    for k in range(3):
        np.add.at(shares, faces[:, k], area / 3)
    return shares / shares.sum()


def closest_on_triangles(X, candidates, points):
    """Closest point to each point on the triangles X (t x 3 x 3) among its candidate triangles
    (p x c): the triangle and the point's barycentric weights there (p, p x 3) and the distance."""
    A, B, C = (X[candidates][:, :, k] for k in range(3))  # p x c x 3 each
    P = points[:, None, :]
    # The closest point is inside the triangle (the plane's foot) or on one of its edges.
    e0, e1, q = B - A, C - A, P - A
    d00, d01, d11 = (e0 * e0).sum(-1), (e0 * e1).sum(-1), (e1 * e1).sum(-1)
    d20, d21 = (q * e0).sum(-1), (q * e1).sum(-1)
    det = d00 * d11 - d01 * d01
    v = (d11 * d20 - d01 * d21) / det
    w = (d00 * d21 - d01 * d20) / det
    inside = (v >= 0) & (w >= 0) & (v + w <= 1)
    weights = np.stack([1 - v - w, v, w], axis=-1)
    foot = A + v[..., None] * e0 + w[..., None] * e1
    distance = np.where(inside, np.linalg.norm(P - foot, axis=-1), np.inf)
    for i, j in [(0, 1), (1, 2), (2, 0)]:
        Xi, Xj = (A, B, C)[i], (A, B, C)[j]
        edge = Xj - Xi
        s = np.clip(((P - Xi) * edge).sum(-1) / (edge * edge).sum(-1), 0, 1)
        on_edge = Xi + s[..., None] * edge
        d = np.linalg.norm(P - on_edge, axis=-1)
        closer = d < distance
        distance = np.where(closer, d, distance)
        bary = np.zeros_like(weights)
        bary[..., i], bary[..., j] = 1 - s, s
        weights = np.where(closer[..., None], bary, weights)
    k = np.argmin(distance, axis=1)
    rows = np.arange(len(points))
    return candidates[rows, k], weights[rows, k], distance[rows, k]


def fit_cloud(W, tris, basis, cloud, start):
    """Point-to-plane ICP: the force (3) whose displacement basis (3 x #W x 3) brings the surface
    tris closest to the cloud, from `start`."""
    force = start.copy()
    rest = W[tris]  # t x 3 x 3
    moved = basis[:, tris]  # 3 x t x 3 x 3
    for _ in range(50):
        X = rest + np.einsum("c,ctkd->tkd", force, moved)
        normal = np.cross(X[:, 1] - X[:, 0], X[:, 2] - X[:, 0])
        normal /= np.linalg.norm(normal, axis=1)[:, None]
        _, candidates = cKDTree(X.mean(axis=1)).query(cloud, k=CANDIDATES)
        tri, bary, distance = closest_on_triangles(X, candidates, cloud)
        keep = distance <= max(3 * np.median(distance), 5e-3)
        tri, bary = tri[keep], bary[keep]
        n = normal[tri]
        at_rest = np.einsum("tk,tkd->td", bary, rest[tri])
        response = np.einsum("tk,ctkd->tcd", bary, moved[:, tri])  # t x 3 x 3
        A = np.einsum("tcd,td->tc", response, n)
        r = np.einsum("td,td->t", cloud[keep] - at_rest, n)
        new, *_ = np.linalg.lstsq(A, r, rcond=None)
        done = np.linalg.norm(new - force) <= 1e-6 * max(1.0, np.linalg.norm(new))
        force = new
        if done:
            break
    return force


class Model:
    """mesh-default (the truth's) and mesh-remeshed (the model's, factorised with the data's fixed
    vertices), and where mesh-default's interior and seen vertices lie in mesh-remeshed."""

    def __init__(self, data):
        self.V, TV = rm.read_msh_nodes_and_tets(os.path.join(data, "mesh-default", "liver.msh"))
        self.W, self.T = rm.read_msh_nodes_and_tets(
            os.path.join(data, "mesh-remeshed", "liver.msh"))
        fixed = np.load(os.path.join(data, "mesh-remeshed", "dirichlet-vertices.npy")).ravel()
        self.free = np.ones(3 * len(self.W), dtype=bool)
        self.free[(3 * fixed[:, None] + np.arange(3)).ravel()] = False
        K = stiffness(self.W, self.T)
        self.solver = spl.splu(K[self.free][:, self.free].tocsc())
        self.tris = np.load(os.path.join(data, "mesh-remeshed", "matching-triangles.npy"))
        self.interior = np.setdiff1d(np.arange(len(self.V)), rm.boundary_nodes(TV))
        seen_triangles = np.load(os.path.join(data, "mesh-default", "matching-triangles.npy"))
        self.seen = np.unique(seen_triangles)
        self.interior_at = locate(self.W, self.T, self.V[self.interior])
        self.seen_at = locate(self.W, self.T, self.V[self.seen])

    def basis(self, shares):
        """Displacements (3 x #W x 3, m per N) under a unit total force in x, y and z."""
        out = np.zeros((3, len(self.W), 3))
        for c in range(3):
            f = np.zeros((len(self.W), 3))
            f[:, c] = shares
            u = np.zeros(3 * len(self.W))
            u[self.free] = self.solver.solve(f.ravel()[self.free])
            out[c] = u.reshape(-1, 3)
        return out

    def at(self, basis, where):
        """basis (3 x #W x 3) interpolated at located points: p x 3 (xyz) x 3 (force component)."""
        tets, weights = where
        return np.stack([np.einsum("pk,pkd->pd", weights, basis[c][self.T[tets]])
                         for c in range(3)], axis=2)


def fit_sequence(model, data, seq, name, method):
    """One row of the table: the best force of every frame by `method`, with `name`'s shares."""
    folder = os.path.join(data, "sequences", seq)
    truth_force = np.load(os.path.join(folder, "true-forces.npy"))
    truth = np.load(os.path.join(folder, "positions-default.npy"))
    V, interior, seen = model.V, model.interior, model.seen
    rest_error = np.mean([np.linalg.norm(truth[k][interior] - V[interior], axis=1).mean()
                          for k in range(len(truth))])
    basis = model.basis(shares_of(name, data, seq, model.W, model.T))
    seen_basis = model.at(basis, model.seen_at).reshape(-1, 3)
    interior_basis = model.at(basis, model.interior_at)
    clouds = sorted(glob.glob(os.path.join(folder, "pointclouds", "pc*.txt")))
    error, magnitude, angle, inner = [], [], [], []
    force = np.zeros(3)
    for k, true in enumerate(truth_force):
        if method == "clouds":
            force = fit_cloud(model.W, model.tris, basis, np.loadtxt(clouds[k]), force)
        else:
            u = (truth[k][seen] - V[seen]).ravel()
            force, *_ = np.linalg.lstsq(seen_basis, u, rcond=None)
        error.append(np.linalg.norm(force - true) / np.linalg.norm(true))
        moved = V[interior] + interior_basis @ force
        inner.append(np.linalg.norm(moved - truth[k][interior], axis=1).mean())
        if k >= FIRST_LATE_FRAME:
            magnitude.append(np.linalg.norm(force) / np.linalg.norm(true) - 1)
            cosine = force @ true / (np.linalg.norm(force) * np.linalg.norm(true))
            angle.append(np.degrees(np.arccos(np.clip(cosine, -1, 1))))
    return {"sequence": seq, "shares": name, "fit": method,
            "force_error_mean_pct": 100 * np.mean(error),
            "magnitude_from_frame10_pct": 100 * np.mean(magnitude),
            "angle_from_frame10_deg": np.mean(angle),
            "interior_error_mean_mm": 1e3 * np.mean(inner),
            "interior_pct_of_rest": 100 * np.mean(inner) / rest_error}


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("out", help="output folder (best_fit.csv)")
    parser.add_argument("--data", default=os.path.join(here, "..", "..", "..", "shared", "data",
                                                       "mestdagh-liver"))
    parser.add_argument("--only", nargs="+", metavar="linear/NAME",
                        help="these sequences (default: every linear one of the data folder)")
    parser.add_argument("--shares", nargs="+", default=["surface", "nodes", "tool"],
                        choices=["surface", "nodes", "tool"])
    a = parser.parse_args()
    if not os.path.isfile(os.path.join(a.data, "mesh-remeshed", "liver.msh")):
        sys.exit(f"{a.data}: no mesh-remeshed/liver.msh (expected the mestdagh-liver data folder)")
    a.data = os.path.normpath(a.data)
    if a.only is None:
        a.only = [s for s in rm.sequences_in(a.data) if s.startswith("linear/")]
    rm.check_sequences(a.data, a.only)
    if any(not s.startswith("linear/") for s in a.only):
        sys.exit(f"{a.data}: {', '.join(s for s in a.only if not s.startswith('linear/'))}: "
                 "not a linear sequence (this fit's model is linear elastic)")
    os.makedirs(a.out, exist_ok=True)
    model = Model(a.data)
    fields = ["sequence", "shares", "fit", "force_error_mean_pct", "magnitude_from_frame10_pct",
              "angle_from_frame10_deg", "interior_error_mean_mm", "interior_pct_of_rest"]
    with open(os.path.join(a.out, "best_fit.csv"), "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=fields)
        writer.writeheader()
        for seq in a.only:
            for name in a.shares:
                for method in ["clouds", "correspondences"]:
                    row = fit_sequence(model, a.data, seq, name, method)
                    writer.writerow({k: (f"{v:.4g}" if isinstance(v, float) else v)
                                     for k, v in row.items()})
                    f.flush()  # a row per fit as it comes: an interrupted run keeps them
                    print(f"{seq:10s} {name:8s} {method:16s} force "
                          f"{row['force_error_mean_pct']:5.1f} % (from frame 10: "
                          f"{row['magnitude_from_frame10_pct']:+5.1f} %, "
                          f"{row['angle_from_frame10_deg']:4.1f} deg)  interior "
                          f"{row['interior_error_mean_mm']:.2f} mm = "
                          f"{row['interior_pct_of_rest']:4.1f} % of rest", flush=True)


if __name__ == "__main__":
    main()
