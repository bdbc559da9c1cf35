"""Shared pieces of the Python suites: the small pulled cylinder of the C++ tests, the CLI."""
import os
import subprocess

import pytest


def cylinder_scene(nodes, material, steps, extra=""):
    """The thesis cylinder made small (tests/support/PulledCylinderScene.h): both ends fixed, a
    periodic pull at mid-length, 10 markers on the front, every node a validation point."""
    return (
        f"mesh: {{generator: cylinder, radius: 0.015, length: 0.18, target_nodes: {nodes}}}\n"
        f"{material}\n"
        "damping: {rayleigh_mass: 0.1, rayleigh_stiffness: 0.01}\n"
        f"time: {{dt: 0.01, steps: {steps}}}\n"
        "output: {pvd: false}\n"
        "fixed:\n"
        "  - region: {half_space: {point: [0, 0, 0.0001], normal: [0, 0, -1]}}\n"
        "  - region: {half_space: {point: [0, 0, 0.1799], normal: [0, 0, 1]}}\n"
        "loads:\n"
        "  - region: {surface_patch: {box: {min: [-0.02, -0.02, 0.075], max: [0.02, 0.02, 0.105]},"
        " direction: [0, -1, 0], max_angle_deg: 60}}\n"
        "    total_force: [0, -0.15, 0]\n"
        "    profile: {kind: sine, period: 1.0}\n"
        "markers:\n"
        "  - region: {surface_patch: {box: {min: [-0.02, -0.02, 0.03], max: [0.02, 0.02, 0.15]},"
        " direction: [0, 1, 0], max_angle_deg: 60}}\n"
        "    count: 10\n"
        "validation_points: {nodes: all}\n" + extra)


@pytest.fixture
def bcassim_cli():
    """Runs the bcassim executable built beside the module; returns the CompletedProcess."""
    binary = os.environ.get("BCASSIM_BINARY")
    if not binary:
        pytest.fail("BCASSIM_BINARY is not set (ctest sets it to the built executable)")

    def run(*args, check=True):
        return subprocess.run([binary, *map(str, args)], capture_output=True, text=True,
                              check=check)

    return run
