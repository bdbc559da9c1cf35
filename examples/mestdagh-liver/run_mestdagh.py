#!/usr/bin/python3
"""The mestdagh-liver benchmark (../shared/data/mestdagh-liver, made with FEniCS) with bcassim.

    examples/mestdagh-liver/run_mestdagh.py BUILD_DIR OUT_DIR [--data DIR] [--only LAW/NAME ...]
        [--skip-verify] [--skip-register] [--floor] [--threads N] [--tangent mean|own]
        [--footprint [full|tilt]] [--distribution surface|nodes] [--pose-error DEG MM]
        [--estimate-pose]

verify:   static solves of mesh-default under the true tool forces (`bcassim simulate`,
          verify.yaml) against positions-default.npy: relative displacement error
          |u - u_true| / |u_true| over all nodes, per frame.
floor:    (--floor) the true tool force applied on mesh-remeshed (`bcassim simulate`, floor.yaml),
          shared over its vertices by the barycentric weights of the true tool vertices: the
          interior error left by the estimation mesh itself when the force is known, and the
          factor on its displacements that fits the truth best (> 1: this mesh is stiffer than
          the one that made the data, < 1: softer; a force estimated from shapes alone carries it).
register: from mesh-remeshed and the point clouds only, the tool force estimated frame after
          frame (`bcassim assimilate`, register.yaml); interior nodes of mesh-default
          interpolated from the estimate (validation points mapped into mesh-remeshed) against
          the truth, next to the rest shape; force error |F_est - F_true| / |F_true|.
          --pose-error DEG MM: every cloud moved by the same rigid motion first (DEG degrees
          about an axis through the first cloud's centroid, MM millimetres along a direction,
          both drawn once with a fixed seed): the clouds of a camera registered that far off.
          --estimate-pose: the observations' pose estimated with the force (six `pose`
          parameters, docs/assimilation-format.md).

The scenes are templates: {data}, {sequence}, {inputs}, {material}, {fixed}, {distribution}
and {threads} are filled in per sequence ({material}: the law of the sequence's family, for both
checks; {distribution}: --distribution, the same for all), nothing else changes between
sequences. Derived inputs (the fixed
vertices without 756, the interior nodes and their true tracks) are written under OUT_DIR, never
into the repository. Summaries: OUT_DIR/verify.csv, OUT_DIR/register.csv and
OUT_DIR/summary.md (the tables of docs/results.md). Needs numpy (/usr/bin/python3 has it).

The sequences are those the data folder holds (every sequences/LAW/NAME with a true-forces.npy,
LAW linear or neohookean), unless --only names some.
"""
import argparse
import csv
import glob
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
LAWS = ("linear", "neohookean")  # the data README's two families, whose constants material_of knows
DT = 1.0  # s per frame: the scenes' time.dt (random walks are per sqrt(s) = per frame)


def read_msh_nodes_and_tets(path):
    """Node positions (#V x 3) and tets (#T x 4, 0-based) of a Gmsh 2.2 ASCII file."""
    with open(path) as f:
        lines = f.read().split("\n")
    i = lines.index("$Nodes")
    n = int(lines[i + 1])
    V = np.array([[float(x) for x in l.split()[1:4]] for l in lines[i + 2:i + 2 + n]])
    j = lines.index("$Elements")
    m = int(lines[j + 1])
    T = []
    for l in lines[j + 2:j + 2 + m]:
        p = [int(x) for x in l.split()]
        if p[1] == 4:
            T.append(p[3 + p[2]:])
    return V, np.array(T) - 1


def boundary_faces(T):
    """Faces (sorted vertex ids) that belong to one tet only."""
    faces = np.sort(np.concatenate([T[:, [0, 1, 2]], T[:, [0, 1, 3]], T[:, [0, 2, 3]],
                                    T[:, [1, 2, 3]]]), axis=1)
    unique, counts = np.unique(faces, axis=0, return_counts=True)
    return unique[counts == 1]


def boundary_nodes(T):
    """Nodes on faces that belong to one tet only."""
    return np.unique(boundary_faces(T))


