"""examples/mestdagh-liver/run_mestdagh.py runs the sequences its data folder holds: found, not
taken from a fixed list, and a sequence that is missing or of an unknown law stops the run with
one line naming it."""
import os
import sys

import numpy as np
import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "examples", "mestdagh-liver"))
import run_mestdagh  # noqa: E402


def make_data(root, sequences, without_forces=()):
    for seq in list(sequences) + list(without_forces):
        folder = root / "sequences" / seq
        folder.mkdir(parents=True)
        if seq in sequences:
            np.save(folder / "true-forces.npy", np.zeros((2, 3)))
    return str(root)


def test_the_sequences_are_those_of_the_data_folder_sorted(tmp_path):
    data = make_data(tmp_path, ["neohookean/s4", "linear/s2", "linear/s10", "odd/a"],
                     without_forces=["linear/s3"])
    assert run_mestdagh.sequences_in(data) == ["linear/s10", "linear/s2", "neohookean/s4",
                                                "odd/a"]


def exit_line(data, sequences):
    with pytest.raises(SystemExit) as stop:
        run_mestdagh.check_sequences(data, sequences)
    return str(stop.value)


def test_a_missing_or_unknown_sequence_stops_with_one_line(tmp_path):
    data = make_data(tmp_path, ["linear/s1", "odd/a"], without_forces=["linear/s3"])
    run_mestdagh.check_sequences(data, ["linear/s1"])  # passes
    folder = os.path.join(data, "sequences")
    assert exit_line(data, ["linear/s1", "linear/s3"]) == (
        f"{folder}/linear/s3: no true-forces.npy (expected a sequence LAW/NAME of the data "
        "folder)")
    assert exit_line(data, ["odd/a"]) == (
        f"{folder}/odd/a: law 'odd' unknown (expected linear or neohookean, the data README's "
        "families)")
    empty = tmp_path / "empty"
    empty.mkdir()
    assert exit_line(str(empty), []) == (
        f"{empty}: no sequences/LAW/NAME/true-forces.npy (expected the mestdagh-liver data "
        "folder)")
