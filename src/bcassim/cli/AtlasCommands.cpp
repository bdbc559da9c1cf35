// `bcassim atlas distance|register|build|transfer|loo`: the statistical atlas of ligament curves
// (LDDMM registration, thesis §4.3, §5.2) from the command line, each printing its results.
#include <fmt/format.h>
#include <tbb/global_control.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/atlas/AnnotatedLivers.h"
#include "bcassim/atlas/AtlasLeaveOneOut.h"
#include "bcassim/atlas/AtlasTransfer.h"
#include "bcassim/atlas/CurveComparison.h"
#include "bcassim/atlas/FaceKernelDistance.h"
#include "bcassim/atlas/LigamentAtlasFile.h"
#include "bcassim/atlas/Registration.h"
#include "bcassim/cli/Commands.h"
#include "bcassim/cli/SharedOptions.h"
#include "bcassim/io/MeshWriter.h"
#include "bcassim/io/PointCsvWriter.h"
#include "bcassim/io/SurfaceReader.h"
#include "bcassim/ligaments/AttachmentCurve.h"
#include "bcassim/ligaments/EsegLabels.h"
#include "bcassim/viz/PlotScripts.h"

namespace bcassim {
namespace {
namespace fs = std::filesystem;

TriMesh readScaled(const std::string& path, double scale) {
  if (!fs::is_regular_file(path)) {
    throw InputError(fmt::format(
        "{}: no such file (expected a triangle surface .obj/.stl/.ply/.vtk/.vtp)", path));
  }
  TriMesh m = readSurface(path);
  if (m.F.rows() == 0) throw InputError(fmt::format("{}: expected triangles, found none", path));
  m.V *= scale;
  return m;
}

// Options shared by the commands that register.
// Defaults: the best of the leave-one-out settings of docs/results-atlas.md.
struct RegistrationFlags {
  double sigmaV = 0.03, sigmaW = 0.02;
  int iterations = 100;
  std::string kernel = "varifold";
  double maxRotation = kScannerFrameMaxRotationDegrees;
  void add(CLI::App& c) {
    c.add_option("--max-rotation", maxRotation,
                 "Largest rotation (degrees) of the rigid pre-alignment: livers from CT lie in "
                 "their scanner's axes, a fit turning one further is refused; 180 accepts any "
                 "orientation")
        ->capture_default_str()
        ->check(CLI::Range(0.0, 180.0));
    c.add_option("--sigma-v", sigmaV, "Deformation kernel width and control-point spacing (m)")
        ->capture_default_str();
    c.add_option("--sigma-w", sigmaW, "Data-term kernel width (m)")->capture_default_str();
    c.add_option("--iterations", iterations, "Most L-BFGS iterations")->capture_default_str();
    c.add_option("--kernel", kernel, "Data term: varifold or current")
        ->check(CLI::IsMember({"varifold", "current"}))
        ->capture_default_str();
  }
  RegistrationOptions options() const {
    RegistrationOptions o;
    o.sigmaV = sigmaV;
    o.sigmaW = sigmaW;
    o.dataTerm = kernel == "current" ? FaceKernelKind::Current : FaceKernelKind::Varifold;
    o.lbfgs.maxIterations = iterations;
    return o;
  }
};

// The rigid pre-alignment's rotation and residual, and a better fit refused as implausible.
void printRigidAlignment(const MultiStartReport& r, double maxRotation) {
  fmt::print(
      "rigid alignment: turns the source {:.1f} deg, RMS closest-point distance {:.2f} mm{}\n",
      r.rotationDegrees, 1e3 * r.rms,
      r.withCurve ? fmt::format(" (surface and ridge together, the ridge's closest {:.0f} %)",
                                100.0 * kCurveKeptFraction)
                  : std::string());
  if (r.rejected)
    fmt::print(
        "implausible pose refused: a rigid fit turning it {:.1f} deg (RMS {:.2f} mm) is beyond "
        "--max-rotation {:g} deg for livers in scanner axes; the fit above is the best within it "
        "(--max-rotation 180 accepts any orientation)\n",
        r.rejectedRotationDegrees, 1e3 * r.rejectedRms, maxRotation);
  if (r.ambiguous)
    fmt::print(
        "ambiguous pose: a rival rigid fit {:.1f} deg away fits alike (RMS {:.2f} mm); signed "
        "principal axes agreement {:.2f} for the fit above, {:.2f} for the rival: check the "
        "orientation\n",
        r.rivalApartDegrees, 1e3 * r.rivalRms, r.axesAgreement, r.rivalAxesAgreement);
}

void plotAtlas(const fs::path& dir, const std::string& title) {
  std::fflush(stdout);
  const std::string problem = runPlotScript("plot_atlas.py", {dir.string(), title});
  if (problem.empty())
    fmt::print("wrote {}\n", (dir / "atlas.png").string());
  else
    fmt::print("plots skipped: {}\n", problem);
}

// Holds TBB, which runs the kernel sums of every atlas command, to `threads` threads while it
// lives; threads 0 (--threads not given) leaves all cores.
class TbbThreadLimit {
 public:
  explicit TbbThreadLimit(int threads) {
    if (threads > 0)
      limit_.emplace(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
  }

 private:
  std::optional<tbb::global_control> limit_;
};

constexpr const char* kKernelThreads = "the kernel sums (default: all cores)";
constexpr const char* kRegistrationThreads =
    "the kernel sums of the registrations (default: all cores)";
constexpr const char* kCurveLabelHelp = ".eseg label of the curve (2: falciform)";
constexpr const char* kLiverDirHelp = "Folder of NAME.obj surfaces with NAME.eseg edge labels";

CurveCentre parseCentre(const std::string& c) {
  if (c == "median") return CurveCentre::Median;
  if (c == "trimmed") return CurveCentre::Trimmed;
  return CurveCentre::Mean;
}

// --ridge-weight of build, loo and transfer: the multi-object data term's weight.
void addRidgeWeightOption(CLI::App& app, double& weight) {
  app.add_option("--ridge-weight", weight,
                 "Weight of the ridge term relative to the surface's, each measured against its "
                 "own size, in the registration and in the rigid fit (dimensionless; 1: as much as "
                 "the surface)")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
}

// --ridge and --ridge-weight of build and loo.
void addRidgeOptions(CLI::App& app, bool& ridge, double& weight) {
  app.add_flag("--ridge", ridge,
               "Multi-object data term: match the livers' ridges (.eseg label 3, the "
               "anterior-inferior border) along with their surfaces, in the rigid fit too");
  addRidgeWeightOption(app, weight);
}

// --centre and --outlier-mads of build and loo.
void addCentreOptions(CLI::App& app, std::string& centre, double& outlierMads) {
  app.add_option("--centre", centre,
                 "Per-plane centre of the crossings: mean (thesis), median (geometric) or trimmed "
                 "(mean after rejecting crossings more than --outlier-mads robust standard "
                 "deviations from the median: atypical curves do not pull it)")
      ->check(CLI::IsMember({"mean", "median", "trimmed"}))
      ->capture_default_str();
  app.add_option("--outlier-mads", outlierMads,
                 "k of --centre trimmed: reject crossings farther than k * 1.4826 * MAD from the "
                 "per-plane median")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
}

// ---------------------------------------------------------------------------------------------

class AtlasDistanceCommand : public Command {
 public:
  AtlasDistanceCommand()
      : Command({"atlas", "distance"}, "Varifold or current distance of two surfaces") {}