def fill(template, **values):
    with open(os.path.join(HERE, template)) as f:
        text = f.read()
    for key, value in values.items():
        text = text.replace("{" + key + "}", str(value))
    return text


class RunFailed(Exception):
    """bcassim exited with an error: its last line (the one-line reason) is the message."""


def run(cmd, log):
    with open(log, "w") as out:
        code = subprocess.call(cmd, stdout=out, stderr=subprocess.STDOUT)
    if code != 0:
        with open(log) as f:
            lines = [l.strip() for l in f if l.strip()]
        raise RunFailed(f"exit {code}: {lines[-1] if lines else '(no output)'}")


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def sequences_in(data):
    """The data folder's sequences as LAW/NAME, sorted: every sequences/LAW/NAME holding a
    true-forces.npy (a copy with more or fewer of them runs as it is, not against a fixed list)."""
    root = os.path.join(data, "sequences")
    return sorted(os.path.relpath(os.path.dirname(p), root).replace(os.sep, "/")
                  for p in glob.glob(os.path.join(root, "*", "*", "true-forces.npy")))


def check_sequences(data, sequences):
    """Stops with one line naming the first sequence that is not in the data folder or whose law
    is not one of LAWS (its constants would be unknown), or when there is none."""
    if not sequences:
        sys.exit(f"{data}: no sequences/LAW/NAME/true-forces.npy (expected the mestdagh-liver "
                 "data folder)")
    for seq in sequences:
        folder = os.path.join(data, "sequences", seq)
        if not os.path.isfile(os.path.join(folder, "true-forces.npy")):
            sys.exit(f"{folder}: no true-forces.npy (expected a sequence LAW/NAME of the data "
                     "folder)")
        if seq.split("/")[0] not in LAWS:
            sys.exit(f"{folder}: law '{seq.split('/')[0]}' unknown (expected "
                     f"{' or '.join(LAWS)}, the data README's families)")


def material_of(seq):
    """The law of the sequence's family with its constants: Neo-Hookean E 4500 Pa, nu 0.49 (the
    data README); linear E 20 kPa, nu 0.45, which the README does not state: those of the
    original repository's SOFA example (python/liver_with_sofa.py), and the only pair that
    reproduces the linear truths (E 4500 Pa, nu 0.49 is 2.5 times off; see docs/results.md)."""
    if seq.startswith("neohookean"):
        return "{model: neohookean, young_modulus: 4500, poisson_ratio: 0.49}"
    return "{model: linear, young_modulus: 20000, poisson_ratio: 0.45}"


def verify(bcassim, data, out, seq):
    """Per-frame relative displacement error of the static solve against positions-default."""
    work = os.path.join(out, "verify", seq.replace("/", "-"))
    os.makedirs(work, exist_ok=True)
    neo = seq.startswith("neohookean")
    fixed = np.load(os.path.join(data, "mesh-default", "dirichlet-vertices.npy"))
    # README quirk: vertex 756 moves in the Neo-Hookean truth (free there); the linear
    # sequences hold all 106.
    if neo:
        fixed = fixed[fixed != 756]
    fixed_file = os.path.join(work, "fixed.txt")
    np.savetxt(fixed_file, fixed, fmt="%d")
    material = material_of(seq)
    scene = os.path.join(work, "verify.yaml")
    with open(scene, "w") as f:
        f.write(fill("verify.yaml", data=data, sequence=seq, material=material, fixed=fixed_file))
    run([bcassim, "simulate", scene, "--out", os.path.join(work, "run"), "-q"],
        os.path.join(work, "simulate.log"))
    V, _ = read_msh_nodes_and_tets(os.path.join(data, "mesh-default", "liver.msh"))
    truth = np.load(os.path.join(data, "sequences", seq, "positions-default.npy"))
    rows = np.loadtxt(os.path.join(work, "run", "validation.csv"), delimiter=",", skiprows=1)
    errors = []
    for k in range(truth.shape[0]):
        frame = rows[np.abs(rows[:, 0] - (k + 1) * DT) < 1e-9 * DT]
        x = np.empty_like(V)
        x[frame[:, 1].astype(int)] = frame[:, 2:5]
        errors.append(np.linalg.norm(x - truth[k]) / np.linalg.norm(truth[k] - V))
    return np.array(errors)


