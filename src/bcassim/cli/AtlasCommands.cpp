#include "bcassim/cli/AtlasCommands.h"

#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/atlas/AnnotatedLivers.h"
#include "bcassim/atlas/AtlasLeaveOneOut.h"
#include "bcassim/atlas/AtlasTransfer.h"
#include "bcassim/atlas/CurveComparison.h"
#include "bcassim/atlas/FaceKernelDistance.h"
#include "bcassim/atlas/LigamentAtlasFile.h"
#include "bcassim/atlas/Registration.h"
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
    throw InputError(
        fmt::format("{}: no such file (expected a triangle surface .obj/.stl/.vtk/.vtp)", path));
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
  void add(CLI::App* c) {
    c->add_option("--sigma-v", sigmaV, "Deformation kernel width and control-point spacing (m)")
        ->capture_default_str();
    c->add_option("--sigma-w", sigmaW, "Data-term kernel width (m)")->capture_default_str();
    c->add_option("--iterations", iterations, "Most L-BFGS iterations")->capture_default_str();
    c->add_option("--kernel", kernel, "Data term: varifold or current")
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

void plotAtlas(const fs::path& dir, const std::string& title) {
  std::fflush(stdout);
  const std::string problem = runPlotScript("plot_atlas.py", {dir.string(), title});
  if (problem.empty())
    fmt::print("wrote {}\n", (dir / "atlas.png").string());
  else
    fmt::print("plots skipped: {}\n", problem);
}

[[noreturn]] void done() { throw CLI::Success(); }

// ---------------------------------------------------------------------------------------------

struct DistanceArgs {
  std::string a, b, kernel = "varifold";
  double sigma = 0.01, scale = 1e-3;
};

void runDistance(const DistanceArgs& d) {
  const TriMesh a = readScaled(d.a, d.scale), b = readScaled(d.b, d.scale);
  const FaceKernelKind k =
      d.kernel == "current" ? FaceKernelKind::Current : FaceKernelKind::Varifold;
  const FaceKernelDistance dist(b, d.sigma, k);
  fmt::print("{:.10g}\n", dist.value(a.V, a.F));
  done();
}

struct RegisterArgs {
  std::string source, target, out = "out/atlas-register";
  double scale = 1e-3;
  bool rigid = false;
  RegistrationFlags reg;
};

void runRegister(const RegisterArgs& r) {
  TriMesh source = readScaled(r.source, r.scale);
  const TriMesh target = readScaled(r.target, r.scale);
  const fs::path out(r.out);
  fs::create_directories(out);
  if (r.rigid) {
    double rms = 0.0;
    const RigidTransform t = alignRigidlyMultiStart(source, target, {}, 8, &rms);
    source.V = t.apply(source.V);
    fmt::print("rigid alignment: RMS closest-point distance {:.2f} mm\n", 1e3 * rms);
  }
  const auto t0 = Clock::now();
  const RegistrationResult res = registerSurface(source, target, r.reg.options());
  const double s = secondsSince(t0);
  fmt::print(
      "{} -> {}: {} / {} faces, {} control points, {} iterations ({} evaluations), {:.2f} s\n",
      r.source, r.target, source.F.rows(), target.F.rows(), res.controlPoints.rows(),
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
  done();
}

struct BuildArgs {
  std::string dir, out = "out/atlas";
  int label = 2, maxSubjects = 0;
  std::vector<std::string> exclude;
  double scale = 1e-3, planeStep = 5.0, minCrossing = 0.25, planeSpacing = 0.005;
  std::string planes = "radial";
  bool noFrechet = false, median = false;
  std::string centre = "mean";
  double outlierMads = kDefaultOutlierMads;
  RegistrationFlags reg;
};

CurveCentre parseCentre(const std::string& c) {
  if (c == "median") return CurveCentre::Median;
  if (c == "trimmed") return CurveCentre::Trimmed;
  return CurveCentre::Mean;
}

// --centre and --outlier-mads of build and loo.
void addCentreOptions(CLI::App* c, std::string& centre, double& outlierMads) {
  c->add_option("--centre", centre,
                "Per-plane centre of the crossings: mean (thesis), median (geometric) or trimmed "
                "(mean after rejecting crossings more than --outlier-mads robust standard "
                "deviations from the median: atypical curves do not pull it)")
      ->check(CLI::IsMember({"mean", "median", "trimmed"}))
      ->capture_default_str();
  c->add_option("--outlier-mads", outlierMads,
                "k of --centre trimmed: reject crossings farther than k * 1.4826 * MAD from the "
                "per-plane median")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
}

void runBuild(BuildArgs b) {
  const auto t0 = Clock::now();
  LiverFolder livers = readAnnotatedLivers(b.dir, b.label, b.scale);
  for (const std::string& s : livers.skipped) fmt::print("skipped {}\n", s);
  std::erase_if(livers.subjects, [&](const AtlasSubject& s) {
    return std::find(b.exclude.begin(), b.exclude.end(), s.name) != b.exclude.end();
  });
  if (b.maxSubjects > 0 && static_cast<int>(livers.subjects.size()) > b.maxSubjects)
    livers.subjects.resize(static_cast<size_t>(b.maxSubjects));
  if (livers.subjects.size() < 2) {
    throw InputError(
        fmt::format("{}: expected at least 2 usable NAME.obj + NAME.eseg livers, found {}", b.dir,
                    livers.subjects.size()));
  }
  fmt::print("{} livers from {}\n", livers.subjects.size(), b.dir);
  LigamentAtlasOptions o;
  o.registration = b.reg.options();
  o.frechetMean = !b.noFrechet;
  o.planeStepDegrees = b.planeStep;
  o.minCrossingFraction = b.minCrossing;
  o.planeSpacing = b.planeSpacing;
  if (b.planes == "parallel") o.planes = CuttingPlaneFamily::Kind::Parallel;
  o.centre = b.median ? CurveCentre::Median : parseCentre(b.centre);
  o.outlierMads = b.outlierMads;
  const LigamentAtlas atlas = buildLigamentAtlas(livers.subjects, o, [](const std::string& s) {
    fmt::print("{}\n", s);
    std::fflush(stdout);
  });
  const fs::path out(b.out);
  writeLigamentAtlas(out.string(), atlas);
  writeCarriedCurveFiles(out.string(), atlas.templ, carryCurve(atlas.curve, atlas.templ.V));
  writePointSetsCsv((out / "curves.csv").string(), "curve", atlas.carriedCurves);
  fmt::print("atlas of {} livers: {} curve points, sigma {:.1f} - {:.1f} mm, {:.1f} s; wrote {}\n",
             atlas.subjects.size(), atlas.curve.mean.size(), 1e3 * atlas.curve.sigma.minCoeff(),
             1e3 * atlas.curve.sigma.maxCoeff(), secondsSince(t0), out.string());
  plotAtlas(out, fmt::format("atlas of {} livers: mean falciform curve and ±σ band",
                             atlas.subjects.size()));
  done();
}

struct TransferArgs {
  std::string atlas, patient, out = "out/atlas-transfer", eseg;
  int label = 2;
  double scale = 1e-3;
  bool project = false;
  RegistrationFlags reg;
};

void runTransfer(const TransferArgs& t) {
  const auto t0 = Clock::now();
  const LigamentAtlas atlas = readLigamentAtlas(t.atlas);
  const TriMesh patient = readScaled(t.patient, t.scale);
  const AtlasTransfer tr = transferAtlas(atlas, patient, t.reg.options(), true, t.project);
  const fs::path out(t.out);
  fs::create_directories(out);
  writeCarriedCurveFiles(out.string(), tr.deformedTemplate, tr.curve);
  writePointsCsv((out / "ligament_curve.csv").string(), tr.curve.mean, {{"sigma", tr.curve.sigma}});
  writeSurface((out / "patient.vtp").string(), patient);
  fmt::print("registration: {} iterations, data {:.4g} -> {:.4g}; {} curve points, {:.1f} s\n",
             tr.registration.iterations, tr.registration.initialData, tr.registration.data,
             tr.curve.mean.rows(), secondsSince(t0));
  if (!t.eseg.empty()) {
    TriMesh raw = readSurface(t.patient);
    const LabelledEdges e = readEseg(t.eseg, raw);
    Eigen::MatrixX3d expert = extractAttachmentCurve(raw, e, t.label, t.eseg).points * t.scale;
    writePointsCsv((out / "expert_curve.csv").string(), expert);
    const CurveDistance d =
        compareCurves(expert, tr.curve.mean,
                      transformed(atlas.curve.planes, tr.rigid.rotation, tr.rigid.translation));
    fmt::print(
        "distance to the expert curve: planes {} mean {:.1f} mm max {:.1f} mm; points mean "
        "{:.1f} mm max {:.1f} mm\n",
        d.planes, 1e3 * d.planeMean, 1e3 * d.planeMax, 1e3 * d.pointMean, 1e3 * d.pointMax);
  }
  fmt::print("wrote {} (x,y,z,sigma in m, patient frame) and .vtp files\n",
             (out / "ligament_curve.csv").string());
  plotAtlas(out, "atlas transferred to " + fs::path(t.patient).filename().string());
  done();
}

struct LooArgs {
  std::string dir, out = "out/atlas-loo", templ;
  int label = 2, heldOut = 10, maxLivers = 0;
  double scale = 1e-3, planeStep = 5.0, minCrossing = 0.25;
  std::string centre = "mean";
  double outlierMads = kDefaultOutlierMads;
  bool scaleAlign = false, frechetTemplate = false, project = false;
  int templateIterations = 60;
  RegistrationFlags reg;
};

void runLoo(LooArgs a) {
  const auto t0 = Clock::now();
  LiverFolder livers = readAnnotatedLivers(a.dir, a.label, a.scale);
  for (const std::string& s : livers.skipped) fmt::print("skipped {}\n", s);
  if (a.maxLivers > 0 && static_cast<int>(livers.subjects.size()) > a.maxLivers)
    livers.subjects.resize(static_cast<size_t>(a.maxLivers));
  const auto n = static_cast<int>(livers.subjects.size());
  if (n < 3) {
    throw InputError(fmt::format(
        "{}: expected at least 3 usable NAME.obj + NAME.eseg livers, found {}", a.dir, n));
  }
  LeaveOneOutOptions o;
  o.atlas.registration = a.reg.options();
  o.atlas.planeStepDegrees = a.planeStep;
  o.atlas.minCrossingFraction = a.minCrossing;
  o.atlas.centre = parseCentre(a.centre);
  o.atlas.outlierMads = a.outlierMads;
  o.scaleAlign = a.scaleAlign;
  o.frechetTemplate = a.frechetTemplate;
  o.projectOntoSubject = a.project;
  o.templateIterations = a.templateIterations;
  if (!a.templ.empty()) {
    o.templateSubject = -1;
    for (int i = 0; i < n; ++i)
      if (livers.subjects[i].name == a.templ) o.templateSubject = i;
    if (o.templateSubject < 0) {
      throw InputError(
          fmt::format("--template {}: expected the name of a usable liver of {}", a.templ, a.dir));
    }
  }
  // Held out: the first `heldOut` livers other than the template (all with --held-out 0).
  for (int i = 0; i < n && (a.heldOut <= 0 || static_cast<int>(o.heldOut.size()) < a.heldOut); ++i)
    if (i != o.templateSubject) o.heldOut.push_back(i);
  fmt::print("{} livers, template {}, {} held out in turn\n", n,
             livers.subjects[o.templateSubject].name, o.heldOut.size());
  const LeaveOneOutResult r = leaveOneOut(livers.subjects, o, [](const std::string& s) {
    fmt::print("{}\n", s);
    std::fflush(stdout);
  });
  const fs::path out(a.out);
  fs::create_directories(out);
  std::ofstream f(out / "loo.csv");
  f << "liver,planes,mean_mm,max_mm,point_mean_mm,point_max_mm,rigid_only_mean_mm,"
       "rigid_only_max_mm,median_mean_mm,median_max_mm,atlas_points,alignment_rms_mm,data_left,"
       "plain_mean_mean_mm,plain_mean_max_mm,scale\n";
  double sumMean = 0, sumMax = 0, worst = 0, sumRigid = 0, sumPoint = 0, sumMedian = 0,
         sumMedianMax = 0, sumPlain = 0, sumPlainMax = 0;
  std::vector<double> perLiver;
  int counted = 0;
  for (const LeaveOneOutFold& fold : r.folds) {
    const CurveDistance& d = fold.distance;
    f << livers.subjects[fold.subject].name << ',' << d.planes << ',' << 1e3 * d.planeMean << ','
      << 1e3 * d.planeMax << ',' << 1e3 * d.pointMean << ',' << 1e3 * d.pointMax << ','
      << 1e3 * fold.rigidOnly.planeMean << ',' << 1e3 * fold.rigidOnly.planeMax << ','
      << 1e3 * fold.median.planeMean << ',' << 1e3 * fold.median.planeMax << ',' << fold.atlasPoints
      << ',' << 1e3 * r.alignmentRms[fold.subject] << ',' << r.dataRatio[fold.subject] << ','
      << 1e3 * fold.plainMean.planeMean << ',' << 1e3 * fold.plainMean.planeMax << ','
      << r.scale[fold.subject] << '\n';
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
        counted, a.planeStep, 1e3 * sumMean / counted, 1e3 * sumMax / counted, 1e3 * worst,
        1e3 * sumPoint / counted, 1e3 * sumRigid / counted);
    fmt::print(
        "with the per-plane geometric median instead of the mean: mean {:.1f} mm, mean of max "
        "{:.1f} mm\n",
        1e3 * sumMedian / counted, 1e3 * sumMedianMax / counted);
    fmt::print(
        "with the per-plane mean of all crossings (thesis): mean {:.1f} mm, mean of max "
        "{:.1f} mm\n",
        1e3 * sumPlain / counted, 1e3 * sumPlainMax / counted);
    std::sort(perLiver.begin(), perLiver.end());
    const size_t m = perLiver.size() / 2;
    const double med = perLiver.size() % 2 ? perLiver[m] : 0.5 * (perLiver[m - 1] + perLiver[m]);
    fmt::print("median over livers {:.1f} mm; {} of {} livers within 10 mm\n", 1e3 * med,
               std::count_if(perLiver.begin(), perLiver.end(), [](double x) { return x <= 0.01; }),
               counted);
  }
  fmt::print("registrations {:.0f} s ({:.1f} s each), total {:.0f} s; wrote {}\n", regSeconds,
             regSeconds / n, secondsSince(t0), (out / "loo.csv").string());
  done();
}

}  // namespace