  void declare(CLI::App& app) override {
    app.add_option("A", a_, "First surface")->required();
    app.add_option("B", b_, "Second surface")->required();
    app.add_option("--kernel", kernel_, "varifold or current")
        ->check(CLI::IsMember({"varifold", "current"}))
        ->capture_default_str();
    app.add_option("--sigma", sigma_, "Kernel width (m)")->capture_default_str();
    addScaleOption(app, scale_);
    addThreadsOption(app, threads_, kKernelThreads, false);
  }

  int run() override {
    const TbbThreadLimit limit(threads_);
    const TriMesh a = readScaled(a_, scale_), b = readScaled(b_, scale_);
    const FaceKernelKind k =
        kernel_ == "current" ? FaceKernelKind::Current : FaceKernelKind::Varifold;
    const FaceKernelDistance dist(b, sigma_, k);
    fmt::print("{:.10g}\n", dist.value(a.V, a.F));
    return 0;
  }

 private:
  std::string a_, b_, kernel_ = "varifold";
  double sigma_ = 0.01, scale_ = 1e-3;
  int threads_ = 0;
};

class AtlasRegisterCommand : public Command {
 public:
  AtlasRegisterCommand()
      : Command({"atlas", "register"}, "LDDMM registration of SOURCE onto TARGET") {}

  void declare(CLI::App& app) override {
    app.add_option("SOURCE", source_, "Surface deformed")->required();
    app.add_option("TARGET", target_, "Surface matched")->required();
    addOutOption(app, out_);
    addScaleOption(app, scale_);
    app.add_flag("--rigid", rigid_, "Align rigidly first (multi-start ICP)");
    reg_.add(app);
    addThreadsOption(app, threads_, kKernelThreads, false);
  }