def tool_shares(data, seq):
    """The true tool vertices of mesh-default as nodal shares on mesh-remeshed: each tool vertex
    (force / count) given to the vertices of the remeshed tet that holds it, by its barycentric
    weights (negative ones, for a vertex just outside the mesh, clipped). {vertex: share}."""
    V, _ = read_msh_nodes_and_tets(os.path.join(data, "mesh-default", "liver.msh"))
    W, T = read_msh_nodes_and_tets(os.path.join(data, "mesh-remeshed", "liver.msh"))
    tool = np.loadtxt(os.path.join(data, "sequences", seq, "tool-vertices-default.txt"),
                      dtype=int, ndmin=1)
    edges = np.stack([W[T[:, 1]] - W[T[:, 0]], W[T[:, 2]] - W[T[:, 0]],
                      W[T[:, 3]] - W[T[:, 0]]], axis=2)
    shares = {}
    for v in tool:
        b = np.linalg.solve(edges, (V[v] - W[T[:, 0]])[:, :, None])[:, :, 0]
        b = np.concatenate([1 - b.sum(axis=1, keepdims=True), b], axis=1)
        best = int(np.argmax(b.min(axis=1)))
        w = np.clip(b[best], 0, None)
        for node, weight in zip(T[best], w / w.sum()):
            shares[int(node)] = shares.get(int(node), 0.0) + weight / len(tool)
    return shares


def floor(bcassim, data, out, seq):
    """Interior error of mesh-remeshed under the true force (the estimation mesh's own error),
    and the factor on its displacements that fits the truth best, per frame."""
    work = os.path.join(out, "floor", seq.replace("/", "-"))
    os.makedirs(work, exist_ok=True)
    V, T = read_msh_nodes_and_tets(os.path.join(data, "mesh-default", "liver.msh"))
    interior = np.setdiff1d(np.arange(len(V)), boundary_nodes(T))
    points = os.path.join(work, "interior-points.csv")
    np.savetxt(points, V[interior], delimiter=",", header="x,y,z", comments="", fmt="%.17g")
    forces = np.load(os.path.join(data, "sequences", seq, "true-forces.npy"))
    loads = []
    for node, share in sorted(tool_shares(data, seq).items()):
        frames = os.path.join(work, f"force-{node}.npy")
        np.save(frames, share * forces)
        loads.append(f"  - region: {{nodes: [{node}]}}\n    total_force_frames: \"{frames}\"")
    scene = os.path.join(work, "floor.yaml")
    with open(scene, "w") as f:
        f.write(fill("floor.yaml", data=data, material=material_of(seq), points=points,
                     loads="\n".join(loads)))
    run([bcassim, "simulate", scene, "--out", os.path.join(work, "run"), "-q"],
        os.path.join(work, "simulate.log"))
    truth = np.load(os.path.join(data, "sequences", seq, "positions-default.npy"))[:, interior]
    rows = np.loadtxt(os.path.join(work, "run", "validation.csv"), delimiter=",", skiprows=1)
    mean_mm, max_mm, rest_mm, factor, scaled_mm = [], [], [], [], []
    for k in range(truth.shape[0]):
        frame = rows[np.abs(rows[:, 0] - (k + 1) * DT) < 1e-9 * DT]
        x = np.empty((len(interior), 3))
        x[frame[:, 1].astype(int)] = frame[:, 2:5]
        u, u_true = x - V[interior], truth[k] - V[interior]
        e = 1e3 * np.linalg.norm(u - u_true, axis=1)
        mean_mm.append(e.mean())
        max_mm.append(e.max())
        rest_mm.append(1e3 * np.linalg.norm(u_true, axis=1).mean())
        factor.append(float((u * u_true).sum() / (u * u).sum()))
        # Under the linear law the displacement is linear in the force: factor x the true force
        # is the force that fits the truth best on this mesh, and this its interior error.
        scaled_mm.append(1e3 * np.linalg.norm(factor[-1] * u - u_true, axis=1).mean())
    return {"sequence": seq, "mean_mm": np.mean(mean_mm), "max_mm": np.max(max_mm),
            "mean_pct_of_rest": 100 * np.mean(mean_mm) / np.mean(rest_mm),
            "factor_min": np.min(factor), "factor_max": np.max(factor),
            "factor_median": float(np.median(factor)),
            "best_multiple_mean_mm": np.mean(scaled_mm) if seq.startswith("linear") else None}


