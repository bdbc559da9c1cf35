// bcassim.mechanics: materials and the mechanical model of a mesh (elasticity, mass, springs,
// loads, Dirichlet conditions as a scene sets them): internal forces (N), stiffness (N/m, as
// scipy.sparse.csc_matrix), stored energy (J) at any positions (m).
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "Bindings.h"
#include "Positions.h"
#include "bcassim/mechanics/MechanicalModel.h"
#include "bcassim/mechanics/materials/Material.h"

namespace py = pybind11;
using namespace pybind11::literals;

namespace bcassim::python {

namespace {
// Material is a std::variant, which pybind11/stl.h would convert alternative by alternative;
// Python sees one opaque Material object instead.
struct MaterialHandle {
  Material law;
};
}  // namespace

void bindMechanics(py::module_& m) {
  py::class_<MaterialHandle>(m, "Material", "A hyperelastic law with its parameters")
      .def(py::init([](const std::string& name, double E, double nu) {
             return MaterialHandle{makeMaterial(name, E, nu)};
           }),
           "name"_a, "E"_a, "nu"_a,
           "name: linear, corotational, stvk, neohookean, mooneyrivlin or ogden; E Young's "
           "modulus (Pa); nu Poisson's ratio")
      .def_property_readonly("name",
                             [](const MaterialHandle& mat) { return materialName(mat.law); });

  py::class_<MechanicalModel>(m, "Model",
                              "Forces and stiffness of one organ model; copies share the mesh")
      .def(py::init([](const TetMesh& mesh, const std::vector<MaterialHandle>& handles,
                       double density, const std::string& mass) {
             if (mass != "lumped" && mass != "consistent")
               throw py::value_error("mass: expected 'lumped' or 'consistent', got '" + mass + "'");
             std::vector<Material> materials;
             for (const MaterialHandle& h : handles) materials.push_back(h.law);
             return makeMechanicalModel(std::make_shared<const TetMesh>(mesh), std::move(materials),
                                        density,
                                        mass == "lumped" ? MassKind::Lumped : MassKind::Consistent);
           }),
           "mesh"_a, "materials"_a, "density"_a = 1000.0, "mass"_a = "lumped",
           "materials: one per region id (or one for all); density in kg/m^3")
      .def_property_readonly("mesh", [](const MechanicalModel& model) { return *model.mesh; })
      .def_property_readonly("num_nodes",
                             [](const MechanicalModel& model) { return model.mesh->numNodes(); })
      .def_property_readonly("num_spring_groups",
                             [](const MechanicalModel& model) { return model.springs.numGroups(); })
      .def_property_readonly("num_loads",
                             [](const MechanicalModel& model) { return model.loads.size(); })
      .def(
          "rest_positions",
          [](const MechanicalModel& model) { return nodeRows(model.restPositions()); },
          "#V x 3 rest positions (m), the Dirichlet values at t = 0 imposed")
      .def(
          "internal_forces",
          [](const MechanicalModel& model, const py::array_t<double, py::array::forcecast>& x,
             double t) {
            const Eigen::VectorXd flat = flatPositions(x, model.mesh->numNodes(), "x");
            Eigen::VectorXd f;
            {
              py::gil_scoped_release release;
              model.internalForces(t, flat, f);
            }
            return nodeRows(f);
          },
          "x"_a, "t"_a = 0.0,
          "f_int = dW/dx (N, #V x 3) at positions x (m) and time t (s): elasticity, springs, "
          "control points")
      .def(
          "forces_and_stiffness",
          [](const MechanicalModel& model, const py::array_t<double, py::array::forcecast>& x,
             double t) {
            const Eigen::VectorXd flat = flatPositions(x, model.mesh->numNodes(), "x");
            Eigen::VectorXd f;
            SparseMatrix K;
            {
              py::gil_scoped_release release;
              model.internalForcesAndStiffness(t, flat, f, K);
            }
            return py::make_tuple(nodeRows(f), K);
          },
          "x"_a, "t"_a = 0.0,
          "(f_int (N, #V x 3), K = d2W/dx2 (N/m, 3N x 3N scipy.sparse.csc_matrix, node-major "
          "dofs)) at positions x (m), time t (s)")
      .def(
          "external_forces",
          [](const MechanicalModel& model, double t) {
            Eigen::VectorXd f;
            model.externalForces(t, f);
            return nodeRows(f);
          },
          "t"_a = 0.0, "Loads and gravity at time t (s), N, #V x 3")
      .def(
          "stored_energy",
          [](const MechanicalModel& model, const py::array_t<double, py::array::forcecast>& x,
             double t) {
            return model.storedEnergy(t, flatPositions(x, model.mesh->numNodes(), "x"));
          },
          "x"_a, "t"_a = 0.0, "W(x, t), J")
      .def(
          "set_material",
          [](MechanicalModel& model, int region, const MaterialHandle& mat) {
            if (region < 0 || region >= model.elasticity.numRegions())
              throw py::value_error("region " + std::to_string(region) + ": expected 0.." +
                                    std::to_string(model.elasticity.numRegions() - 1));
            model.elasticity.setMaterial(region, mat.law);
          },
          "region"_a, "material"_a, "Replaces the material of a region")
      .def(
          "spring_coefficients",
          [](const MechanicalModel& model, int group) {
            if (group < 0 || group >= model.springs.numGroups())
              throw py::value_error("spring group " + std::to_string(group) + ": expected 0.." +
                                    std::to_string(model.springs.numGroups() - 1));
            const CubicSpringCoefficients& k = model.springs.coefficients(group);
            return py::make_tuple(k.kAlpha, k.kBeta, k.kGamma);
          },
          "group"_a, "(k_alpha N/m^3, k_beta N/m^2, k_gamma N/m) of a spring group");
}

}  // namespace bcassim::python
