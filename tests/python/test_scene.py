"""Scenes from Python: a small cyl-E-same driven from Python gives the same estimates as the
command line; stepping a scene gives simulate's tracks; changes to the model take effect; a bad
scene raises InputError with the file, line and key, the same line the command line prints."""
import numpy as np
import pytest

import bcassim
from conftest import cylinder_scene

STEPS = 60
TRUTH = cylinder_scene(200, "material: {model: stvk, young_modulus: 8000, poisson_ratio: 0.45}",
                       STEPS)
ESTIMATE = cylinder_scene(
    200, "material: {model: stvk, young_modulus: 4000, poisson_ratio: 0.45}", STEPS,
    "assimilation:\n"
    "  filter: roukf\n"
    "  threads: 2\n"
    "  parameters:\n"
    "    - {name: E, young_modulus: {region: 0}, mean: 4000, stddev: 2000, transform: log,"
    " truth: 8000}\n"
    "  observations: {tracks: truth/markers.csv, noise_stddev: 1.0e-4, sigma: 1.0e-4,"
    " until_step: 45}\n"
    "  validation: {tracks: truth/validation.csv}\n")


def test_python_driven_cyl_e_same_equals_the_command_line(tmp_path, bcassim_cli):
    (tmp_path / "truth.yaml").write_text(TRUTH)
    (tmp_path / "estimate.yaml").write_text(ESTIMATE)
    bcassim_cli("simulate", tmp_path / "truth.yaml", "--out", tmp_path / "truth")
    bcassim_cli("assimilate", tmp_path / "estimate.yaml", "--out", tmp_path / "cli")

    scene = bcassim.scene.load(str(tmp_path / "estimate.yaml"))
    assert [p.name for p in scene.parameters] == ["E"] and scene.parameters[0].truth == 8000
    seen = []
    result = bcassim.scene.assimilate(scene, str(tmp_path / "py"),
                                      progress=lambda p: seen.append((p.step, p.free_run)))
    assert [s for s, _ in seen] == list(range(1, STEPS + 1))
    assert [free for _, free in seen] == [s > 45 for s in range(1, STEPS + 1)]

    cli = bcassim.io.read_estimates(str(tmp_path / "cli" / "estimates.csv"))["E"]
    py = bcassim.io.read_estimates(str(tmp_path / "py" / "estimates.csv"))["E"]
    np.testing.assert_array_equal(py["step"], np.arange(STEPS + 1))
    np.testing.assert_allclose(py["mean"], cli["mean"], rtol=1e-12)
    np.testing.assert_allclose(py["stddev"], cli["stddev"], rtol=1e-12)
    (E,) = result.parameters
    assert E.mean == pytest.approx(py["mean"][-1], rel=1e-8)  # the CSV keeps 9 digits
    assert abs(E.mean - 8000) < abs(4000 - 8000) / 4  # the estimate moved most of the way
    assert result.estimated.all.mean_percent < result.initial.all.mean_percent


def test_stepping_a_scene_gives_the_simulate_tracks(tmp_path):
    scene = bcassim.scene.load_string(TRUTH, "truth.yaml", str(tmp_path))
    runs = bcassim.scene.simulate(scene, str(tmp_path / "sim"))
    assert runs[0]["steps"] == STEPS
    times, tracks = bcassim.io.read_tracks(str(tmp_path / "sim" / "markers.csv"))

    sim = bcassim.scene.Simulation(scene)
    markers = []
    sim.run(steps=20, callback=lambda s: markers.append(s.markers()))
    sim.run(callback=lambda s: markers.append(s.markers()))  # to the scene's end
    assert sim.step_index == STEPS and sim.time == pytest.approx(STEPS * scene.dt)
    np.testing.assert_allclose(np.array(markers), tracks[-STEPS:], rtol=0, atol=1e-12)
    assert sim.positions.shape == (sim.model.num_nodes, 3)


def test_changes_to_the_model_take_effect(tmp_path):
    stiff = bcassim.scene.load_string(TRUTH, "truth.yaml", str(tmp_path))
    soft = bcassim.scene.load_string(TRUTH, "truth.yaml", str(tmp_path))
    soft.set_young_modulus(0, 2000, law="stvk", nu=0.45)
    soft.set_load_force(0, 2 * stiff.load_force(0))
    np.testing.assert_allclose(soft.load_force(0), [0, -0.3, 0])
    peak = []
    for scene in (stiff, soft):
        sim = bcassim.scene.Simulation(scene)
        sim.run(steps=25)
        peak.append(np.abs(sim.positions - scene.model.rest_positions()).max())
    assert peak[1] > 4 * peak[0]  # 4x softer and twice the force: far larger motion


def test_a_bad_scene_raises_the_command_lines_one_line_error(tmp_path, bcassim_cli):
    bad = TRUTH.replace("time: {dt: 0.01,", "time: {dt: fast,")
    (tmp_path / "bad.yaml").write_text(bad)
    with pytest.raises(bcassim.InputError) as error:
        bcassim.scene.load(str(tmp_path / "bad.yaml"))
    message = str(error.value)
    assert message.startswith(str(tmp_path / "bad.yaml") + ":4: time.dt: expected")
    assert "\n" not in message
    cli = bcassim_cli("simulate", tmp_path / "bad.yaml", "--out", tmp_path / "o", check=False)
    assert cli.returncode != 0 and message in cli.stderr


def test_a_failing_step_is_a_numerical_error_naming_the_step(tmp_path):
    scene = bcassim.scene.load_string(TRUTH, "huge.yaml", str(tmp_path))
    scene.set_load_force(0, [0, -1e4, 0])  # 10 kN on a 3 cm cylinder: elements invert
    sim = bcassim.scene.Simulation(scene)
    with pytest.raises(bcassim.NumericalError, match=r"huge.yaml: step \d+ \(t = [0-9.e-]+ s\)"):
        sim.run(steps=STEPS)
