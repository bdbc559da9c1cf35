// `bcassim ligament fit CURVE.csv --model neo-hookean`: a hyperelastic law fitted to a measured
// uniaxial curve (thesis §4.4, eq. 4.9): parameters with standard errors, residual, small-strain
// moduli; in --out, the fitted curve (fit.csv) and the parameters (parameters.csv).
// `bcassim ligament springs --young E --thickness h --width w --length L`: cubic spring
// coefficients estimated by ROUKF from a stretched membrane of that law (thesis §2.3.4, §4.4),
// written as priors per metre of ligament (springs.yaml) with the per-frame comparison.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "bcassim/Error.h"
#include "bcassim/calibration/SpringCalibration.h"
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

// Young's modulus (Pa) of a Neo-Hookean fit of `ligament fit`: its --out folder or its
// parameters.csv. Other laws are refused (the membrane is Neo-Hookean).
double youngModulusOfFit(const std::string& path) {
  std::filesystem::path file = path;
  if (std::filesystem::is_directory(file)) file /= "parameters.csv";
  std::ifstream in(file);
  if (!in) throw InputError(fmt::format("--fit {}: cannot read {}", path, file.string()));
  std::string line;
  double young = 0;
  bool found = false;
  for (int n = 1; std::getline(in, line); ++n) {
    const std::string name = line.substr(0, line.find(','));
    if (name == "c10" || name == "c01" || name == "alpha")
      throw InputError(fmt::format(
          "--fit {}:{}: parameter {}: not a neo-hookean fit; the membrane is neo-hookean",
          file.string(), n, name));
    if (name != "young_modulus") continue;
    const size_t comma = line.find(',');
    const std::string value = line.substr(comma + 1, line.find(',', comma + 1) - comma - 1);
    char* end = nullptr;
    young = std::strtod(value.c_str(), &end);
    if (end == value.c_str() || !(young > 0))
      throw InputError(fmt::format("--fit {}:{}: young_modulus '{}': expected a number > 0 Pa",
                                   file.string(), n, value));
    found = true;
  }
  if (!found)
    throw InputError(
        fmt::format("--fit {}: no young_modulus row (a parameters.csv of ligament fit)", path));
  return young;
}

class LigamentSpringsCommand : public Command {
 public:
  LigamentSpringsCommand()
      : Command({"ligament", "springs"},
                "Cubic spring priors per metre of ligament from a stretched FEM membrane (ROUKF, "
                "thesis §2.3.4, §4.4)") {}

  void declare(CLI::App& app) override {
    SpringCalibrationOptions& o = options_;
    app.add_option("--material", material_,
                   "Membrane law: neo-hookean (or another material name of the scene format)")
        ->capture_default_str();
    youngOption_ = checkPositive(
        app.add_option("--young", o.membrane.young, "Young's modulus of the membrane, Pa"));
    app.add_option("--fit", fit_,
                   "Young's modulus from a neo-hookean `ligament fit`: its --out folder or "
                   "parameters.csv (instead of --young)")
        ->excludes(youngOption_);
    app.add_option("--poisson", o.membrane.poisson, "Poisson's ratio of the membrane, -")
        ->capture_default_str();
    checkPositive(app.add_option("--thickness", o.membrane.size(2), "Membrane thickness, m"))
        ->required();
    checkPositive(app.add_option("--width", o.membrane.size(0),
                                 "Membrane width (across the pull, the ligament's extent), m"))
        ->required();
    checkPositive(app.add_option("--length", o.membrane.size(1),
                                 "Membrane length (along the pull) = the springs' rest length, m"))
        ->required();
    checkPositive(app.add_option("--strain", o.strain,
                                 "Largest engineering strain of the stretch, - (at most 1)"))
        ->capture_default_str();
    app.add_option("--frames", o.frames, "Quasi-static frames from 0 to --strain")
        ->capture_default_str();
    app.add_option("--passes", o.passes, "Loading passes the filter sees")->capture_default_str();
    app.add_option("--lattice-cells", latticeCells_,
                   "Spring lattice cells across and along (default: 4 across, and along as many as "
                   "make square cells, at least 2: 4 x 10 for 40 x 100 mm)")
        ->expected(2);
    app.add_option("--membrane-cells", membraneCells_,
                   "Hexahedra of the membrane mesh across, along, through, 6 tets each; they must "
                   "be multiples of the lattice's (default: 4 times the lattice's, 1 through)")
        ->expected(3);
    checkPositive(app.add_option("--force-sigma", o.forceSigma,
                                 "Observation sigma of the reaction, relative to the frame's, -"))
        ->capture_default_str();
    checkNonNegative(app.add_option("--position-sigma", o.positionSigma,
                                    "Observation sigma of the node positions, m (0: not observed)"))
        ->capture_default_str();
    addOutOption(app, out_);
  }

