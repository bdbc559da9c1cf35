// bcassim.calibration: hyperelastic laws fitted to uniaxial stress-strain curves (thesis eq. 4.9),
// and cubic spring coefficients estimated from a stretched FEM membrane (§2.3.4;
// docs/calibration.md). SI units: stretch (-), stress (Pa), lengths (m), forces (N).
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include <tuple>

#include "Bindings.h"
#include "bcassim/calibration/SpringCalibration.h"
#include "bcassim/calibration/UniaxialFit.h"

namespace py = pybind11;
using namespace pybind11::literals;

namespace bcassim::python {

void bindCalibration(py::module_& m) {
  py::class_<UniaxialCurve>(m, "UniaxialCurve", "Stretch (-) and nominal stress (Pa)")
      .def(py::init([](Eigen::VectorXd stretch, Eigen::VectorXd stress) {
             if (stretch.size() != stress.size())
               throw py::value_error("stretch and nominal_stress: expected the same length");
             return UniaxialCurve{std::move(stretch), std::move(stress), {}};
           }),
           "stretch"_a, "nominal_stress"_a)
      .def_readonly("stretch", &UniaxialCurve::stretch)
      .def_readonly("nominal_stress", &UniaxialCurve::nominalStress);
  m.def("read_uniaxial_curve", &readUniaxialCurve, "path"_a,
        "CSV with a header: stretch or strain, nominal_stress_Pa or cauchy_stress_Pa");

  py::class_<UniaxialFitResult>(m, "UniaxialFit")
      .def_property_readonly("law",
                             [](const UniaxialFitResult& r) { return uniaxialLawName(r.law); })
      .def_readonly("names", &UniaxialFitResult::names)
      .def_readonly("units", &UniaxialFitResult::units)
      .def_readonly("parameters", &UniaxialFitResult::parameters)
      .def_readonly("standard_errors", &UniaxialFitResult::standardErrors)
      .def_readonly("residuals", &UniaxialFitResult::residuals, "model - measured, Pa")
      .def_readonly("rms_residual", &UniaxialFitResult::rmsResidual, "Pa")
      .def_readonly("r_squared", &UniaxialFitResult::rSquared)
      .def_readonly("shear_modulus", &UniaxialFitResult::shearModulus, "small-strain, Pa");
  m.def(
      "fit_uniaxial",
      [](const UniaxialCurve& curve, const std::string& model,
         const std::map<std::string, std::pair<double, double>>& bounds) {
        UniaxialFitOptions o;
        for (const auto& [name, b] : bounds) o.bounds[name] = {b.first, b.second};
        return fitUniaxial(curve, parseUniaxialLaw(model), o);
      },
      "curve"_a, "model"_a = "neo-hookean",
      "bounds"_a = std::map<std::string, std::pair<double, double>>(),
      "Least-squares fit of neo-hookean, mooney-rivlin or ogden (incompressible); bounds: "
      "{name: (lower, upper)} in the parameter's unit (use +-inf for one side)");
  m.def(
      "nominal_stress",
      [](const std::string& model, const Eigen::VectorXd& p, const Eigen::VectorXd& stretch) {
        const UniaxialLaw law = parseUniaxialLaw(model);
        if (p.size() != static_cast<Eigen::Index>(uniaxialParameterNames(law).size()))
          throw py::value_error("parameters: expected " +
                                std::to_string(uniaxialParameterNames(law).size()) + " values");
        Eigen::VectorXd s(stretch.size());
        for (Eigen::Index i = 0; i < stretch.size(); ++i)
          s(i) = uniaxialNominalStress(law, p, stretch(i));
        return s;
      },
      "model"_a, "parameters"_a, "stretch"_a, "The law's nominal stress (Pa) at each stretch");

  py::class_<SpringCalibrationResult>(m, "SpringCalibration")
      .def_property_readonly(
          "coefficients",
          [](const SpringCalibrationResult& r) {
            return Eigen::Vector3d(r.estimated.kAlpha, r.estimated.kBeta, r.estimated.kGamma);
          },
          "one lattice spring's k_alpha N/m^3, k_beta N/m^2, k_gamma N/m")
      .def_readonly("stddev", &SpringCalibrationResult::stddev)
      .def_property_readonly(
          "per_metre",
          [](const SpringCalibrationResult& r) {
            Eigen::Matrix<double, 3, 2> p;
            for (int c = 0; c < 3; ++c) p.row(c) << r.perMetre[c].mean, r.perMetre[c].stddev;
            return p;
          },
          "(mean, stddev) of K_alpha, K_beta, K_gamma per metre of width, rows")
      .def_property_readonly(
          "frames",
          [](const SpringCalibrationResult& r) {
            Eigen::MatrixXd f(r.frames.size(), 4);
            for (size_t i = 0; i < r.frames.size(); ++i)
              f.row(i) << r.frames[i].strain, r.frames[i].displacement,
                  r.frames[i].membraneReaction, r.frames[i].latticeReaction;
            return f;
          },
          "per frame: strain, displacement (m), membrane and lattice reactions (N)")
      .def_readonly("max_reaction_error", &SpringCalibrationResult::maxReactionError)
      .def_readonly("attachment_mean_error", &SpringCalibrationResult::attachmentMeanError, "m")
      .def_readonly("attachment_max_error", &SpringCalibrationResult::attachmentMaxError, "m")
      .def_readonly("mean_error", &SpringCalibrationResult::meanError, "m, all lattice nodes")
      .def_readonly("max_error", &SpringCalibrationResult::maxError, "m, all lattice nodes")
      .def_readonly("speed_ratio", &SpringCalibrationResult::speedRatio, "per frame");
  m.def(
      "calibrate_springs",
      [](double young, double thickness, double width, double length, double poisson, double strain,
         int frames, int passes, const std::string& material, std::pair<int, int> latticeCells,
         std::tuple<int, int, int> membraneCells) {
        SpringCalibrationOptions o;
        o.membrane.material = material == "neo-hookean" ? "neohookean" : material;
        o.membrane.young = young;
        o.membrane.poisson = poisson;
        o.membrane.size = Vec3(width, length, thickness);
        std::tie(o.membrane.cellsX, o.membrane.cellsY, o.membrane.cellsZ) = membraneCells;
        std::tie(o.latticeX, o.latticeY) = latticeCells;
        o.strain = strain;
        o.frames = frames;
        o.passes = passes;
        py::gil_scoped_release release;
        return calibrateSprings(o);
      },
      "young"_a, "thickness"_a, "width"_a, "length"_a, "poisson"_a = 0.45, "strain"_a = 0.45,
      "frames"_a = 9, "passes"_a = 5, "material"_a = "neo-hookean",
      "lattice_cells"_a = std::pair<int, int>(4, 10),
      "membrane_cells"_a = std::tuple<int, int, int>(16, 40, 1),
      "Cubic spring coefficients fitted by ROUKF to a stretched membrane (Pa, m), as `bcassim "
      "ligament springs`");
}

}  // namespace bcassim::python