  int run() override {
    const TbbThreadLimit limit(threads_);
    TriMesh source = readScaled(source_, scale_);
    const TriMesh target = readScaled(target_, scale_);
    const fs::path out(out_);
    fs::create_directories(out);
    if (rigid_) {
      MultiStartReport report;
      const RigidTransform t =
          alignRigidlyMultiStart(source, target, {}, 8, nullptr, reg_.maxRotation, &report);
      source.V = t.apply(source.V);
      printRigidAlignment(report, reg_.maxRotation);
    }
    const auto t0 = Clock::now();
    const RegistrationResult res = registerSurface(source, target, reg_.options());
    const double s = secondsSince(t0);
    fmt::print(
        "{} -> {}: {} / {} faces, {} control points, {} iterations ({} evaluations), {:.2f} s\n",
        source_, target_, source.F.rows(), target.F.rows(), res.controlPoints.rows(),
        res.iterations, res.evaluations, s);
    fmt::print("data term {:.4g} -> {:.4g} ({:.1f} % left), regularity {:.4g}\n", res.initialData,
               res.data, 100.0 * res.data / res.initialData, res.regularity);
    writeSurface((out / "source.vtp").string(), source);
    writeSurface((out / "target.vtp").string(), target);
    writeSurface((out / "deformed.vtp").string(), TriMesh{res.deformedVertices, source.F});
    FieldSet f;
    f.pointVectors.push_back({"momentum", res.momenta});
    writePointCloud((out / "control_points.vtp").string(), res.controlPoints, f);
    fmt::print("wrote {}/{{source,target,deformed,control_points}}.vtp\n", out.string());
    return 0;
  }

 private:
  std::string source_, target_, out_ = "out/atlas-register";
  double scale_ = 1e-3;
  bool rigid_ = false;
  RegistrationFlags reg_;
  int threads_ = 0;
};

class AtlasBuildCommand : public Command {
 public:
  AtlasBuildCommand()
      : Command({"atlas", "build"}, "Atlas of a ligament curve from annotated livers") {
    reg_.iterations = 60;
  }

  void declare(CLI::App& app) override {
    app.add_option("LIVER_DIR", dir_, kLiverDirHelp)->required();
    addOutOption(app, out_);
    app.add_option("--label", label_, kCurveLabelHelp)->capture_default_str();
    app.add_option("--max-livers", maxSubjects_, "Use the first N usable livers (0: all)");
    app.add_option("--exclude", exclude_, "Liver names to leave out (e.g. LiTS-3)");
    app.add_option("--plane-step", planeStep_, "Angle between radial cutting planes (degrees)")
        ->capture_default_str();
    app.add_flag("--no-frechet", noFrechet_,
                 "Keep the first liver as template instead of the Frechet mean (faster)");
    app.add_option("--planes", planes_,
                   "Cutting planes: radial (around the left-right axis; falciform) or parallel "
                   "(perpendicular to it; curves along a flatter surface)")
        ->check(CLI::IsMember({"radial", "parallel"}))
        ->capture_default_str();
    app.add_option("--plane-spacing", planeSpacing_, "Distance between parallel planes (m)")
        ->capture_default_str();
    app.add_option("--min-crossing", minCrossing_,
                   "Fraction of the curves that must cross a plane for it to get a mean point")
        ->capture_default_str();
    app.add_flag("--median", median_, "Same as --centre median");
    addCentreOptions(app, centre_, outlierMads_);
    addScaleOption(app, scale_);
    addRidgeOptions(app, ridge_, ridgeWeight_);
    reg_.add(app);
    addThreadsOption(app, threads_, kRegistrationThreads, false);
  }

  int run() override {
    const TbbThreadLimit limit(threads_);
    const auto t0 = Clock::now();
    LiverFolder livers = readAnnotatedLivers(dir_, label_, scale_);
    for (const std::string& s : livers.skipped) fmt::print("skipped {}\n", s);
    std::erase_if(livers.subjects, [&](const AtlasSubject& s) {
      return std::find(exclude_.begin(), exclude_.end(), s.name) != exclude_.end();
    });
    if (maxSubjects_ > 0 && static_cast<int>(livers.subjects.size()) > maxSubjects_)
      livers.subjects.resize(static_cast<size_t>(maxSubjects_));
    if (livers.subjects.size() < 2) {
      throw InputError(
          fmt::format("{}: expected at least 2 usable NAME.obj + NAME.eseg livers, found {}", dir_,
                      livers.subjects.size()));
    }
    fmt::print("{} livers from {}\n", livers.subjects.size(), dir_);
    LigamentAtlasOptions o;
    o.registration = reg_.options();
    o.maxRotationDegrees = reg_.maxRotation;
    o.frechetMean = !noFrechet_;
    o.planeStepDegrees = planeStep_;
    o.minCrossingFraction = minCrossing_;
    o.planeSpacing = planeSpacing_;
    if (planes_ == "parallel") o.planes = CuttingPlaneFamily::Kind::Parallel;
    o.centre = median_ ? CurveCentre::Median : parseCentre(centre_);
    o.outlierMads = outlierMads_;
    o.ridge = ridge_;
    o.registration.curveWeight = ridgeWeight_;
    const LigamentAtlas atlas = buildLigamentAtlas(livers.subjects, o, [](const std::string& s) {
      fmt::print("{}\n", s);
      std::fflush(stdout);
    });
    const fs::path out(out_);
    writeLigamentAtlas(out.string(), atlas);
    writeCarriedCurveFiles(out.string(), atlas.templ, carryCurve(atlas.curve, atlas.templ.V));
    writePointSetsCsv((out / "curves.csv").string(), "curve", atlas.carriedCurves);
    fmt::print(
        "atlas of {} livers: {} curve points, sigma {:.1f} - {:.1f} mm, {:.1f} s; wrote {}\n",
        atlas.subjects.size(), atlas.curve.mean.size(), 1e3 * atlas.curve.sigma.minCoeff(),
        1e3 * atlas.curve.sigma.maxCoeff(), secondsSince(t0), out.string());
    plotAtlas(out, fmt::format("atlas of {} livers: mean falciform curve and ±σ band",
                               atlas.subjects.size()));
    return 0;
  }

