"""examples/mestdagh-liver/best_fit.py, the independent check of the registration's force error:
its P1 stiffness passes the patch test, its closest points agree with brute force, and its
point-cloud fit recovers a known force."""
import os
import sys

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "examples", "mestdagh-liver"))
import best_fit  # noqa: E402


def cube_mesh(n, size=0.1):
    """An n x n x n grid of cubes of side size / n, each cut into 6 tets (Kuhn)."""
    g = np.linspace(0, size, n + 1)
    X = np.array([[x, y, z] for z in g for y in g for x in g])
    idx = lambda i, j, k: i + (n + 1) * (j + (n + 1) * k)  # noqa: E731
    T = []
    paths = [(0, 1, 2), (0, 2, 1), (1, 0, 2), (1, 2, 0), (2, 0, 1), (2, 1, 0)]
    for k in range(n):
        for j in range(n):
            for i in range(n):
                for path in paths:
                    corner = [i, j, k]
                    tet = [idx(*corner)]
                    for axis in path:
                        corner[axis] += 1
                        tet.append(idx(*corner))
                    T.append(tet)
    return X, np.array(T)


def test_stiffness_passes_the_patch_test_and_the_strain_energy():
    X, T = cube_mesh(3)
    K = best_fit.stiffness(X, T)
    # A rigid motion (a translation and a small rotation's linear part) costs no force.
    rigid = np.tile([1e-3, -2e-3, 5e-4], len(X)) + np.cross([0.0, 0.0, 1.0], X).ravel()
    assert np.abs(K @ rigid).max() < 1e-9 * np.abs(K).max() * np.abs(rigid).max()
    # A uniform strain: no force on the interior nodes, and the energy of the continuum.
    strain = np.array([[1e-3, 2e-4, 0.0], [2e-4, -5e-4, 3e-4], [0.0, 3e-4, 8e-4]])
    u = (X @ strain.T).ravel()
    f = (K @ u).reshape(-1, 3)
    inner = np.all((X > 1e-9) & (X < 0.1 - 1e-9), axis=1)
    assert inner.sum() == 8
    assert np.abs(f[inner]).max() < 1e-9 * np.abs(f).max()
    lam = best_fit.YOUNG * best_fit.POISSON / ((1 + best_fit.POISSON) * (1 - 2 * best_fit.POISSON))
    mu = best_fit.YOUNG / (2 * (1 + best_fit.POISSON))
    density = 0.5 * lam * np.trace(strain) ** 2 + mu * (strain * strain).sum()
    assert 0.5 * u @ K @ u == pytest.approx(density * 0.1 ** 3, rel=1e-10)


def test_closest_points_on_triangles_agree_with_brute_force():
    rng = np.random.default_rng(7)
    tris = rng.normal(size=(30, 3, 3))
    points = 2 * rng.normal(size=(200, 3))
    candidates = np.tile(np.arange(len(tris)), (len(points), 1))
    tri, bary, distance = best_fit.closest_on_triangles(tris, candidates, points)
    # Brute force: the closest of a fine barycentric grid on every triangle.
    m = 60
    grid = np.array([[1 - a / m - b / m, a / m, b / m]
                     for a in range(m + 1) for b in range(m + 1 - a)])
    samples = np.einsum("sk,tkd->tsd", grid, tris)
    brute = np.linalg.norm(samples[None] - points[:, None, None], axis=-1).min(axis=(1, 2))
    assert np.all(distance <= brute + 1e-12)
    assert np.all(distance >= brute - 0.02 * np.linalg.norm(tris[:, 1] - tris[:, 0], axis=1).max())
    assert np.all(bary >= -1e-12) and np.allclose(bary.sum(axis=1), 1)
    foot = np.einsum("pk,pkd->pd", bary, tris[tri])
    assert np.allclose(np.linalg.norm(foot - points, axis=1), distance, rtol=0, atol=1e-12)


def test_the_cloud_fit_recovers_a_known_force():
    import scipy.sparse.linalg as spl

    X, T = cube_mesh(4)
    K = best_fit.stiffness(X, T)
    fixed = np.flatnonzero(X[:, 2] < 1e-9)
    free = np.ones(3 * len(X), dtype=bool)
    free[(3 * fixed[:, None] + np.arange(3)).ravel()] = False
    solver = spl.splu(K[free][:, free].tocsc())
    top = np.flatnonzero(X[:, 2] > 0.1 - 1e-9)
    shares = np.zeros(len(X))
    shares[top] = 1.0 / len(top)
    basis = np.zeros((3, len(X), 3))
    for c in range(3):
        f = np.zeros((len(X), 3))
        f[:, c] = shares
        u = np.zeros(3 * len(X))
        u[free] = solver.solve(f.ravel()[free])
        basis[c] = u.reshape(-1, 3)
    faces = best_fit.rm.boundary_faces(T)
    # The camera sees the top and two sides (x = 0.1 m, y = 0.1 m): each force component moves one
    # of them along its normal.
    on = lambda axis: (X[faces][:, :, axis] > 0.1 - 1e-9).all(axis=1)  # noqa: E731
    sides = faces[on(0) | on(1) | on(2)]
    true = np.array([30.0, -20.0, -40.0])  # N: a few mm on a 20 kPa, 10 cm cube
    moved = X + np.einsum("c,cnd->nd", true, basis)
    rng = np.random.default_rng(3)
    pick = rng.integers(len(sides), size=400)
    w = rng.dirichlet(np.ones(3), size=400)
    cloud = np.einsum("pk,pkd->pd", w, moved[sides[pick]])
    force = best_fit.fit_cloud(X, sides, basis, cloud, np.zeros(3))
    assert np.linalg.norm(force - true) < 1e-4 * np.linalg.norm(true)