  int run() override {
    SpringCalibrationOptions& o = options_;
    if (!fit_.empty())
      o.membrane.young = youngModulusOfFit(fit_);
    else if (youngOption_->count() == 0)
      throw InputError("--young or --fit: the membrane's Young's modulus is required");
    o.membrane.material = material_ == "neo-hookean" ? "neohookean" : material_;
    if (latticeCells_.empty()) {
      const double along = 4.0 * o.membrane.size(1) / o.membrane.size(0);
      latticeCells_ = {4, std::max(2, static_cast<int>(std::lround(along)))};
    }
    if (membraneCells_.empty()) membraneCells_ = {4 * latticeCells_[0], 4 * latticeCells_[1], 1};
    o.membrane.cellsX = membraneCells_[0];
    o.membrane.cellsY = membraneCells_[1];
    o.membrane.cellsZ = membraneCells_[2];
    o.latticeX = latticeCells_[0];
    o.latticeY = latticeCells_[1];
    const SpringCalibrationResult r = calibrateSprings(o);
    print(r);
    write(r);
    return 0;
  }

 private:
  void print(const SpringCalibrationResult& r) const {
    const SpringCalibrationOptions& o = options_;
    const Vec3 mm = 1e3 * o.membrane.size;
    fmt::print("membrane: {} E {:.6g} Pa nu {:.3g}, {:g} x {:g} x {:g} mm, {} tets, {} nodes\n",
               o.membrane.material, o.membrane.young, o.membrane.poisson, mm(0), mm(1), mm(2),
               r.membraneTets, r.membraneNodes);
    fmt::print("lattice: {} x {} x 1 cells, {} nodes, {} edge + {} diagonal springs\n", o.latticeX,
               o.latticeY, r.latticeNodes, r.edgeSprings, r.diagonalSprings);
    fmt::print("stretch: {} frames to {:g} % strain, {} passes of ROUKF\n", o.frames,
               100 * o.strain, o.passes);
    const char* names[3] = {"k_alpha", "k_beta", "k_gamma"};
    const char* units[3] = {"N/m^3", "N/m^2", "N/m"};
    const double start[3] = {r.initial.kAlpha, r.initial.kBeta, r.initial.kGamma};
    const double est[3] = {r.estimated.kAlpha, r.estimated.kBeta, r.estimated.kGamma};
    for (int c = 0; c < 3; ++c)
      fmt::print("lattice spring {}: {:.6g} ± {:.3g} {} (start {:.6g} ± {:.3g})\n", names[c],
                 est[c], r.stddev(c), units[c], start[c], r.initialStddev(c));
    fmt::print("reaction: max error {:.3g} % of the membrane's (pulled alike)\n",
               100 * r.maxReactionError);
    fmt::print(
        "under the membrane's force: attachment (pulled end) mean error {:.3f} mm, max {:.3f} mm; "
        "all nodes mean {:.3f} mm, max {:.3f} mm\n",
        1e3 * r.attachmentMeanError, 1e3 * r.attachmentMaxError, 1e3 * r.meanError,
        1e3 * r.maxError);
    fmt::print(
        "time per frame: membrane {:.3f} ms, springs {:.4f} ms (median), ratio {:.1f}x; per "
        "Newton iteration: {:.3f} ms, {:.4f} ms, ratio {:.1f}x\n",
        r.membraneMedianMs, r.latticeMedianMs, r.speedRatio, r.membraneMedianMsPerIteration,
        r.latticeMedianMsPerIteration, r.iterationSpeedRatio);
    for (int c = 0; c < 3; ++c)
      fmt::print("prior per metre {}: {:.6g} ± {:.3g} {} per m (rest length {:g} m)\n", names[c],
                 r.perMetre[c].mean, r.perMetre[c].stddev, units[c], o.membrane.size(1));
    fmt::print("cubic fit of the strip's reaction: RMS {:.3g} % of the largest\n",
               100 * r.perMetreFitError);
    for (int c = 0; c < 3; ++c)
      fmt::print("prior per metre, coefficients >= 0, {}: {:.6g} ± {:.3g} {} per m\n", names[c],
                 r.perMetreNonNegative[c].mean, r.perMetreNonNegative[c].stddev, units[c]);
    fmt::print("its fit: RMS {:.3g} % of the largest reaction\n",
               100 * r.perMetreNonNegativeFitError);
  }