# --footprint: the force's share over the zone estimated too (LoadFootprint): "full" = tilts and
# concentration, "tilt" = the tilts only (the force's centre moves, its spread stays the zone's).
FOOTPRINT_TILTS = """
    - {force: {load: 0, footprint: tilt_u}, mean: 0, stddev: 1, random_walk: 0.02}
    - {force: {load: 0, footprint: tilt_v}, mean: 0, stddev: 1, random_walk: 0.02}"""
# The observations' pose (a camera registration's error): a prior of 0.1 rad (~6 deg) and 1 cm,
# with a random walk (0.01 rad, 1 mm per sqrt(s)) so that a first frame that turns it far can be
# undone by the next ones (docs/results.md, *A camera registered off*).
POSE_PARAMETERS = "".join(
    f"\n    - {{pose: {c}, mean: 0, stddev: {0.1 if c[0] == 'r' else 0.01}, "
    f"random_walk: {0.01 if c[0] == 'r' else 0.001}}}"
    for c in ("rx", "ry", "rz", "tx", "ty", "tz"))


def moved_clouds(data, seq, pose_error, folder):
    """The sequence's clouds moved by one rigid motion of pose_error = (degrees, millimetres)."""
    rng = np.random.default_rng(2022)
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    direction = rng.normal(size=3)
    direction /= np.linalg.norm(direction)
    a = np.radians(pose_error[0])
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    R = np.eye(3) + np.sin(a) * K + (1 - np.cos(a)) * K @ K
    source = os.path.join(data, "sequences", seq, "pointclouds")
    files = sorted(f for f in os.listdir(source) if f.endswith(".txt"))
    centre = np.loadtxt(os.path.join(source, files[0])).mean(axis=0)
    os.makedirs(folder, exist_ok=True)
    for name in files:
        p = np.loadtxt(os.path.join(source, name))
        moved = (p - centre) @ R.T + centre + 1e-3 * pose_error[1] * direction
        np.savetxt(os.path.join(folder, name), moved, fmt="%.17g")
    return folder


FOOTPRINT_PARAMETERS = {
    "none": "",
    "tilt": FOOTPRINT_TILTS,
    "full": FOOTPRINT_TILTS + """
    - {force: {load: 0, footprint: concentration}, mean: 0, stddev: 1, random_walk: 0.02}""",
}

TANGENT_SETTINGS = {
    "mean": "tangent: mean\n  tangent_refresh_every: 2\n  tangent_background: true",
    "own": "tangent: own\n  reuse_factorization: false",
}


