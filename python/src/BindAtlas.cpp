// bcassim.atlas: LDDMM surface registration (thesis §4.2), varifold and current distances, the
// ligament atlas (build, read, write) and its transfer onto a new liver (§4.3). Metres.
#include <pybind11/eigen.h>
#include <pybind11/functional.h>
#include <pybind11/stl.h>

#include "Bindings.h"
#include "bcassim/atlas/AnnotatedLivers.h"
#include "bcassim/atlas/AtlasTransfer.h"
#include "bcassim/atlas/FaceKernelDistance.h"
#include "bcassim/atlas/LigamentAtlas.h"
#include "bcassim/atlas/LigamentAtlasFile.h"
#include "bcassim/atlas/Registration.h"

namespace py = pybind11;
using namespace pybind11::literals;

namespace bcassim::python {

namespace {
FaceKernelKind kernelKind(const std::string& name) {
  if (name == "varifold") return FaceKernelKind::Varifold;
  if (name == "current") return FaceKernelKind::Current;
  throw py::value_error("data_term: expected 'varifold' or 'current', got '" + name + "'");
}

RegistrationOptions registrationOptions(double sigmaV, double sigmaW, const std::string& dataTerm,
                                        int maxIterations) {
  RegistrationOptions o;
  o.sigmaV = sigmaV;
  o.sigmaW = sigmaW;
  o.dataTerm = kernelKind(dataTerm);
  o.lbfgs.maxIterations = maxIterations;
  return o;
}
}  // namespace

void bindAtlas(py::module_& m) {
  m.def(
      "surface_distance",
      [](const TriMesh& a, const TriMesh& b, double sigmaW, const std::string& kind) {
        const FaceKernelDistance d(b, sigmaW, kernelKind(kind));
        return d.value(a.V, a.F);
      },
      "a"_a, "b"_a, "sigma_w"_a = 0.01, "kind"_a = "varifold",
      "Squared varifold (or current) distance between two surfaces, kernel width sigma_w (m)");

  py::class_<RegistrationResult>(m, "RegistrationResult")
      .def_readonly("control_points", &RegistrationResult::controlPoints)
      .def_readonly("momenta", &RegistrationResult::momenta)
      .def_readonly("deformed_vertices", &RegistrationResult::deformedVertices,
                    "Source vertices moved onto the target, #V x 3 (m)")
      .def_readonly("initial_data", &RegistrationResult::initialData)
      .def_readonly("data", &RegistrationResult::data)
      .def_readonly("regularity", &RegistrationResult::regularity)
      .def_readonly("iterations", &RegistrationResult::iterations)
      .def_readonly("converged", &RegistrationResult::converged);
  m.def(
      "register_surface",
      [](const TriMesh& source, const TriMesh& target, double sigmaV, double sigmaW,
         const std::string& dataTerm, int maxIterations) {
        const RegistrationOptions o = registrationOptions(sigmaV, sigmaW, dataTerm, maxIterations);
        py::gil_scoped_release release;
        return registerSurface(source, target, o);
      },
      "source"_a, "target"_a, "sigma_v"_a = 0.02, "sigma_w"_a = 0.01, "data_term"_a = "varifold",
      "max_iterations"_a = 200,
      "Diffeomorphic (LDDMM) registration of source onto target: deformation kernel sigma_v, "
      "data kernel sigma_w (m)");

  py::class_<AtlasSubject>(m, "AtlasSubject", "A training liver: surface and attachment curve (m)")
      .def(py::init([](std::string name, TriMesh surface, Eigen::MatrixX3d curve) {
             return AtlasSubject{std::move(name), std::move(surface), std::move(curve)};
           }),
           "name"_a, "surface"_a, "curve"_a)
      .def_readonly("name", &AtlasSubject::name)
      .def_readonly("surface", &AtlasSubject::surface)
      .def_readonly("curve", &AtlasSubject::curve);
  m.def(
      "read_annotated_livers",
      [](const std::string& dir, int label, double scale) {
        LiverFolder folder = readAnnotatedLivers(dir, label, scale);
        return py::make_tuple(folder.subjects, folder.skipped);
      },
      "dir"_a, "label"_a = 2, "scale"_a = 1e-3,
      "(subjects, skipped) from NAME.obj + NAME.eseg pairs; scale: metres per file unit");

  py::class_<CarriedCurve>(m, "CarriedCurve", "The atlas curve on a surface: mean +- sigma band")
      .def_readonly("mean", &CarriedCurve::mean)
      .def_readonly("lower", &CarriedCurve::lower)
      .def_readonly("upper", &CarriedCurve::upper)
      .def_readonly("sigma", &CarriedCurve::sigma);
  py::class_<LigamentAtlas>(m, "LigamentAtlas", "Mean liver shape and mean ligament curve")
      .def_readonly("template", &LigamentAtlas::templ)
      .def_readonly("subjects", &LigamentAtlas::subjects)
      .def_readonly("alignment_rms", &LigamentAtlas::alignmentRms)
      .def_property_readonly(
          "curve", [](const LigamentAtlas& a) { return carryCurve(a.curve, a.templ.V); },
          "The mean curve and its band on the template");
  m.def(
      "build_ligament_atlas",
      [](const std::vector<AtlasSubject>& subjects, double sigmaV, double sigmaW, bool frechetMean,
         int maxIterations, const std::optional<py::function>& log) {
        LigamentAtlasOptions o;
        o.registration = registrationOptions(sigmaV, sigmaW, "varifold", maxIterations);
        o.frechetMean = frechetMean;
        std::shared_ptr<py::function> f;
        if (log) f = std::make_shared<py::function>(*log);
        AtlasLog logLine;
        if (f)
          logLine = [f](const std::string& line) {
            py::gil_scoped_acquire gil;
            (*f)(line);
          };
        py::gil_scoped_release release;
        return buildLigamentAtlas(subjects, o, logLine);
      },
      "subjects"_a, "sigma_v"_a = 0.02, "sigma_w"_a = 0.01, "frechet_mean"_a = true,
      "max_iterations"_a = 200, "log"_a = py::none(),
      "The statistical atlas of thesis §4.3 (eq. 4.8): mean shape, carried curves, their mean "
      "and sigma per cutting plane; log(line) reports progress");
  m.def("write_ligament_atlas", &writeLigamentAtlas, "dir"_a, "atlas"_a);
  m.def("read_ligament_atlas", &readLigamentAtlas, "dir"_a,
        py::call_guard<py::gil_scoped_release>());

  py::class_<AtlasTransfer>(m, "AtlasTransfer", "The atlas carried onto a patient (m)")
      .def_readonly("rigid", &AtlasTransfer::rigid)
      .def_readonly("rigid_rms", &AtlasTransfer::rigidRms)
      .def_property_readonly("rigid_rotation_degrees",
                             [](const AtlasTransfer& t) { return t.rigidReport.rotationDegrees; })
      .def_property_readonly("implausible_pose_refused",
                             [](const AtlasTransfer& t) { return t.rigidReport.rejected; })
      .def_readonly("registration", &AtlasTransfer::registration)
      .def_readonly("deformed_template", &AtlasTransfer::deformedTemplate)
      .def_readonly("curve", &AtlasTransfer::curve);
  m.def(
      "transfer_atlas",
      [](const LigamentAtlas& atlas, const TriMesh& patient, double sigmaV, double sigmaW,
         int maxIterations, bool rigidAlign, bool project, double maxRotation) {
        const RegistrationOptions o =
            registrationOptions(sigmaV, sigmaW, "varifold", maxIterations);
        py::gil_scoped_release release;
        return transferAtlas(atlas, patient, o, rigidAlign, project, maxRotation);
      },
      "atlas"_a, "patient"_a, "sigma_v"_a = 0.02, "sigma_w"_a = 0.01, "max_iterations"_a = 200,
      "rigid_align"_a = true, "project_onto_patient"_a = false, "max_rotation_degrees"_a = 180.0,
      "Rigid alignment then registration of the atlas template onto the patient surface (m); "
      "the mean curve and its band on the patient. max_rotation_degrees: 90 refuses poses "
      "turning the template further (CT livers in their scanner's axes), 180 any orientation");
}

}  // namespace bcassim::python