void addAtlasCommands(CLI::App& app) {
  CLI::App* atlas = app.add_subcommand(
      "atlas", "Statistical atlas of ligament curves (LDDMM registration, thesis §4.3, §5.2)");
  atlas->require_subcommand(1);
  const char* scaleHelp = "Factor from file coordinates to metres (the shared livers are mm)";

  auto d = std::make_shared<DistanceArgs>();
  CLI::App* dist =
      atlas->add_subcommand("distance", "Varifold or current distance of two surfaces");
  dist->add_option("A", d->a, "First surface")->required();
  dist->add_option("B", d->b, "Second surface")->required();
  dist->add_option("--kernel", d->kernel, "varifold or current")
      ->check(CLI::IsMember({"varifold", "current"}))
      ->capture_default_str();
  dist->add_option("--sigma", d->sigma, "Kernel width (m)")->capture_default_str();
  dist->add_option("--scale", d->scale, scaleHelp)->capture_default_str();
  dist->callback([d] { runDistance(*d); });

  auto r = std::make_shared<RegisterArgs>();
  CLI::App* reg = atlas->add_subcommand("register", "LDDMM registration of SOURCE onto TARGET");
  reg->add_option("SOURCE", r->source, "Surface deformed")->required();
  reg->add_option("TARGET", r->target, "Surface matched")->required();
  reg->add_option("-o,--out", r->out, "Output folder")->capture_default_str();
  reg->add_option("--scale", r->scale, scaleHelp)->capture_default_str();
  reg->add_flag("--rigid", r->rigid, "Align rigidly first (multi-start ICP)");
  r->reg.add(reg);
  reg->callback([r] { runRegister(*r); });

  auto b = std::make_shared<BuildArgs>();
  CLI::App* build =
      atlas->add_subcommand("build", "Atlas of a ligament curve from annotated livers");
  build->add_option("LIVER_DIR", b->dir, "Folder of NAME.obj surfaces with NAME.eseg edge labels")
      ->required();
  build->add_option("-o,--out", b->out, "Atlas folder")->capture_default_str();
  build->add_option("--label", b->label, ".eseg label of the curve (2: falciform)")
      ->capture_default_str();
  build->add_option("--max-livers", b->maxSubjects, "Use the first N usable livers (0: all)");
  build->add_option("--exclude", b->exclude, "Liver names to leave out (e.g. LiTS-3)");
  build->add_option("--plane-step", b->planeStep, "Angle between radial cutting planes (degrees)")
      ->capture_default_str();
  build->add_flag("--no-frechet", b->noFrechet,
                  "Keep the first liver as template instead of the Frechet mean (faster)");
  build
      ->add_option("--planes", b->planes,
                   "Cutting planes: radial (around the left-right axis; falciform) or parallel "
                   "(perpendicular to it; curves along a flatter surface)")
      ->check(CLI::IsMember({"radial", "parallel"}))
      ->capture_default_str();
  build->add_option("--plane-spacing", b->planeSpacing, "Distance between parallel planes (m)")
      ->capture_default_str();
  build
      ->add_option("--min-crossing", b->minCrossing,
                   "Fraction of the curves that must cross a plane for it to get a mean point")
      ->capture_default_str();
  build->add_flag("--median", b->median, "Same as --centre median");
  addCentreOptions(build, b->centre, b->outlierMads);
  build->add_option("--scale", b->scale, scaleHelp)->capture_default_str();
  b->reg.iterations = 60;
  b->reg.add(build);
  build->callback([b] { runBuild(*b); });

  auto t = std::make_shared<TransferArgs>();
  CLI::App* tr = atlas->add_subcommand(
      "transfer",
      "Register an atlas onto a patient surface; writes ligament_curve.csv (x,y,z,sigma)");
  tr->add_option("ATLAS", t->atlas, "Atlas folder of 'bcassim atlas build'")->required();
  tr->add_option("PATIENT", t->patient, "Patient liver surface")->required();
  tr->add_option("-o,--out", t->out, "Output folder")->capture_default_str();
  tr->add_option("--eseg", t->eseg, "Expert .eseg of the patient: report the distance to it");
  tr->add_option("--label", t->label, ".eseg label of the curve (2: falciform)")
      ->capture_default_str();
  tr->add_option("--scale", t->scale, scaleHelp)->capture_default_str();
  tr->add_flag("--project", t->project,
               "Move the transferred curve and band to their closest points on the patient's "
               "surface (the registration leaves the deformed template a few mm off it)");
  t->reg.add(tr);
  tr->callback([t] { runTransfer(*t); });

  auto l = std::make_shared<LooArgs>();
  CLI::App* loo = atlas->add_subcommand(
      "loo", "Leave-one-out validation on annotated livers (thesis §5.2, Table 5.1)");
  loo->add_option("LIVER_DIR", l->dir, "Folder of NAME.obj surfaces with NAME.eseg edge labels")
      ->required();
  loo->add_option("-o,--out", l->out, "Output folder (loo.csv)")->capture_default_str();
  loo->add_option("--template", l->templ, "Liver used as template (default: the first usable)");
  loo->add_option("--held-out", l->heldOut, "Livers held out in turn (0: all but the template)")
      ->capture_default_str();
  loo->add_option("--max-livers", l->maxLivers, "Use the first N usable livers (0: all)");
  loo->add_option("--label", l->label, ".eseg label of the curve (2: falciform)")
      ->capture_default_str();
  loo->add_option("--plane-step", l->planeStep, "Angle between radial cutting planes (degrees)")
      ->capture_default_str();
  loo->add_option("--min-crossing", l->minCrossing,
                  "Fraction of the curves that must cross a plane for it to get a mean point")
      ->capture_default_str();
  loo->add_option("--scale", l->scale, scaleHelp)->capture_default_str();
  addCentreOptions(loo, l->centre, l->outlierMads);
  loo->add_flag("--scale-align", l->scaleAlign,
                "Scale every liver to the template's surface area before aligning and registering "
                "it (distances are still measured in the liver's own size)");
  loo->add_flag("--project", l->project,
                "Move the transferred curve to its closest points on the held-out liver's surface "
                "(as atlas transfer --project)");
  loo->add_flag("--frechet-template", l->frechetTemplate,
                "Template shape: Frechet mean of all the surfaces (eq. 4.8, started from "
                "--template; no curve enters it) instead of the --template liver itself");
  loo->add_option("--template-iterations", l->templateIterations,
                  "L-BFGS iterations of the Frechet-mean template (as atlas build)")
      ->capture_default_str();
  l->reg.add(loo);
  loo->callback([l] { runLoo(*l); });
}

}  // namespace bcassim
