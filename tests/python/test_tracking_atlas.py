"""Tracking and atlas from Python: marker identities through shuffles and a dropout, rigid
registration of points to a surface, surface distances and LDDMM registration. Metres."""
import numpy as np
import pytest

import bcassim
from bcassim.atlas import register_surface, surface_distance
from bcassim.mesh import TriMesh, make_icosphere_surface
from bcassim.tracking import DetectionFrame, MarkerTracker, TrackerOptions, track_markers


def rotation(axis, degrees):
    axis = np.asarray(axis, float) / np.linalg.norm(axis)
    a = np.radians(degrees)
    K = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(a) * K + (1 - np.cos(a)) * K @ K


def test_marker_identities_survive_shuffles_and_a_dropout():
    rng = np.random.default_rng(2)
    start = rng.uniform(-0.05, 0.05, (6, 3))
    velocity = rng.uniform(-0.01, 0.01, (6, 3))
    frames, truth = [], []
    for k in range(30):
        t = k / 30
        order = rng.permutation(6)
        if k == 12:
            order = order[order != 4]  # marker 4 unseen for one frame
        frames.append(DetectionFrame(t, start[order] + velocity[order] * t))
        truth.append(order)
    ids, tracks, report = track_markers(frames, TrackerOptions(gate=0.005))
    assert len(tracks) == 6 and report == []
    identity = {}
    for k in range(3, 30):  # confirmed after three frames
        for row, marker in enumerate(truth[k]):
            identity.setdefault(marker, ids[k][row])
            assert ids[k][row] == identity[marker]
    online = MarkerTracker(TrackerOptions(gate=0.005))
    labels, lines = online.add_frame(DetectionFrame(0.0, np.full((1, 3), np.nan)))
    assert labels == [-1] and "detection 0: non-finite coordinate" in lines[0]


def test_points_are_registered_rigidly_onto_a_surface():
    sphere = make_icosphere_surface(0.05, 3)  # an ellipsoid: no flat face to slide along
    surface = TriMesh(np.asarray(sphere.V) * [1.5, 1.0, 0.6], sphere.F)
    R, t = rotation([1, 2, 3], 12), np.array([0.01, -0.004, 0.006])
    points = (np.asarray(surface.V) - t) @ R  # surface = R points + t
    result = bcassim.tracking.register_points_to_surface(points, surface)
    np.testing.assert_allclose(result.transform.rotation, R, atol=1e-6)
    np.testing.assert_allclose(result.transform.translation, t, atol=1e-6)
    assert result.rms < 1e-6 and result.overlap == 1.0
    with pytest.raises(bcassim.InputError):
        bcassim.tracking.register_points_to_surface(points[:3], surface)


def test_surface_distance_and_registration():
    sphere = make_icosphere_surface(0.05, 2)
    moved = TriMesh(np.asarray(sphere.V) * [1.2, 1.0, 0.9] + [0.005, 0, 0], sphere.F)
    assert surface_distance(sphere, sphere, 0.01) == pytest.approx(0, abs=1e-12)
    d0 = surface_distance(sphere, moved, 0.01)
    assert d0 > 0
    r = register_surface(sphere, moved, sigma_v=0.03, sigma_w=0.01, max_iterations=50)
    assert r.deformed_vertices.shape == (len(sphere.V), 3)
    assert r.initial_data == pytest.approx(d0, rel=1e-9)
    assert r.data < 0.1 * r.initial_data