 private:
  std::string dir_, out_ = "out/atlas";
  int label_ = 2, maxSubjects_ = 0;
  std::vector<std::string> exclude_;
  double scale_ = 1e-3, planeStep_ = 5.0, minCrossing_ = 0.25, planeSpacing_ = 0.005;
  std::string planes_ = "radial";
  bool noFrechet_ = false, median_ = false, ridge_ = false;
  std::string centre_ = "mean";
  double outlierMads_ = kDefaultOutlierMads, ridgeWeight_ = 1.0;
  RegistrationFlags reg_;
  int threads_ = 0;
};

// rigid_transform.csv: the template-to-patient rotation (rows r0..r2) and translation, in metres
// and in the patient file's units (metres / scale).
void writeRigidTransform(const std::string& path, const RigidTransform& t, double scale) {
  std::ofstream f(path);
  f << "row,r0,r1,r2,translation_m,translation_file_units\n";
  for (int i = 0; i < 3; ++i)
    f << fmt::format("{},{:.17g},{:.17g},{:.17g},{:.17g},{:.17g}\n", i, t.rotation(i, 0),
                     t.rotation(i, 1), t.rotation(i, 2), t.translation(i),
                     t.translation(i) / scale);
  if (!f) throw OutputError(fmt::format("{}: cannot write", path));
}

class AtlasTransferCommand : public Command {
 public:
  AtlasTransferCommand()
      : Command({"atlas", "transfer"},
                "Register an atlas onto a patient surface; writes ligament_curve.csv "
                "(x,y,z,sigma)") {}

  void declare(CLI::App& app) override {
    app.add_option("ATLAS", atlas_, "Atlas folder of 'bcassim atlas build'")->required();
    app.add_option("PATIENT", patient_, "Patient liver surface")->required();
    addOutOption(app, out_);
    app.add_option("--eseg", eseg_, "Expert .eseg of the patient: report the distance to it");
    app.add_option("--label", label_, kCurveLabelHelp)->capture_default_str();
    addScaleOption(app, scale_);
    app.add_flag("--project", project_,
                 "Move the transferred curve and band to their closest points on the patient's "
                 "surface (the registration leaves the deformed template a few mm off it)");
    app.add_option("--ridge-from", ridgeFrom_,
                   "A .eseg of the patient whose label 3 marks its ridge (the anterior-inferior "
                   "border, labelled or detected): matched with the atlas template's ridge "
                   "(rigid fit and multi-object data term); its falciform labels are not used");
    addRidgeWeightOption(app, ridgeWeight_);
    reg_.add(app);
    addThreadsOption(app, threads_, kKernelThreads, false);
  }