  void write(const SpringCalibrationResult& r) const {
    const SpringCalibrationOptions& o = options_;
    createOutputDirectory(out_);
    const std::filesystem::path dir = out_;
    std::ofstream y(dir / "springs.yaml");
    const char* names[3] = {"k_alpha", "k_beta", "k_gamma"};
    const char* units[3] = {"N/m^3", "N/m^2", "N/m"};
    y << fmt::format(
        "# Cubic spring priors from a stretched {} membrane (bcassim ligament springs, thesis "
        "§2.3.4, §4.4):\n# E {:.9g} Pa, nu {:.9g}, {:.9g} x {:.9g} x {:.9g} m, {} frames to "
        "{:.9g} strain.\n",
        o.membrane.material, o.membrane.young, o.membrane.poisson, o.membrane.size(0),
        o.membrane.size(1), o.membrane.size(2), o.frames, o.strain);
    y << "# Per metre of ligament width, for springs of rest length `rest_length`: springs s "
         "metres apart\n# along the ligament each take s times these (springs.groups[]."
         "coefficients, and the mean and\n# stddev of assimilation.parameters[] of kind spring; "
         "docs/calibration.md).\n";
    y << "ligament_spring_priors:\n";
    y << fmt::format("  rest_length: {:.9g}  # m\n", o.membrane.size(1));
    for (int c = 0; c < 3; ++c)
      y << fmt::format("  {}: {{mean: {:.9g}, stddev: {:.9g}}}  # {} per m of width\n", names[c],
                       r.perMetre[c].mean, r.perMetre[c].stddev, units[c]);
    y << fmt::format(
        "  fit_error: {:.6g}  # RMS of the cubic fit, relative to the largest reaction\n",
        r.perMetreFitError);
    y << "  non_negative:  # the best fit with every coefficient >= 0, as springs.groups[] take\n";
    for (int c = 0; c < 3; ++c)
      y << fmt::format("    {}: {{mean: {:.9g}, stddev: {:.9g}}}  # {} per m of width\n", names[c],
                       r.perMetreNonNegative[c].mean, r.perMetreNonNegative[c].stddev, units[c]);
    y << fmt::format("    fit_error: {:.6g}\n", r.perMetreNonNegativeFitError);
    y << fmt::format("  lattice:  # one spring of the estimated {} x {} x 1 lattice\n", o.latticeX,
                     o.latticeY);
    const Eigen::Vector3d est(r.estimated.kAlpha, r.estimated.kBeta, r.estimated.kGamma);
    for (int c = 0; c < 3; ++c)
      y << fmt::format("    {}: {{mean: {:.9g}, stddev: {:.9g}}}  # {}\n", names[c], est(c),
                       r.stddev(c), units[c]);
    y << fmt::format(
        "  comparison: {{attachment_mean_error: {:.6g}, attachment_max_error: {:.6g}, "
        "mean_error: {:.6g}, max_error: {:.6g}, max_reaction_error: {:.6g}, speed_ratio: {:.4g}, "
        "speed_ratio_per_iteration: {:.4g}}}  # m, m, m, m, -, -, -\n",
        r.attachmentMeanError, r.attachmentMaxError, r.meanError, r.maxError, r.maxReactionError,
        r.speedRatio, r.iterationSpeedRatio);

    std::ofstream f(dir / "frames.csv");
    f << "frame,strain,displacement_m,membrane_reaction_N,lattice_reaction_N,"
         "force_driven_displacement_m,attachment_mean_error_m,attachment_max_error_m,mean_error_m,"
         "max_error_m,membrane_ms,lattice_ms,membrane_newton,lattice_newton\n";
    for (size_t i = 0; i < r.frames.size(); ++i) {
      const SpringFrame& s = r.frames[i];
      f << fmt::format(
          "{},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.6g},"
          "{:.6g},{},{}\n",
          i + 1, s.strain, s.displacement, s.membraneReaction, s.latticeReaction,
          s.forceDrivenDisplacement, s.attachmentMeanError, s.attachmentMaxError, s.meanError,
          s.maxError, 1e3 * s.membraneSeconds, 1e3 * s.latticeSeconds, s.membraneIterations,
          s.latticeIterations);
    }
    std::ofstream e(dir / "estimates.csv");
    e << "step,frame,k_alpha,k_beta,k_gamma,sd_k_alpha,sd_k_beta,sd_k_gamma\n";
    for (size_t i = 0; i < r.stepMean.size(); ++i)
      e << fmt::format("{},{},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}\n", i + 1,
                       r.stepFrame[i] + 1, r.stepMean[i](0), r.stepMean[i](1), r.stepMean[i](2),
                       r.stepStddev[i](0), r.stepStddev[i](1), r.stepStddev[i](2));
    std::ofstream sh(dir / "shape.csv");
    sh << "node,membrane_x,membrane_y,membrane_z,lattice_x,lattice_y,lattice_z\n";
    for (Eigen::Index p = 0; p < r.lastLattice.size() / 3; ++p)
      sh << fmt::format("{},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g},{:.9g}\n", p, r.lastMembrane(3 * p),
                        r.lastMembrane(3 * p + 1), r.lastMembrane(3 * p + 2), r.lastLattice(3 * p),
                        r.lastLattice(3 * p + 1), r.lastLattice(3 * p + 2));
    if (!y || !f || !e || !sh)
      throw OutputError(fmt::format("{}: cannot write the springs' files", out_));
  }

  SpringCalibrationOptions options_;
  std::string material_ = "neo-hookean", fit_, out_ = "out/ligament-springs";
  std::vector<int> membraneCells_, latticeCells_;  // empty: from the size (see --help)
  CLI::Option* youngOption_ = nullptr;
};

}  // namespace

std::unique_ptr<Command> makeLigamentFitCommand() { return std::make_unique<LigamentFitCommand>(); }
std::unique_ptr<Command> makeLigamentSpringsCommand() {
  return std::make_unique<LigamentSpringsCommand>();
}

}  // namespace bcassim
