// `bcassim ligament fit CURVE.csv --model neo-hookean`: a hyperelastic law fitted to a measured
// uniaxial curve (thesis §4.4, eq. 4.9): parameters with standard errors, residual, small-strain
// moduli; in --out, the fitted curve (fit.csv) and the parameters (parameters.csv).
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <filesystem>
#include <fstream>

#include "bcassim/Error.h"
#include "bcassim/calibration/UniaxialFit.h"
#include "bcassim/cli/Commands.h"
#include "bcassim/cli/SharedOptions.h"
#include "bcassim/run/OutputFiles.h"

namespace bcassim {
namespace {

// "NAME=LO:HI", either side may be empty (no bound there).
std::pair<std::string, ParameterBound> parseBound(const std::string& text) {
  const auto eq = text.find('='), colon = text.find(':', eq == std::string::npos ? 0 : eq);
  if (eq == std::string::npos || colon == std::string::npos || eq == 0)
    throw InputError(fmt::format("--bound '{}': expected NAME=LOWER:UPPER, e.g. alpha=1:30", text));
  ParameterBound b;
  const auto number = [&](const std::string& s, double fallback) {
    if (s.empty()) return fallback;
    try {
      size_t used = 0;
      const double v = std::stod(s, &used);
      if (used == s.size() && std::isfinite(v)) return v;
    } catch (const std::exception&) {
    }
    throw InputError(fmt::format("--bound '{}': '{}' is not a number", text, s));
  };
  b.lower = number(text.substr(eq + 1, colon - eq - 1), b.lower);
  b.upper = number(text.substr(colon + 1), b.upper);
  return {text.substr(0, eq), b};
}

class LigamentFitCommand : public Command {
 public:
  LigamentFitCommand()
      : Command({"ligament", "fit"},
                "Fit a hyperelastic law to a uniaxial stress-strain curve (thesis eq. 4.9)") {}

  void declare(CLI::App& app) override {
    app.add_option("curve", curve_,
                   "CSV with a header: stretch or strain, and nominal_stress_Pa or "
                   "cauchy_stress_Pa (SI units: Pa)")
        ->required();
    app.add_option("--model", model_, "neo-hookean, mooney-rivlin or ogden (incompressible)")
        ->capture_default_str();
    app.add_option("--bound", bounds_,
                   "NAME=LOWER:UPPER bounds a parameter (Pa for mu, c10, c01; - for alpha); "
                   "repeatable; an empty side is unbounded");
    addOutOption(app, out_);
  }

  int run() override {
    const UniaxialLaw law = parseUniaxialLaw(model_);
    UniaxialFitOptions options;
    for (const std::string& b : bounds_) options.bounds.insert(parseBound(b));
    const UniaxialCurve curve = readUniaxialCurve(curve_);
    const UniaxialFitResult fit = fitUniaxial(curve, law, options);
    fmt::print("curve: {} ({} points, stretch {:.4g} to {:.4g})\n", curve_, curve.stretch.size(),
               curve.stretch.minCoeff(), curve.stretch.maxCoeff());
    fmt::print("model: {} (incompressible, uniaxial)\n", uniaxialLawName(law));
    for (size_t k = 0; k < fit.names.size(); ++k)
      fmt::print("{}: {:.6g} ± {:.3g} {}\n", fit.names[k], fit.parameters(k), fit.standardErrors(k),
                 fit.units[k]);
    fmt::print("residual: RMS {:.4g} Pa, R² {:.6f}\n", fit.rmsResidual, fit.rSquared);
    fmt::print("small strain: shear modulus {:.6g} Pa, Young's modulus {:.6g} Pa\n",
               fit.shearModulus, 3.0 * fit.shearModulus);
    write(curve, fit);
    return 0;
  }

 private:
  void write(const UniaxialCurve& curve, const UniaxialFitResult& fit) const {
    createOutputDirectory(out_);
    const std::string curvePath = (std::filesystem::path(out_) / "fit.csv").string();
    std::ofstream c(curvePath);
    c << "stretch,measured_nominal_stress_Pa,fitted_nominal_stress_Pa\n";
    for (Eigen::Index i = 0; i < curve.stretch.size(); ++i)
      c << fmt::format("{:.9g},{:.9g},{:.9g}\n", curve.stretch(i), curve.nominalStress(i),
                       curve.nominalStress(i) + fit.residuals(i));
    const std::string paramPath = (std::filesystem::path(out_) / "parameters.csv").string();
    std::ofstream p(paramPath);
    p << "parameter,value,standard_error,unit\n";
    for (size_t k = 0; k < fit.names.size(); ++k)
      p << fmt::format("{},{:.9g},{:.9g},{}\n", fit.names[k], fit.parameters(k),
                       fit.standardErrors(k), fit.units[k]);
    p << fmt::format("young_modulus,{:.9g},,Pa\n", 3.0 * fit.shearModulus);
    if (!c || !p) throw OutputError(fmt::format("{}: cannot write the fit's files", out_));
  }

  std::string curve_, model_ = "neo-hookean", out_ = "out/ligament-fit";
  std::vector<std::string> bounds_;
};

}  // namespace

std::unique_ptr<Command> makeLigamentFitCommand() { return std::make_unique<LigamentFitCommand>(); }

}  // namespace bcassim
