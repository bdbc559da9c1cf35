"""NumPy arrays in and out of bcassim: views without copies where the layout allows, their
ownership, shapes accepted and refused, sparse matrices as scipy.sparse."""
import gc

import numpy as np
import pytest
import scipy.sparse

import bcassim
from bcassim.mechanics import Material, Model
from bcassim.mesh import BoxRegion, SphereRegion, TetMesh, make_box_mesh, select_nodes


def test_mesh_arrays_are_read_only_views_that_keep_the_mesh_alive():
    mesh = make_box_mesh([0.1, 0.02, 0.03], 4, 2, 2)
    V = mesh.V
    assert V.shape == (mesh.num_nodes, 3) and V.dtype == np.float64
    assert not V.flags.writeable and V.flags.f_contiguous
    assert np.shares_memory(V, mesh.V)  # both views of the C++ storage: no copy
    expected = V.copy()
    del mesh
    gc.collect()
    np.testing.assert_array_equal(V, expected)  # the view keeps its mesh alive
    assert V.max(axis=0) == pytest.approx([0.1, 0.02, 0.03])


def test_assigning_an_array_replaces_the_member():
    mesh = make_box_mesh([1, 1, 1], 1, 1, 1)
    moved = np.ascontiguousarray(mesh.V) * 2.0  # C order: converted on assignment
    mesh.V = moved
    np.testing.assert_array_equal(mesh.V, moved)
    moved[0, 0] = 42.0
    assert mesh.V[0, 0] != 42.0  # the mesh owns its copy


def test_tet_mesh_round_trips_through_a_file(tmp_path):
    mesh = make_box_mesh([0.1, 0.02, 0.02], 3, 1, 1)
    path = str(tmp_path / "box.vtu")
    displaced = np.asarray(mesh.V) + [0.001, 0, 0]
    bcassim.io.write_tet_mesh(path, mesh, positions=displaced,
                              fields={"u_m": displaced - mesh.V, "id": np.arange(mesh.num_nodes)})
    back = bcassim.io.read_tet_mesh(path)
    np.testing.assert_array_equal(back.V, displaced)  # stored in binary: exact
    np.testing.assert_array_equal(back.T, mesh.T)


def test_bad_meshes_and_shapes_are_refused_with_one_line():
    mesh = make_box_mesh([1, 1, 1], 1, 1, 1)
    with pytest.raises(bcassim.InputError, match="TetMesh"):
        TetMesh(mesh.V, np.array([[0, 1, 2, 99]]))
    model = Model(mesh, [Material("stvk", 1e4, 0.3)])
    with pytest.raises(ValueError, match=r"x: expected 8 x 3 or 24 values \(m\)"):
        model.internal_forces(np.zeros((7, 3)))


def test_flat_and_matrix_positions_agree_and_forces_are_the_energy_gradient():
    mesh = make_box_mesh([0.1, 0.02, 0.02], 3, 1, 1)
    model = Model(mesh, [Material("neohookean", 5e3, 0.45)])
    rng = np.random.default_rng(1)
    x = np.asarray(model.rest_positions()) + 1e-3 * rng.standard_normal((mesh.num_nodes, 3))
    f, K = model.forces_and_stiffness(x)
    np.testing.assert_array_equal(f, model.internal_forces(x.ravel()))
    assert isinstance(K, scipy.sparse.csc_matrix) and K.shape == (3 * mesh.num_nodes,) * 2
    assert abs(K - K.T).max() <= 1e-9 * abs(K).max()
    # f = dW/dx and K = df/dx by central differences (second order: h^2 error).
    h = 1e-7
    d = rng.standard_normal(x.shape)
    dW = (model.stored_energy(x + h * d) - model.stored_energy(x - h * d)) / (2 * h)
    assert dW == pytest.approx(np.sum(f * d), rel=1e-6)
    df = (model.internal_forces(x + h * d) - model.internal_forces(x - h * d)) / (2 * h)
    np.testing.assert_allclose(df.ravel(), K @ d.ravel(), atol=1e-6 * abs(K @ d.ravel()).max())


def test_regions_select_nodes():
    mesh = make_box_mesh([1, 1, 1], 2, 2, 2)
    ids = select_nodes(mesh, BoxRegion([0, 0, 0], [0, 1, 1]))
    assert ids.dtype.kind == "i" and len(ids) == 9
    assert np.all(np.asarray(mesh.V)[ids, 0] == 0)
    assert list(select_nodes(mesh, SphereRegion([0, 0, 0], 1e-9))) == [0]
    with pytest.raises(bcassim.InputError):
        select_nodes(mesh, SphereRegion([0, 0, 0], -1))
