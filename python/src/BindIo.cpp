// bcassim.io: the readers and writers of the library (the same validation and one-line errors as
// the command line): tet meshes (.vtk, .vtu, .msh, .mesh), surfaces (.stl, .obj, .ply, .vtk, .vtp),
// point sets (.csv, .txt, .npy, .ply). Metres unless a file says otherwise.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "Bindings.h"
#include "bcassim/io/FieldSet.h"
#include "bcassim/io/MeshReader.h"
#include "bcassim/io/MeshWriter.h"
#include "bcassim/io/PointReader.h"
#include "bcassim/io/RigidTransformReader.h"
#include "bcassim/io/SurfaceReader.h"

namespace py = pybind11;
using namespace pybind11::literals;

namespace bcassim::python {

namespace {
// Point fields from a dict name -> array: #V values are scalars, #V x 3 arrays vectors.
FieldSet pointFieldsFrom(const py::dict& fields) {
  FieldSet set;
  for (auto [key, value] : fields) {
    const auto name = py::cast<std::string>(key);
    const auto array = py::array_t<double, py::array::forcecast>::ensure(value);
    if (!array) throw py::value_error("field '" + name + "': expected an array of numbers");
    if (array.ndim() == 2 && array.shape(1) == 3)
      set.pointVectors.emplace_back(name, py::cast<Eigen::MatrixX3d>(array));
    else
      set.pointScalars.emplace_back(name, py::cast<Eigen::VectorXd>(array.attr("ravel")()));
  }
  return set;
}
}  // namespace

void bindIo(py::module_& m) {
  m.def(
      "read_tet_mesh", &readTetMesh, "path"_a, "region_field"_a = "",
      py::call_guard<py::gil_scoped_release>(),
      "Reads and validates a tet mesh (.vtk, .vtu, .msh, .mesh; metres); InputError names the file "
      "and "
      "line");
  m.def(
      "write_tet_mesh",
      [](const std::string& path, const TetMesh& mesh, std::optional<Eigen::MatrixX3d> positions,
         const py::dict& fields) {
        Eigen::VectorXd x;
        if (positions) {
          if (positions->rows() != mesh.numNodes())
            throw py::value_error("positions: expected " + std::to_string(mesh.numNodes()) +
                                  " rows, one per node");
          const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> rows = *positions;
          x = Eigen::Map<const Eigen::VectorXd>(rows.data(), rows.size());
        }
        writeTetMesh(path, mesh, x, pointFieldsFrom(fields));
      },
      "path"_a, "mesh"_a, "positions"_a = py::none(), "fields"_a = py::dict(),
      "Writes .vtu or .vtk for ParaView: at `positions` (#V x 3, m; None: rest) with point fields "
      "(dict name -> #V or #V x 3 array, name with its SI unit)");
  m.def("read_surface", &readSurface, "path"_a, py::call_guard<py::gil_scoped_release>(),
        "Reads a triangle surface (.stl, .obj, .ply, .vtk, .vtp), coordinates as stored");
  m.def("write_surface", &writeSurface, "path"_a, "mesh"_a,
        py::call_guard<py::gil_scoped_release>(), "Writes .stl, .obj, .vtk or .vtp");
  m.def("read_points", &readPoints, "path"_a, py::call_guard<py::gil_scoped_release>(),
        "Reads #P x 3 points from .csv (x,y,z columns), .txt (x y z per line), .npy or .ply (its "
        "vertices)");
  m.def("read_rigid_transform", &readRigidTransform, "path"_a,
        py::call_guard<py::gil_scoped_release>(),
        "Reads a 4 x 4 rigid transform (rotation, translation in m; last row 0 0 0 1) from .csv, "
        ".txt or .npy, as `bcassim register` writes it: a RigidTransform (the nearest rotation of "
        "a matrix written to a few digits); a scaling, shear or reflection raises InputError");
}

}  // namespace bcassim::python
