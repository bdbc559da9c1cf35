// The compiled part of `import bcassim`: one submodule per room of the C++ tree, as the library
// names them; bcassim/__init__.py makes each importable as bcassim.<room>.
#include "Bindings.h"

namespace {
struct Room {
  const char* name;
  const char* doc;
  void (*bind)(pybind11::module_&);
};
}  // namespace

PYBIND11_MODULE(_bcassim, m) {
  using namespace bcassim::python;
  m.doc() =
      "bcassim: boundary-condition estimation of organ models by Kalman filtering over FEM. "
      "SI units everywhere (m, Pa, N, s).";
  m.attr("__version__") = BCASSIM_VERSION;
  bindErrors(m);
  const Room rooms[] = {
      {"mesh", "Tetrahedral and surface meshes, generators, regions (m)", bindMesh},
      {"io", "Reading and writing meshes, surfaces and point sets (m)", bindIo},
      {"mechanics", "Forces and stiffness of a mechanical model (N, N/m, J)", bindMechanics},
      {"assimilation", "Kalman filters (UKF, ROUKF, ETKF) over any forecast model",
       bindAssimilation},
      {"scene", "YAML scenes: load, change, simulate, assimilate", bindScene},
      {"atlas", "Surface registration, distances, the ligament atlas", bindAtlas},
      {"tracking", "Marker identities over frames, rigid registration (m)", bindTracking},
      {"calibration", "Hyperelastic laws fitted to tissue curves", bindCalibration},
      {"liver", "The liver pipeline of thesis chapter 5", bindLiver},
  };
  for (const Room& room : rooms) {
    auto sub = m.def_submodule(room.name, room.doc);
    room.bind(sub);
  }
}
