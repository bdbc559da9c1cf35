"""bcassim: boundary-condition estimation of organ models by Kalman filtering over FEM.

Submodules mirror the C++ tree: bcassim.mesh, .io, .mechanics, .assimilation, .scene, .atlas,
.tracking, .calibration, .liver. Units are SI everywhere (m, Pa, N, s). Errors are
bcassim.InputError (a ValueError), bcassim.OutputError and bcassim.NumericalError (an
ArithmeticError), each with the same one-line message as the command line.
"""
import sys as _sys

from . import _bcassim
from ._bcassim import InputError, NumericalError, OutputError, __version__
from ._bcassim import assimilation, atlas, calibration, io, liver, mechanics, mesh, scene, tracking
from . import _tables

# `import bcassim.mesh` and `from bcassim.mesh import TetMesh` work like for a package.
for _name in ("mesh", "io", "mechanics", "assimilation", "scene", "atlas", "tracking", "liver",
              "calibration"):
    _sys.modules[__name__ + "." + _name] = getattr(_bcassim, _name)

io.read_hidden_points = _tables.read_hidden_points
io.read_estimates = _tables.read_estimates
io.read_tracks = _tables.read_tracks

__all__ = ["InputError", "NumericalError", "OutputError", "assimilation", "atlas", "calibration",
           "io", "liver",
           "mechanics", "mesh", "scene", "tracking", "__version__"]
