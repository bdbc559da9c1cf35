"""Tracking, atlas and calibration from Python: marker identities through shuffles and a dropout,
rigid registration of points to a surface, surface distances, LDDMM registration, a small atlas,
a hyperelastic law fitted to a uniaxial curve, springs fitted to a stretched membrane. SI units."""
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
    assert result.converged and result.last_move <= 1e-10
    untrimmed = bcassim.tracking.register_points_to_surface(points[::40], surface, median_factor=0)
    np.testing.assert_allclose(untrimmed.transform.rotation, R, atol=1e-6)
    assert untrimmed.overlap == 1.0
    with pytest.raises(bcassim.InputError):
        bcassim.tracking.register_points_to_surface(points[:3], surface)


def test_a_registration_is_read_back_as_a_scene_would(tmp_path):
    """What `bcassim register` writes (4 x 4, points -> model) reads back as the same motion."""
    R, t = rotation([0, 1, 1], 25), np.array([0.1, 0.02, -0.3])
    M = np.eye(4)
    M[:3, :3], M[:3, 3] = R, t
    np.savetxt(tmp_path / "transform.csv", M, delimiter=",", fmt="%.17g")
    read = bcassim.io.read_rigid_transform(str(tmp_path / "transform.csv"))
    np.testing.assert_allclose(read.rotation, R, atol=1e-15)
    np.testing.assert_allclose(read.translation, t, atol=1e-15)
    np.savetxt(tmp_path / "mm.txt", np.diag([1e3, 1e3, 1e3, 1.0]))
    with pytest.raises(bcassim.InputError, match="scales lengths by 1000"):
        bcassim.io.read_rigid_transform(str(tmp_path / "mm.txt"))


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


def test_a_small_atlas_is_built_and_transferred(tmp_path):
    sphere = make_icosphere_surface(0.05, 2)
    V = np.asarray(sphere.V)
    subjects = []
    for i, scale in enumerate([(1.0, 1.0, 1.0), (1.1, 0.95, 1.0), (0.95, 1.05, 1.05)]):
        moved = V * scale
        # An attachment curve over the top of each shape: the vertices near the plane x = 0.
        top = moved[(np.abs(moved[:, 0]) < 0.012) & (moved[:, 2] > 0)]
        curve = top[np.argsort(top[:, 1])]
        subjects.append(bcassim.atlas.AtlasSubject(f"s{i}", TriMesh(moved, sphere.F), curve))
    lines = []
    atlas = bcassim.atlas.build_ligament_atlas(subjects, sigma_v=0.03, sigma_w=0.01,
                                               frechet_mean=False, max_iterations=10,
                                               log=lines.append)
    assert atlas.subjects == ["s0", "s1", "s2"] and lines
    curve = atlas.curve
    assert len(curve.mean) >= 3 and np.all(curve.sigma >= 0)
    bcassim.atlas.write_ligament_atlas(str(tmp_path / "atlas"), atlas)
    again = bcassim.atlas.read_ligament_atlas(str(tmp_path / "atlas"))
    np.testing.assert_allclose(again.curve.mean, curve.mean, atol=1e-9)
    patient = TriMesh(V * [1.05, 1.0, 0.97], sphere.F)
    transfer = bcassim.atlas.transfer_atlas(again, patient, sigma_v=0.03, max_iterations=10,
                                            max_rotation_degrees=90)
    assert transfer.rigid_rotation_degrees < 10 and not transfer.implausible_pose_refused
    # The mean curve lands on (near) the patient's surface, within the patient's extent.
    r = np.linalg.norm(transfer.curve.mean / [0.0525, 0.05, 0.0485], axis=1)
    assert np.all(np.abs(r - 1) < 0.1)


def test_a_hyperelastic_law_is_fitted_to_a_curve(tmp_path):
    stretch = np.linspace(1.01, 1.45, 20)
    stress = bcassim.calibration.nominal_stress("ogden", [40e3, 6.0], stretch)
    curve = bcassim.calibration.UniaxialCurve(stretch, stress)
    fit = bcassim.calibration.fit_uniaxial(curve, "ogden")
    assert fit.names == ["mu", "alpha"]
    np.testing.assert_allclose(fit.parameters, [40e3, 6.0], rtol=1e-6)
    bounded = bcassim.calibration.fit_uniaxial(curve, "ogden", bounds={"alpha": (1.0, 4.0)})
    assert bounded.parameters[1] <= 4.0
    path = tmp_path / "mpa.csv"
    path.write_text("strain,nominal_stress_MPa\n0,0\n0.1,0.01\n")
    with pytest.raises(bcassim.InputError, match="stress in MPa; expected Pa"):
        bcassim.calibration.read_uniaxial_curve(str(path))


def test_springs_fitted_to_a_small_membrane_reproduce_its_reaction():
    r = bcassim.calibration.calibrate_springs(
        403e3, 1e-3, 0.04, 0.1, membrane_cells=(8, 20, 1), lattice_cells=(4, 10))
    membrane, lattice = r.frames[:, 2], r.frames[:, 3]
    assert r.frames.shape == (9, 4)
    np.testing.assert_allclose(lattice, membrane, rtol=0.05)
    assert r.attachment_max_error < 1e-3
    assert r.per_metre[1, 0] < 0 < r.per_metre[2, 0]  # Neo-Hookean softens: K_beta < 0
    with pytest.raises(bcassim.InputError, match="must divide"):
        bcassim.calibration.calibrate_springs(403e3, 1e-3, 0.04, 0.1, lattice_cells=(3, 10))

