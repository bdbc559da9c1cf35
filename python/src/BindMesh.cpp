// bcassim.mesh: TetMesh, TriMesh, the mesh generators, regions and node/tet selection, rigid
// transforms. Arrays are NumPy views of the C++ storage where the layout allows (read-only);
// assigning an array replaces the member. Metres.
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "Bindings.h"
#include "bcassim/mesh/BoundarySurface.h"
#include "bcassim/mesh/MeshGenerators.h"
#include "bcassim/mesh/MeshValidation.h"
#include "bcassim/mesh/PointSetAlignment.h"
#include "bcassim/mesh/Region.h"
#include "bcassim/mesh/RigidTransform.h"
#include "bcassim/mesh/TetMesh.h"
#include "bcassim/mesh/TriMesh.h"

namespace py = pybind11;
using namespace pybind11::literals;

namespace bcassim::python {

void bindMesh(py::module_& m) {
  py::class_<TetMesh>(m, "TetMesh",
                      "Linear tetrahedral mesh: V (#V x 3 rest positions, m), T (#T x 4 node "
                      "indices, positively oriented), region (#T ids, empty = all 0)")
      .def(py::init([](Eigen::MatrixX3d V, Eigen::MatrixX4i T, std::optional<Eigen::VectorXi> r) {
             TetMesh mesh{std::move(V), std::move(T), r ? std::move(*r) : Eigen::VectorXi()};
             validateTetMesh(mesh, "TetMesh(V, T)");
             return mesh;
           }),
           "V"_a, "T"_a, "region"_a = py::none(),
           "Checks the mesh (indices in range, positive volumes): InputError otherwise")
      .def_readwrite("V", &TetMesh::V)
      .def_readwrite("T", &TetMesh::T)
      .def_readwrite("region", &TetMesh::region)
      .def_property_readonly("num_nodes", &TetMesh::numNodes)
      .def_property_readonly("num_tets", &TetMesh::numTets)
      .def("__repr__", [](const TetMesh& mesh) {
        return "<bcassim.mesh.TetMesh " + std::to_string(mesh.numNodes()) + " nodes, " +
               std::to_string(mesh.numTets()) + " tets>";
      });

  py::class_<TriMesh>(m, "TriMesh", "Triangle surface: V (#V x 3, m), F (#F x 3 vertex indices)")
      .def(py::init([](Eigen::MatrixX3d V, Eigen::MatrixX3i F) {
             return TriMesh{std::move(V), std::move(F)};
           }),
           "V"_a, "F"_a)
      .def_readwrite("V", &TriMesh::V)
      .def_readwrite("F", &TriMesh::F)
      .def("__repr__", [](const TriMesh& mesh) {
        return "<bcassim.mesh.TriMesh " + std::to_string(mesh.V.rows()) + " vertices, " +
               std::to_string(mesh.F.rows()) + " faces>";
      });

  m.def("make_box_mesh", &makeBoxMesh, "size"_a, "nx"_a, "ny"_a, "nz"_a,
        py::call_guard<py::gil_scoped_release>(),
        "Box [0, size] (m) split into nx x ny x nz cubes of 6 tets each");
  m.def("make_cylinder_mesh", &makeCylinderMesh, "radius"_a, "length"_a, "target_nodes"_a,
        py::call_guard<py::gil_scoped_release>(),
        "Cylinder of radius and length (m) along z from 0, about target_nodes nodes");
  m.def("make_icosphere_surface", &makeIcosphereSurface, "radius"_a, "levels"_a,
        "Sphere surface (m) from an icosahedron subdivided `levels` times");
  m.def(
      "boundary_surface",
      [](const TetMesh& mesh) { return toTriMesh(mesh, extractBoundary(mesh)); }, "mesh"_a,
      "The boundary triangles of a tet mesh, outward, on the mesh's own node numbering");

  py::class_<BoxRegion>(m, "BoxRegion", "Axis-aligned box, corners in m (boundary included)")
      .def(py::init([](const Vec3& lo, const Vec3& hi) {
             return BoxRegion{lo, hi};
           }),
           "min"_a, "max"_a)
      .def_readwrite("min", &BoxRegion::min)
      .def_readwrite("max", &BoxRegion::max);
  py::class_<SphereRegion>(m, "SphereRegion", "Ball: centre (m) and radius (m)")
      .def(py::init([](const Vec3& c, double r) {
             return SphereRegion{c, r};
           }),
           "center"_a, "radius"_a)
      .def_readwrite("center", &SphereRegion::center)
      .def_readwrite("radius", &SphereRegion::radius);
  py::class_<HalfSpaceRegion>(m, "HalfSpaceRegion", "Points x with (x - point) . normal >= 0 (m)")
      .def(py::init([](const Vec3& p, const Vec3& n) {
             return HalfSpaceRegion{p, n};
           }),
           "point"_a, "normal"_a)
      .def_readwrite("point", &HalfSpaceRegion::point)
      .def_readwrite("normal", &HalfSpaceRegion::normal);
  py::class_<IndexListRegion>(m, "IndexListRegion", "Explicit node (or tet) ids")
      .def(py::init([](std::vector<int> ids) { return IndexListRegion{std::move(ids)}; }),
           "indices"_a)
      .def_readwrite("indices", &IndexListRegion::indices);
  py::class_<SurfacePatchRegion>(
      m, "SurfacePatchRegion",
      "Boundary nodes inside `within` (a BoxRegion or SphereRegion) whose outward normal is within "
      "max_angle_deg of `direction` (None: any)")
      .def(py::init([](std::variant<BoxRegion, SphereRegion> within, std::optional<Vec3> direction,
                       double maxAngleDeg) {
             return SurfacePatchRegion{std::move(within), direction, maxAngleDeg};
           }),
           "within"_a, "direction"_a = py::none(), "max_angle_deg"_a = 90.0);

  m.def(
      "select_nodes",
      [](const TetMesh& mesh, const Region& region) {
        const std::vector<int> ids = selectNodes(mesh, region);
        return Eigen::VectorXi(Eigen::Map<const Eigen::VectorXi>(ids.data(), ids.size()));
      },
      "mesh"_a, "region"_a, "Sorted node ids of the mesh in the region (rest positions)");
  m.def(
      "select_tets",
      [](const TetMesh& mesh, const Region& region) {
        const std::vector<int> ids = selectTets(mesh, region);
        return Eigen::VectorXi(Eigen::Map<const Eigen::VectorXi>(ids.data(), ids.size()));
      },
      "mesh"_a, "region"_a, "Sorted ids of the tets whose centroid lies in the region");

  py::class_<RigidTransform>(m, "RigidTransform", "x -> rotation x + translation (m)")
      .def(py::init([](const Mat3& r, const Vec3& t) {
             return RigidTransform{r, t};
           }),
           "rotation"_a = Mat3::Identity(), "translation"_a = Vec3::Zero())
      .def_readwrite("rotation", &RigidTransform::rotation)
      .def_readwrite("translation", &RigidTransform::translation)
      .def("apply", &RigidTransform::apply, "points"_a, "Moves #P x 3 points")
      .def("inverse", &RigidTransform::inverse);
  m.def(
      "kabsch_fit",
      [](const Eigen::MatrixX3d& P, const Eigen::MatrixX3d& Q, const Eigen::VectorXd& w) {
        return kabschFit(P, Q, w);
      },
      "P"_a, "Q"_a, "weights"_a = Eigen::VectorXd(),
      "The rigid transform moving points P onto their correspondents Q (least squares)");
}

}  // namespace bcassim::python
