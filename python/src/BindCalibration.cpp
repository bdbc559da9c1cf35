// bcassim.calibration: hyperelastic laws fitted to uniaxial stress-strain curves (thesis eq. 4.9,
// docs/calibration.md). Stretch (-) and nominal stress (Pa).
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "Bindings.h"
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
}

}  // namespace bcassim::python