def register(bcassim, data, out, seq, threads, tangent="own", footprint="none",
             distribution="surface", reforecasts=2, pose_error=None, estimate_pose=False):
    """Force and interior-node errors of the estimation on mesh-remeshed, per frame."""
    work = os.path.join(out, "register", seq.replace("/", "-"))
    inputs = os.path.join(work, "inputs")
    os.makedirs(inputs, exist_ok=True)
    V, T = read_msh_nodes_and_tets(os.path.join(data, "mesh-default", "liver.msh"))
    interior = np.setdiff1d(np.arange(len(V)), boundary_nodes(T))
    truth = np.load(os.path.join(data, "sequences", seq, "positions-default.npy"))
    with open(os.path.join(inputs, "interior-points.csv"), "w") as f:
        f.write("x,y,z\n")
        for p in V[interior]:
            f.write(f"{p[0]!r},{p[1]!r},{p[2]!r}\n")
    with open(os.path.join(inputs, "interior-truth.csv"), "w") as f:
        f.write("time,marker,x,y,z\n")
        for k in range(-1, truth.shape[0]):
            P = V[interior] if k < 0 else truth[k][interior]
            t = (k + 1) * DT
            for i, p in enumerate(P):
                f.write(f"{t!r},{i},{p[0]!r},{p[1]!r},{p[2]!r}\n")
    clouds = (moved_clouds(data, seq, pose_error, os.path.join(inputs, "clouds")) if pose_error
              else os.path.join(data, "sequences", seq, "pointclouds"))
    scene = os.path.join(work, "register.yaml")
    with open(scene, "w") as f:
        f.write(fill("register.yaml", data=data, sequence=seq, inputs=inputs, threads=threads,
                     material=material_of(seq), tangent_settings=TANGENT_SETTINGS[tangent],
                     distribution=distribution, reforecasts=reforecasts, clouds=clouds,
                     footprint=FOOTPRINT_PARAMETERS[footprint],
                     pose=POSE_PARAMETERS if estimate_pose else ""))
    run_dir = os.path.join(work, "run")
    run([bcassim, "assimilate", scene, "--out", run_dir, "-q", "--no-plots"],
        os.path.join(work, "assimilate.log"))

    true_forces = np.load(os.path.join(data, "sequences", seq, "true-forces.npy"))
    estimate = {}
    for r in read_csv(os.path.join(run_dir, "estimates.csv")):
        estimate.setdefault(int(r["step"]), {})[r["parameter"]] = float(r["mean"])
    force = np.array([[estimate[k + 1][c] for c in ("Fx", "Fy", "Fz")]
                      for k in range(true_forces.shape[0])])
    force_error = 100 * np.linalg.norm(force - true_forces, axis=1) / np.linalg.norm(
        true_forces, axis=1)
    # Once the estimate has left the zero prior (frame 10 on): how much of that error is the
    # force's size and how much its direction.
    late, late_true = force[9:], true_forces[9:]
    magnitude = np.linalg.norm(late, axis=1) / np.linalg.norm(late_true, axis=1) - 1
    cosine = (late * late_true).sum(axis=1) / (np.linalg.norm(late, axis=1) *
                                               np.linalg.norm(late_true, axis=1))
    direction = np.degrees(np.arccos(np.clip(cosine, -1, 1)))
    errors = read_csv(os.path.join(run_dir, "errors.csv"))
    by_step = {int(r["step"]): r for r in errors}
    steps = range(1, true_forces.shape[0] + 1)
    est_mean = np.array([float(by_step[k]["estimated_mean_mm"]) for k in steps])
    est_max = np.array([float(by_step[k]["estimated_max_mm"]) for k in steps])
    ini_mean = np.array([float(by_step[k]["initial_mean_mm"]) for k in steps])
    ini_max = np.array([float(by_step[k]["initial_max_mm"]) for k in steps])
    timing = read_csv(os.path.join(run_dir, "timing.csv"))
    ms = np.array([float(r["total_ms"]) for r in timing])
    used = np.array([int(r["cloud_points_used"]) for r in read_csv(os.path.join(run_dir,
                                                                                "filter.csv"))])
    return {
        "sequence": seq, "frames": len(steps), "interior_nodes": len(interior),
        "mean_mm": est_mean.mean(), "max_mm": est_max.max(),
        "rest_mean_mm": ini_mean.mean(), "rest_max_mm": ini_max.max(),
        "mean_pct_of_rest": 100 * est_mean.mean() / ini_mean.mean(),
        "force_mean_pct": force_error.mean(), "force_max_pct": force_error.max(),
        "force_mean_pct_after_first": force_error[1:].mean(),
        "force_magnitude_pct_from_frame_10": 100 * magnitude.mean(),
        "force_direction_deg_from_frame_10": direction.mean(),
        "median_ms": float(np.median(ms)), "mean_ms": ms.mean(),
        # The budget is 50 ms a frame: the first (a cold start from the prior) apart.
        "first_frame_ms": float(ms[0]), "slowest_after_first_ms": float(ms[1:].max(initial=0)),
        "frames_over_50ms": int((ms > 50).sum()),
        "cloud_points_used_min": int(used.min()),
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("build")
    parser.add_argument("out")
    parser.add_argument("--data", default=os.path.join(HERE, "..", "..", "..", "shared", "data",
                                                       "mestdagh-liver"))
    parser.add_argument("--only", nargs="+", metavar="LAW/NAME",
                        help="these sequences (default: all of the data folder's)")
    parser.add_argument("--skip-verify", action="store_true")
    parser.add_argument("--skip-register", action="store_true")
    parser.add_argument("--floor", action="store_true",
                        help="also solve mesh-remeshed under the true forces: the interior "
                             "error the estimation mesh leaves when the force is known")
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--tangent", choices=sorted(TANGENT_SETTINGS), default="own",
                        help="registration: own (Newton for every sigma point) or mean "
                             "(sigma points linearised about the analysed mean, the mean by "
                             "chord iterations: 25-70x faster, see docs/results.md)")
    parser.add_argument("--footprint", nargs="?", const="full", default="none",
                        choices=sorted(FOOTPRINT_PARAMETERS),
                        help="registration: estimate how the force is shared over the zone too, "
                             "not only its three components: full (tilt_u, tilt_v, "
                             "concentration; the default of a bare --footprint) or tilt (the "
                             "tilts only: the force's centre moves, its spread stays)")
    parser.add_argument("--distribution", choices=["surface", "nodes"], default="surface",
                        help="registration: how the estimated force is shared over the zone: "
                             "surface (a uniform traction on its faces, the same load on any "
                             "mesh) or nodes (split evenly over its vertices)")
    parser.add_argument("--reforecasts", type=int, default=2,
                        help="registration: times a frame whose analysis moved the force by more "
                             "than one forecast standard deviation is forecast and analysed again "
                             "about that estimate (0: never; default 2)")
    parser.add_argument("--pose-error", nargs=2, type=float, metavar=("DEG", "MM"),
                        help="registration: every cloud moved by one rigid motion of DEG degrees "
                             "and MM millimetres first (a camera registered that far off)")
    parser.add_argument("--estimate-pose", action="store_true",
                        help="registration: estimate the observations' pose with the force (six "
                             "pose parameters)")
    a = parser.parse_args()
    if not 0 <= a.reforecasts <= 20:
        parser.error(f"--reforecasts: expected 0 to 20, got {a.reforecasts}")
    bcassim = os.path.abspath(os.path.join(a.build, "bcassim"))
    data = os.path.abspath(a.data)
    out = os.path.abspath(a.out)
    if a.only is None:
        a.only = sequences_in(data)
    check_sequences(data, a.only)
    os.makedirs(out, exist_ok=True)
    md = []
    if not a.skip_verify:
        md += ["| sequence | material | frames | max relative error | mean relative error |",
               "|---|---|---|---|---|"]
        with open(os.path.join(out, "verify.csv"), "w") as f:
            f.write("sequence,frames,max_relative_error,mean_relative_error\n")
            for seq in a.only:
                try:
                    e = verify(bcassim, data, out, seq)
                except RunFailed as failure:
                    f.write(f"{seq},0,,\n")
                    md.append(f"| {seq} | {seq.split('/')[0]} | failed | {failure} | |")
                    print(f"verify {seq}: failed, {failure}", flush=True)
                    continue
                f.write(f"{seq},{len(e)},{e.max():.3e},{e.mean():.3e}\n")
                md.append(f"| {seq} | {seq.split('/')[0]} | {len(e)} | {e.max():.1e} | "
                          f"{e.mean():.1e} |")
                print(f"verify {seq}: max {e.max():.2e}, mean {e.mean():.2e}", flush=True)
        md.append("")
    if a.floor:
        md += ["| sequence | interior error under the true force, mean / max (mm) | "
               "mean, % of rest | displacement factor that fits the truth, median (min-max) | "
               "linear law: interior error under that multiple of the true force (mm) |",
               "|---|---|---|---|---|"]
        with open(os.path.join(out, "floor.csv"), "w") as f:
            f.write("sequence,mean_mm,max_mm,mean_pct_of_rest,factor_median,factor_min,"
                    "factor_max,best_multiple_mean_mm\n")
            for seq in a.only:
                try:
                    r = floor(bcassim, data, out, seq)
                    best = r["best_multiple_mean_mm"]
                except RunFailed as failure:
                    md.append(f"| {seq} | failed: {failure} | | | |")
                    print(f"floor {seq}: failed, {failure}", flush=True)
                    continue
                f.write(f"{seq},{r['mean_mm']:.4g},{r['max_mm']:.4g},"
                        f"{r['mean_pct_of_rest']:.4g},{r['factor_median']:.4g},"
                        f"{r['factor_min']:.4g},{r['factor_max']:.4g},"
                        f"{'' if best is None else f'{best:.4g}'}\n")
                md.append(f"| {seq} | {r['mean_mm']:.2f} / {r['max_mm']:.2f} | "
                          f"{r['mean_pct_of_rest']:.1f} | {r['factor_median']:.3f} "
                          f"({r['factor_min']:.3f}-{r['factor_max']:.3f}) | "
                          f"{'-' if best is None else f'{best:.2f}'} |")
                print(f"floor {seq}: interior {r['mean_mm']:.2f}/{r['max_mm']:.2f} mm "
                      f"({r['mean_pct_of_rest']:.1f} % of rest), factor "
                      f"{r['factor_median']:.3f}", flush=True)
        md.append("")
    if not a.skip_register:
        results, failed = [], []
        for seq in a.only:
            try:
                results.append(register(bcassim, data, out, seq, a.threads, a.tangent,
                                        a.footprint, a.distribution, a.reforecasts, a.pose_error,
                                        a.estimate_pose))
            except RunFailed as failure:
                failed.append((seq, str(failure)))
                print(f"register {seq}: failed, {failure}", flush=True)
        keys = list(results[0].keys()) if results else []
        with open(os.path.join(out, "register.csv"), "w") as f:
            f.write(",".join(keys) + "\n")
            for r in results:
                f.write(",".join(f"{r[k]:.4g}" if isinstance(r[k], float) else str(r[k])
                                 for k in keys) + "\n")
        md += ["| sequence | interior error mean / max (mm) | rest shape mean / max (mm) | "
               "mean, % of rest | force error mean / max (%) | force from frame 10: magnitude, "
               "direction | ms per frame: median, first, slowest after the first | frames over "
               "50 ms |",
               "|---|---|---|---|---|---|---|---|"]
        for r in results:
            md.append(f"| {r['sequence']} | {r['mean_mm']:.2f} / {r['max_mm']:.2f} | "
                      f"{r['rest_mean_mm']:.2f} / {r['rest_max_mm']:.2f} | "
                      f"{r['mean_pct_of_rest']:.1f} | {r['force_mean_pct']:.1f} / "
                      f"{r['force_max_pct']:.1f} | "
                      f"{r['force_magnitude_pct_from_frame_10']:+.1f} %, "
                      f"{r['force_direction_deg_from_frame_10']:.1f}° | {r['median_ms']:.0f}, "
                      f"{r['first_frame_ms']:.0f}, {r['slowest_after_first_ms']:.0f} | "
                      f"{r['frames_over_50ms']} of {r['frames']} |")
            print(f"register {r['sequence']}: interior {r['mean_mm']:.2f}/{r['max_mm']:.2f} mm "
                  f"(rest {r['rest_mean_mm']:.2f}/{r['rest_max_mm']:.2f}), force "
                  f"{r['force_mean_pct']:.1f}/{r['force_max_pct']:.1f} %, "
                  f"{r['median_ms']:.0f} ms/frame (first {r['first_frame_ms']:.0f}, then at "
                  f"most {r['slowest_after_first_ms']:.0f})", flush=True)
        for seq, failure in failed:
            md.append(f"| {seq} | failed: {failure} | | | | | | |")
    with open(os.path.join(out, "summary.md"), "w") as f:
        f.write("\n".join(md) + "\n")


if __name__ == "__main__":
    main()