  int run() override {
    const TbbThreadLimit limit(threads_);
    const auto t0 = Clock::now();
    const LigamentAtlas atlas = readLigamentAtlas(atlas_);
    const TriMesh patient = readScaled(patient_, scale_);
    std::optional<Eigen::MatrixX2i> ridge;
    if (!ridgeFrom_.empty()) {
      ridge = edgesLabelled(readEseg(ridgeFrom_, patient), 3);
      if (ridge->rows() == 0)
        throw InputError(fmt::format("{}: no edge carries label 3 (the ridge)", ridgeFrom_));
    }
    RegistrationOptions ro = reg_.options();
    ro.curveWeight = ridgeWeight_;
    const AtlasTransfer tr = transferAtlas(atlas, patient, ro, true, project_, reg_.maxRotation,
                                           ridge ? &*ridge : nullptr);
    printRigidAlignment(tr.rigidReport, reg_.maxRotation);
    const fs::path out(out_);
    fs::create_directories(out);
    writeCarriedCurveFiles(out.string(), tr.deformedTemplate, tr.curve);
    writePointsCsv((out / "ligament_curve.csv").string(), tr.curve.mean,
                   {{"sigma", tr.curve.sigma}});
    // The same curve in the patient file's own units (e.g. mm for the CT livers), for tools that
    // read the surface as it is stored.
    writePointsCsv((out / "ligament_curve_file_units.csv").string(), tr.curve.mean / scale_,
                   {{"sigma", tr.curve.sigma / scale_}});
    writeRigidTransform((out / "rigid_transform.csv").string(), tr.rigid, scale_);
    writeSurface((out / "patient.vtp").string(), patient);
    fmt::print("registration: {} iterations, data {:.4g} -> {:.4g}; {} curve points, {:.1f} s\n",
               tr.registration.iterations, tr.registration.initialData, tr.registration.data,
               tr.curve.mean.rows(), secondsSince(t0));
    if (!eseg_.empty()) {
      TriMesh raw = readSurface(patient_);
      const LabelledEdges e = readEseg(eseg_, raw);
      Eigen::MatrixX3d expert = extractAttachmentCurve(raw, e, label_, eseg_).points * scale_;
      writePointsCsv((out / "expert_curve.csv").string(), expert);
      const CurveDistance d =
          compareCurves(expert, tr.curve.mean,
                        transformed(atlas.curve.planes, tr.rigid.rotation, tr.rigid.translation));
      // No plane crossed by both curves: the per-plane distance is undefined, not zero.
      const std::string perPlane =
          d.planes == 0 ? "planes 0 (no plane crosses both curves): per-plane distance undefined"
                        : fmt::format("planes {} mean {:.1f} mm max {:.1f} mm", d.planes,
                                      1e3 * d.planeMean, 1e3 * d.planeMax);
      fmt::print("distance to the expert curve: {}; points mean {:.1f} mm max {:.1f} mm\n",
                 perPlane, 1e3 * d.pointMean, 1e3 * d.pointMax);
      // The same against every labelled edge, not only the band's longest path.
      const Eigen::MatrixX2i band = edgesLabelled(e, label_);
      const CurveDistance b = compareCurveToBand(
          raw.V * scale_, band, tr.curve.mean,
          transformed(atlas.curve.planes, tr.rigid.rotation, tr.rigid.translation));
      fmt::print("distance to the expert's whole band ({} edges): {}; band points mean {:.1f} mm\n",
                 band.rows(),
                 b.planes == 0 ? std::string("planes 0: per-plane distance undefined")
                               : fmt::format("planes {} mean {:.1f} mm max {:.1f} mm", b.planes,
                                             1e3 * b.planeMean, 1e3 * b.planeMax),
                 1e3 * b.pointMean);
    }
    fmt::print("wrote {} (x,y,z,sigma in m, patient frame) and .vtp files\n",
               (out / "ligament_curve.csv").string());
    plotAtlas(out, "atlas transferred to " + fs::path(patient_).filename().string());
    return 0;
  }

