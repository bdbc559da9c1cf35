// The compiled part of `import bcassim`: one submodule per room of the C++ tree, as the library
// names them; bcassim/__init__.py makes each importable as bcassim.<room>.
#include "Bindings.h"

PYBIND11_MODULE(_bcassim, m) {
  using namespace bcassim::python;
  m.doc() =
      "bcassim: boundary-condition estimation of organ models by Kalman filtering over FEM. "
      "SI units everywhere (m, Pa, N, s).";
  m.attr("__version__") = BCASSIM_VERSION;
  bindErrors(m);
  auto mesh = m.def_submodule("mesh", "Tetrahedral and surface meshes, generators, regions (m)");
  bindMesh(mesh);
  auto io = m.def_submodule("io", "Reading and writing meshes, surfaces and point sets (m)");
  bindIo(io);
  auto mechanics =
      m.def_submodule("mechanics", "Forces and stiffness of a mechanical model (N, N/m, J)");
  bindMechanics(mechanics);
  auto assimilation =
      m.def_submodule("assimilation", "Kalman filters (UKF, ROUKF, ETKF) over any forecast model");
  bindAssimilation(assimilation);
  auto scene = m.def_submodule("scene", "YAML scenes: load, change, simulate, assimilate");
  bindScene(scene);
  auto atlas = m.def_submodule("atlas", "Surface registration, distances, the ligament atlas");
  bindAtlas(atlas);
  auto tracking =
      m.def_submodule("tracking", "Marker identities over frames, rigid registration (m)");
  bindTracking(tracking);
  auto calibration = m.def_submodule("calibration", "Hyperelastic laws fitted to tissue curves");
  bindCalibration(calibration);
  auto liver = m.def_submodule("liver", "The liver pipeline of thesis chapter 5");
  bindLiver(liver);
}