 private:
  std::string atlas_, patient_, out_ = "out/atlas-transfer", eseg_, ridgeFrom_;
  int label_ = 2;
  double scale_ = 1e-3, ridgeWeight_ = 1.0;
  bool project_ = false;
  RegistrationFlags reg_;
  int threads_ = 0;
};

// The median of `v` (0 when empty).
double medianOf(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

// Writes loo.csv (one row per fold) into out and prints the means over the folds.
void reportLeaveOneOut(const LeaveOneOutResult& r, const std::vector<AtlasSubject>& subjects,
                       double planeStep, const std::vector<int>& nearestCounts, const fs::path& out,
                       double seconds) {
  fs::create_directories(out);
  std::ofstream f(out / "loo.csv");
  f << "liver,planes,mean_mm,max_mm,point_mean_mm,point_max_mm,rigid_only_mean_mm,"
       "rigid_only_max_mm,median_mean_mm,median_max_mm,atlas_points,alignment_rms_mm,data_left,"
       "plain_mean_mean_mm,plain_mean_max_mm,scale,band_planes,band_mean_mm,band_max_mm,"
       "band_point_mean_mm,fused_curves,fused_planes,fused_mean_mm,fused_max_mm,"
       "fused_band_mean_mm\n";
  double sumMean = 0, sumMax = 0, worst = 0, sumRigid = 0, sumPoint = 0, sumMedian = 0,
         sumMedianMax = 0, sumPlain = 0, sumPlainMax = 0;
  std::vector<double> perLiver;
  int counted = 0, bandCounted = 0;
  double sumBand = 0, sumBandMax = 0, worstBand = 0;
  for (const LeaveOneOutFold& fold : r.folds) {
    const CurveDistance& d = fold.distance;
    // Empty fields where no plane crosses both curves: undefined, not 0 mm.
    const auto perPlane = [&](double metres) {
      return d.planes == 0 ? std::string() : fmt::format("{}", 1e3 * metres);
    };
    f << subjects[fold.subject].name << ',' << d.planes << ',' << perPlane(d.planeMean) << ','
      << perPlane(d.planeMax) << ',' << 1e3 * d.pointMean << ',' << 1e3 * d.pointMax << ','
      << 1e3 * fold.rigidOnly.planeMean << ',' << 1e3 * fold.rigidOnly.planeMax << ','
      << 1e3 * fold.median.planeMean << ',' << 1e3 * fold.median.planeMax << ',' << fold.atlasPoints
      << ',' << 1e3 * r.alignmentRms[fold.subject] << ',' << r.dataRatio[fold.subject] << ','
      << 1e3 * fold.plainMean.planeMean << ',' << 1e3 * fold.plainMean.planeMax << ','
      << r.scale[fold.subject] << ',' << fold.band.planes << ','
      << (fold.band.planes == 0 ? std::string() : fmt::format("{}", 1e3 * fold.band.planeMean))
      << ','
      << (fold.band.planes == 0 ? std::string() : fmt::format("{}", 1e3 * fold.band.planeMax))
      << ',' << 1e3 * fold.band.pointMean << ',' << fold.fusedCurves << ',' << fold.fused.planes
      << ','
      << (fold.fused.planes == 0 ? std::string() : fmt::format("{}", 1e3 * fold.fused.planeMean))
      << ','
      << (fold.fused.planes == 0 ? std::string() : fmt::format("{}", 1e3 * fold.fused.planeMax))
      << ','
      << (fold.fusedBand.planes == 0 ? std::string()
                                     : fmt::format("{}", 1e3 * fold.fusedBand.planeMean))
      << '\n';
    if (fold.band.planes > 0) {
      ++bandCounted;
      sumBand += fold.band.planeMean;
      sumBandMax += fold.band.planeMax;
      worstBand = std::max(worstBand, fold.band.planeMean);
    }
    if (d.planes == 0) continue;
    ++counted;
    sumMean += d.planeMean;
    sumMax += d.planeMax;
    sumRigid += fold.rigidOnly.planeMean;
    sumPoint += d.pointMean;
    sumMedian += fold.median.planeMean;
    sumMedianMax += fold.median.planeMax;
    sumPlain += fold.plainMean.planeMean;
    sumPlainMax += fold.plainMean.planeMax;
    perLiver.push_back(d.planeMean);
    worst = std::max(worst, d.planeMax);
  }
  double regSeconds = 0;
  for (double s : r.registrationSeconds) regSeconds += s;
  if (counted > 0) {
    fmt::print(
        "leave-one-out over {} livers (falciform, radial planes every {} deg): mean {:.1f} mm, "
        "mean of max {:.1f} mm, largest {:.1f} mm; expert points to curve {:.1f} mm; "
        "rigid only {:.1f} mm\n",
        counted, planeStep, 1e3 * sumMean / counted, 1e3 * sumMax / counted, 1e3 * worst,
        1e3 * sumPoint / counted, 1e3 * sumRigid / counted);
    fmt::print(
        "with the per-plane geometric median instead of the mean: mean {:.1f} mm, mean of max "
        "{:.1f} mm\n",
        1e3 * sumMedian / counted, 1e3 * sumMedianMax / counted);
    fmt::print(
        "with the per-plane mean of all crossings (thesis): mean {:.1f} mm, mean of max "
        "{:.1f} mm\n",
        1e3 * sumPlain / counted, 1e3 * sumPlainMax / counted);
    fmt::print("median over livers {:.1f} mm; {} of {} livers within 10 mm\n",
               1e3 * medianOf(perLiver),
               std::count_if(perLiver.begin(), perLiver.end(), [](double x) { return x <= 0.01; }),
               counted);
  }
  if (bandCounted > 0) {
    fmt::print(
        "against the whole annotated band (nearest band crossing per plane) over {} livers: mean "
        "{:.1f} mm, mean of max {:.1f} mm, worst liver {:.1f} mm\n",
        bandCounted, 1e3 * sumBand / bandCounted, 1e3 * sumBandMax / bandCounted, 1e3 * worstBand);
  }
  // The curves fused over several templates, over the same folds.
  if (!r.folds.empty() && r.folds.front().fusedCurves > 0) {
    std::vector<double> fused;
    double band = 0, largest = 0;
    int bandShared = 0, curves = 0;
    for (const LeaveOneOutFold& fold : r.folds) {
      curves = std::max(curves, fold.fusedCurves);
      if (fold.fused.planes > 0) {
        fused.push_back(fold.fused.planeMean);
        largest = std::max(largest, fold.fused.planeMean);
      }
      if (fold.fusedBand.planes > 0) {
        ++bandShared;
        band += fold.fusedBand.planeMean;
      }
    }
    double sum = 0;
    for (double x : fused) sum += x;
    fmt::print(
        "fused over {} templates: {} livers share a plane: mean {:.1f} mm, median {:.1f} mm, worst "
        "liver {:.1f} mm; against the whole band ({} livers) {:.1f} mm\n",
        curves, fused.size(), 1e3 * sum / std::max<double>(1.0, static_cast<double>(fused.size())),
        1e3 * medianOf(fused), 1e3 * largest, bandShared, 1e3 * band / std::max(bandShared, 1));
  }
  // The atlases of the nearest shapes, over the same folds.
  const size_t kinds = r.folds.empty() ? 0 : r.folds.front().nearest.size();
  for (size_t k = 0; k < kinds; ++k) {
    int planesShared = 0, bandShared = 0;
    double sum = 0, sumMax = 0, largest = 0, band = 0;
    for (const LeaveOneOutFold& fold : r.folds) {
      const CurveDistance& d = fold.nearest[k];
      if (d.planes > 0) {
        ++planesShared;
        sum += d.planeMean;
        sumMax += d.planeMax;
        largest = std::max(largest, d.planeMean);
      }
      if (fold.nearestBand[k].planes > 0) {
        ++bandShared;
        band += fold.nearestBand[k].planeMean;
      }
    }
    fmt::print(
        "atlas of the {} nearest shapes: {} livers share a plane: mean {:.1f} mm, mean of max "
        "{:.1f} mm, worst liver {:.1f} mm; against the whole band ({} livers) {:.1f} mm\n",
        nearestCounts[k], planesShared, 1e3 * sum / std::max(planesShared, 1),
        1e3 * sumMax / std::max(planesShared, 1), 1e3 * largest, bandShared,
        1e3 * band / std::max(bandShared, 1));
  }
  fmt::print("registrations {:.0f} s ({:.1f} s each), total {:.0f} s; wrote {}\n", regSeconds,
             regSeconds / static_cast<double>(subjects.size()), seconds,
             (out / "loo.csv").string());
}

class AtlasLooCommand : public Command {
 public:
  AtlasLooCommand()
      : Command({"atlas", "loo"},
                "Leave-one-out validation on annotated livers (thesis §5.2, Table 5.1)") {}

  void declare(CLI::App& app) override {
    app.add_option("LIVER_DIR", dir_, kLiverDirHelp)->required();
    addOutOption(app, out_);
    app.add_option("--template", templ_, "Liver used as template (default: the first usable)");
    app.add_option("--held-out", heldOut_, "Livers held out in turn (0: all but the template)")
        ->capture_default_str();
    app.add_option("--max-livers", maxLivers_, "Use the first N usable livers (0: all)");
    app.add_option("--label", label_, kCurveLabelHelp)->capture_default_str();
    app.add_option("--plane-step", planeStep_, "Angle between radial cutting planes (degrees)")
        ->capture_default_str();
    app.add_option("--min-crossing", minCrossing_,
                   "Fraction of the curves that must cross a plane for it to get a mean point")
        ->capture_default_str();
    addScaleOption(app, scale_);
    addCentreOptions(app, centre_, outlierMads_);
    app.add_flag("--scale-align", scaleAlign_,
                 "Scale every liver to the template's surface area before aligning and "
                 "registering it (distances are still measured in the liver's own size)");
    app.add_flag("--project", project_,
                 "Move the transferred curve to its closest points on the held-out liver's "
                 "surface (as atlas transfer --project)");
    app.add_flag("--frechet-template", frechetTemplate_,
                 "Template shape: Frechet mean of all the surfaces (eq. 4.8, started from "
                 "--template; no curve enters it) instead of the --template liver itself");
    app.add_option("--template-iterations", templateIterations_,
                   "L-BFGS iterations of the Frechet-mean template (as atlas build)")
        ->capture_default_str();
    addRidgeOptions(app, ridge_, ridgeWeight_);
    app.add_flag("--ridge-on-held-out", ridgeOnHeldOut_,
                 "With --ridge: align and register the held-out liver with its ridge too (a "
                 "patient whose ridge is labelled or detected; without it, from its surface "
                 "alone)");
    app.add_option("--nearest", nearest_,
                   "Also report, for each count K given, every fold's atlas made from the K "
                   "training livers nearest in shape to the held-out one (by the distance "
                   "between their registered templates, which are in correspondence), e.g. "
                   "--nearest 5,10,20")
        ->delimiter(',');
    app.add_option("--fuse-templates", fuseTemplates_,
                   "Multi-template fusion: run the leave-one-out again with each of these livers "
                   "as the template and also report, per fold, the per-plane centre (--centre) "
                   "of the curves all the templates transferred onto the held-out liver, e.g. "
                   "--fuse-templates LiTS-5,LiTS-9 (columns fused_* of loo.csv; each adds a "
                   "run's time)")
        ->delimiter(',');
    reg_.add(app);
    addThreadsOption(app, threads_, kRegistrationThreads, false);
  }

  int run() override {
    const TbbThreadLimit limit(threads_);
    const auto t0 = Clock::now();
    if (ridgeOnHeldOut_ && !ridge_) throw InputError("--ridge-on-held-out: needs --ridge");
    for (int k : nearest_)
      if (k < 1) throw InputError(fmt::format("--nearest {}: expected a count >= 1", k));
    LiverFolder livers = readAnnotatedLivers(dir_, label_, scale_);
    for (const std::string& s : livers.skipped) fmt::print("skipped {}\n", s);
    if (maxLivers_ > 0 && static_cast<int>(livers.subjects.size()) > maxLivers_)
      livers.subjects.resize(static_cast<size_t>(maxLivers_));
    const auto n = static_cast<int>(livers.subjects.size());
    if (n < 3) {
      throw InputError(fmt::format(
          "{}: expected at least 3 usable NAME.obj + NAME.eseg livers, found {}", dir_, n));
    }
    LeaveOneOutOptions o;
    o.atlas.registration = reg_.options();
    o.atlas.maxRotationDegrees = reg_.maxRotation;
    o.atlas.planeStepDegrees = planeStep_;
    o.atlas.minCrossingFraction = minCrossing_;
    o.atlas.centre = parseCentre(centre_);
    o.atlas.outlierMads = outlierMads_;
    o.scaleAlign = scaleAlign_;
    o.frechetTemplate = frechetTemplate_;
    o.projectOntoSubject = project_;
    o.templateIterations = templateIterations_;
    o.ridge = ridge_;
    o.ridgeOnHeldOut = ridgeOnHeldOut_;
    o.nearestCounts = nearest_;
    o.atlas.registration.curveWeight = ridgeWeight_;
    // The index of the usable liver called `name`, -1 if none.
    const auto liverIndex = [&](const std::string& name) {
      for (int i = 0; i < n; ++i)
        if (livers.subjects[i].name == name) return i;
      return -1;
    };
    if (!templ_.empty()) {
      o.templateSubject = liverIndex(templ_);
      if (o.templateSubject < 0) {
        throw InputError(
            fmt::format("--template {}: expected the name of a usable liver of {}", templ_, dir_));
      }
    }
    for (const std::string& name : fuseTemplates_) {
      const int found = liverIndex(name);
      if (found < 0 || found == o.templateSubject) {
        throw InputError(fmt::format(
            "--fuse-templates {}: expected the name of a usable liver of {} other than the "
            "template",
            name, dir_));
      }
      if (std::find(o.fusionTemplates.begin(), o.fusionTemplates.end(), found) !=
          o.fusionTemplates.end())
        throw InputError(
            fmt::format("--fuse-templates {}: named twice; expected each liver once", name));
      o.fusionTemplates.push_back(found);
    }
    // Held out: the first `heldOut_` livers other than the template (all with --held-out 0).
    for (int i = 0; i < n && (heldOut_ <= 0 || static_cast<int>(o.heldOut.size()) < heldOut_); ++i)
      if (i != o.templateSubject) o.heldOut.push_back(i);
    fmt::print("{} livers, template {}, {} held out in turn\n", n,
               livers.subjects[o.templateSubject].name, o.heldOut.size());
    const LeaveOneOutResult r = leaveOneOut(livers.subjects, o, [](const std::string& s) {
      fmt::print("{}\n", s);
      std::fflush(stdout);
    });
    reportLeaveOneOut(r, livers.subjects, planeStep_, nearest_, fs::path(out_), secondsSince(t0));
    return 0;
  }

 private:
  std::string dir_, out_ = "out/atlas-loo", templ_;
  std::vector<std::string> fuseTemplates_;
  int label_ = 2, heldOut_ = 10, maxLivers_ = 0;
  double scale_ = 1e-3, planeStep_ = 5.0, minCrossing_ = 0.25;
  std::string centre_ = "mean";
  double outlierMads_ = kDefaultOutlierMads;
  bool scaleAlign_ = false, frechetTemplate_ = false, project_ = false;
  bool ridge_ = false, ridgeOnHeldOut_ = false;
  double ridgeWeight_ = 1.0;
  int templateIterations_ = 60;
  std::vector<int> nearest_;
  RegistrationFlags reg_;
  int threads_ = 0;
};

}  // namespace

std::unique_ptr<Command> makeAtlasDistanceCommand() {
  return std::make_unique<AtlasDistanceCommand>();
}
std::unique_ptr<Command> makeAtlasRegisterCommand() {
  return std::make_unique<AtlasRegisterCommand>();
}
std::unique_ptr<Command> makeAtlasBuildCommand() { return std::make_unique<AtlasBuildCommand>(); }
std::unique_ptr<Command> makeAtlasTransferCommand() {
  return std::make_unique<AtlasTransferCommand>();
}
std::unique_ptr<Command> makeAtlasLooCommand() { return std::make_unique<AtlasLooCommand>(); }

}  // namespace bcassim
