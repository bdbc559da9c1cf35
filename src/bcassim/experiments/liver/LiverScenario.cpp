#include "bcassim/experiments/liver/LiverScenario.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>

#include "bcassim/Error.h"
#include "bcassim/VectorFormat.h"
#include "bcassim/experiments/liver/LiverPhantom.h"
#include "bcassim/io/MeshWriter.h"
#include "bcassim/io/PointCsvWriter.h"
#include "bcassim/io/SurfaceReader.h"
#include "bcassim/ligaments/AttachmentCurve.h"
#include "bcassim/ligaments/EsegLabels.h"
#include "bcassim/ligaments/LigamentSprings.h"
#include "bcassim/ligaments/VesselRegion.h"
#include "bcassim/mechanics/StaticSolver.h"
#include "bcassim/mechanics/solvers/LinearSolverFactory.h"
#include "bcassim/mesh/BoundarySurface.h"
#include "bcassim/mesh/ClosestPoint.h"
#include "bcassim/scene/NodePoints.h"
#include "bcassim/scene/SceneLoader.h"

namespace bcassim {
namespace {

namespace fs = std::filesystem;

// Thesis §5.1: Ogden liver (alpha 0.88, G 7.21 kPa, i.e. FEBio c = 16.47 kPa), nu 0.49.
constexpr double kTruthShear = 7210.0;  // Pa
constexpr double kTruthAlpha = 0.88;
constexpr double kTruthNu = 0.49;
constexpr double kEstimationYoung = 15000.0;  // Pa, StVK (thesis)
constexpr double kEstimationNu = 0.49;
constexpr double kDensity = 1000.0;      // kg/m^3
constexpr double kTruthSpacing = 0.002;  // m between truth springs: a dense "membrane"
constexpr int kTruthGroups = 24;         // stretches over which the truth stiffness varies
constexpr double kFixedRadius = 0.006;   // m: baseline nodes held around each attachment

Vec3 centroid(const Eigen::MatrixX3d& P) { return P.colwise().mean().transpose(); }

Vec3 unitOr(const Vec3& v, const Vec3& fallback) {
  const double n = v.norm();
  return n > 1e-12 ? Vec3(v / n) : fallback;
}

Eigen::MatrixX3d rowsOf(const Eigen::MatrixX3d& V, const std::vector<int>& ids) {
  Eigen::MatrixX3d P(static_cast<Eigen::Index>(ids.size()), 3);
  for (size_t i = 0; i < ids.size(); ++i) P.row(static_cast<Eigen::Index>(i)) = V.row(ids[i]);
  return P;
}

// The anatomical frame of the coarse mesh (see LiverAnatomy).
LiverAnatomy findAnatomy(const TetMesh& mesh, const Eigen::MatrixX3d& curve,
                         const Vec3& ligamentNormal, const Eigen::MatrixX3d* ridge) {
  LiverAnatomy a;
  double volume = 0;
  Vec3 c = Vec3::Zero();
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t) {
    Vec3 p[4];
    for (int k = 0; k < 4; ++k) p[k] = mesh.V.row(mesh.T(t, k)).transpose();
    const double v = std::abs((p[1] - p[0]).cross(p[2] - p[0]).dot(p[3] - p[0])) / 6.0;
    volume += v;
    c += v * (p[0] + p[1] + p[2] + p[3]) / 4.0;
  }
  a.center = c / volume;

  // The falciform ligament lies in the sagittal plane: that plane holds the curve's main
  // direction and the outward surface normal along it, so its normal is the lateral axis.
  const Vec3 cc = centroid(curve);
  const Eigen::MatrixX3d D = curve.rowwise() - cc.transpose();
  Eigen::SelfAdjointEigenSolver<Mat3> pca(D.transpose() * D);
  const Vec3 along = pca.eigenvectors().col(2);
  const Vec3 n = ligamentNormal.normalized();
  Vec3 lateral = unitOr(along.cross(n), pca.eigenvectors().col(0));
  // Towards the larger lobe (the right one): more volume on the positive side of the plane.
  double positive = 0;
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t) {
    Vec3 m = Vec3::Zero();
    for (int k = 0; k < 4; ++k) m += mesh.V.row(mesh.T(t, k)).transpose() / 4.0;
    positive += (m - cc).dot(lateral) > 0 ? 1.0 : -1.0;
  }
  if (positive < 0) lateral = -lateral;
  a.lateral = lateral;
  // Anterior: the way the ligament leaves the liver (to the abdominal wall), in the plane.
  a.anterior = unitOr(n - n.dot(lateral) * lateral, lateral.unitOrthogonal());
  // Superior: from the ridge (the anterior-inferior border, label 3) up to the ligament.
  Vec3 up = Vec3::Zero();
  if (ridge && ridge->rows() >= 2) {
    up = cc - centroid(*ridge);
    a.ridgeFound = true;
  }
  up -= up.dot(lateral) * lateral + up.dot(a.anterior) * a.anterior;
  a.superior = unitOr(up, lateral.cross(a.anterior));

  // Loaded regions: the far parts of each lobe along the lateral axis.
  double maxRight = 0, maxLeft = 0;
  for (Eigen::Index i = 0; i < mesh.numNodes(); ++i) {
    const double s = (mesh.V.row(i).transpose() - cc).dot(lateral);
    maxRight = std::max(maxRight, s);
    maxLeft = std::min(maxLeft, s);
  }
  Vec3 right = Vec3::Zero(), left = Vec3::Zero();
  int nr = 0, nl = 0;
  for (Eigen::Index i = 0; i < mesh.numNodes(); ++i) {
    const Vec3 p = mesh.V.row(i).transpose();
    const double s = (p - cc).dot(lateral);
    if (s > 0.6 * maxRight) right += p, ++nr;
    if (s < 0.6 * maxLeft) left += p, ++nl;
  }
  if (nr == 0 || nl == 0)
    throw InputError("liver: the falciform plane does not split the liver into two lobes");
  a.rightLoad = right / nr;
  a.leftLoad = left / nl;
  // Hilum / IVC: the porta hepatis is the deepest notch of the visceral side, so take the surface
  // point closest to the centre among those facing away from the ligament.
  const BoundarySurface boundary = extractBoundary(mesh);
  double best = std::numeric_limits<double>::infinity();
  for (int node : boundary.nodes) {
    const Vec3 p = mesh.V.row(node).transpose();
    if (boundary.vertexNormals.row(node).dot(a.anterior) >= 0) continue;
    if ((p - a.center).norm() < best) best = (p - a.center).norm(), a.hilum = p;
  }
  if (!std::isfinite(best)) a.hilum = guessHilumPoint(mesh, curve, -a.anterior);
  // Hold at least a few tets' worth of nodes, however coarse the mesh.
  while (static_cast<int>(nodesWithinRadius(mesh, a.hilum, a.vesselRadius).size()) < 12)
    a.vesselRadius *= 1.1;
  return a;
}

// Depth of each node below the boundary surface (0 on it), m.
std::vector<double> nodeDepths(const TetMesh& mesh, const BoundarySurface& boundary) {
  const SurfaceLocator locator(toTriMesh(mesh, boundary));
  std::vector<double> depth(static_cast<size_t>(mesh.numNodes()), 0.0);
  for (Eigen::Index i = 0; i < mesh.numNodes(); ++i)
    if (boundary.vertexNormals.row(i).squaredNorm() == 0)
      depth[static_cast<size_t>(i)] = locator.closest(mesh.V.row(i).transpose()).distance;
  return depth;
}

// Largest static displacement (m) of `model` (a scene's mesh, material and fixed sections) under
// `force` (N) spread over the nodes in the sphere: the loads are scaled from it so that every
// liver deforms alike whatever its size and shape.
double staticDisplacement(const std::string& model, const Vec3& center, double radius,
                          const Vec3& force, const fs::path& dir) {
  const std::string yaml =
      model + fmt::format(
                  "integrator: {{type: static}}\nloads:\n  - region: {{sphere: {{center: "
                  "{}, radius: {}}}}}\n    total_force: {}\n",
                  formatVec3(center), radius, formatVec3(force));
  const Scene scene = loadSceneFromString(yaml, "load calibration", dir.string());
  Eigen::VectorXd x = scene.model.restPositions();
  StaticSolver solver(scene.model, makeLinearSolver("cholmod"), scene.statics);
  if (!solver.solve(scene.model, 0.0, x).converged)
    throw NumericalError("liver: the load calibration did not reach equilibrium");
  return (x - scene.model.restPositions()).reshaped(3, x.size() / 3).colwise().norm().maxCoeff();
}

// Scene text shared by the three models: time, damping, vessels, loads and the points.
std::string commonScene(const LiverScenarioOptions& o, const LiverAnatomy& a, double rightForce,
                        double leftForce, const std::string& extraFixed = "") {
  const Vec3 down = -a.superior;
  std::string s;
  s += fmt::format("density: {}                                   # kg/m^3\n", kDensity);
  s += "damping: {rayleigh_mass: 1.0, rayleigh_stiffness: 0.02}   # 1/s, s\n";
  s += fmt::format("time: {{dt: {}, steps: {}}}                    # s\n", o.dt, o.steps);
  s += "fixed:                                          # vessels at the hilum / IVC\n";
  s += fmt::format("  - region: {{sphere: {{center: {}, radius: {}}}}}\n", formatVec3(a.hilum),
                   a.vesselRadius);
  s += extraFixed;
  s += "loads:                                          # right lobe: down only; left: up, down\n";
  s += fmt::format("  - region: {{sphere: {{center: {}, radius: {}}}}}\n", formatVec3(a.rightLoad),
                   a.loadRadius);
  s += fmt::format("    total_force: {}             # N at the peak\n",
                   formatVec3(rightForce * down));
  s += "    profile: {kind: half_sine, period: 4.0}    # s\n";
  s += fmt::format("  - region: {{sphere: {{center: {}, radius: {}}}}}\n", formatVec3(a.leftLoad),
                   a.loadRadius);
  s += fmt::format("    total_force: {}\n", formatVec3(-leftForce * a.anterior));
  s += "    profile: {kind: sine, period: 3.0}\n";
  s += "markers: [{file: markers.csv}]                  # observed, anterior surface\n";
  s += "validation_points: {file: validation.csv}       # inner, never observed\n";
  s += "hidden_points: {file: tumours.csv}              # tumours: predicted with uncertainty\n";
  return s;
}

}  // namespace

LiverScenario prepareLiverScenario(const LiverScenarioOptions& o, const std::string& outDir) {
  if (o.groups < 1 || o.markers < 3 || o.validationPoints < 1 || o.tumours < 0 || o.steps < 1 ||
      o.observedSteps < 0 || o.dt <= 0 || o.scale <= 0)
    throw InputError("liver: bad options (groups >= 1, markers >= 3, steps >= 1, dt > 0)");
  const fs::path dir(outDir);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw InputError(outDir + ": cannot create directory (" + ec.message() + ")");

  TriMesh surface;
  LabelledEdges edges;
  std::string name;
  double scale = o.scale;
  if (o.surface == kLiverPhantomName) {
    LiverPhantom phantom = makeLiverPhantom();
    surface = std::move(phantom.surface);
    edges = std::move(phantom.edges);
    name = kLiverPhantomName;
    scale = 1.0;  // built in metres
  } else {
    surface = readSurface(o.surface);
    const std::string esegPath =
        o.eseg.empty() ? fs::path(o.surface).replace_extension(".eseg").string() : o.eseg;
    if (!fs::exists(esegPath))
      throw InputError(esegPath + ": missing edge labels (.eseg with label 2 = falciform)");
    edges = readEseg(esegPath, surface);
    name = fs::path(o.surface).filename().string();
  }
  const Eigen::MatrixX3d curve = scale * extractAttachmentCurve(surface, edges, 2, name).points;
  Eigen::MatrixX3d ridge;
  bool hasRidge = std::find(edges.labels.begin(), edges.labels.end(), 3) != edges.labels.end();
  if (hasRidge) ridge = scale * extractAttachmentCurve(surface, edges, 3, name).points;

  LiverScenario result;
  result.dir = outDir;
  SurfaceMeshingOptions mo;
  mo.scale = scale;
  mo.targetNodes = o.coarseNodes;
  const SurfaceMeshingResult coarse = meshSurface(surface, mo, name);
  mo.targetNodes = o.fineNodes;
  const SurfaceMeshingResult fine = meshSurface(surface, mo, name);
  result.coarse = coarse.report;
  result.fine = fine.report;
  const TetMesh& mesh = coarse.mesh;

  // The estimation springs: their normals orient the anatomy; they size the prior and give the
  // baseline's fixed nodes.
  LigamentOptions lo;
  lo.length = o.ligamentLength;
  lo.numGroups = o.groups;
  const LigamentSprings est = buildLigamentSprings(mesh, curve, lo);
  result.curveLength = est.curveLength;
  const LiverAnatomy a = findAnatomy(mesh, curve, est.normals.colwise().sum().transpose(),
                                     hasRidge ? &ridge : nullptr);
  result.anatomy = a;

  // Observed markers: anterior boundary nodes away from the fixed vessels.
  const BoundarySurface boundary = extractBoundary(mesh);
  std::vector<int> anterior;
  for (int n : boundary.nodes) {
    const Vec3 p = mesh.V.row(n).transpose();
    if (boundary.vertexNormals.row(n).dot(a.anterior) > 0.5 &&
        (p - a.hilum).norm() > 2 * a.vesselRadius)
      anterior.push_back(n);
  }
  if (static_cast<int>(anterior.size()) < o.markers)
    throw InputError(fmt::format("{}: only {} anterior surface nodes for {} markers", name,
                                 anterior.size(), o.markers));
  const Eigen::MatrixX3d markers = rowsOf(mesh.V, farthestPointSample(mesh, anterior, o.markers));

  // Tumours deep inside, validation points spread over the rest of the interior.
  const std::vector<double> depth = nodeDepths(mesh, boundary);
  const double maxDepth = *std::max_element(depth.begin(), depth.end());
  std::vector<int> deep, inner;
  for (Eigen::Index i = 0; i < mesh.numNodes(); ++i) {
    const double d = depth[static_cast<size_t>(i)];
    if ((mesh.V.row(i).transpose() - a.hilum).norm() < 1.5 * a.vesselRadius) continue;
    if (d > 0.6 * maxDepth) deep.push_back(static_cast<int>(i));
    if (d > 0.3 * maxDepth) inner.push_back(static_cast<int>(i));
  }
  const std::vector<int> tumourNodes = farthestPointSample(mesh, deep, o.tumours);
  std::vector<int> rest;
  for (int n : inner)
    if (std::find(tumourNodes.begin(), tumourNodes.end(), n) == tumourNodes.end())
      rest.push_back(n);
  if (static_cast<int>(rest.size()) < o.validationPoints)
    throw InputError(fmt::format("{}: only {} inner nodes for {} validation points", name,
                                 rest.size(), o.validationPoints));
  const Eigen::MatrixX3d validation =
      rowsOf(mesh.V, farthestPointSample(mesh, rest, o.validationPoints));
  const Eigen::MatrixX3d tumours = rowsOf(mesh.V, tumourNodes);

  const double perLayer = static_cast<double>(est.springs.springs().size()) / lo.layers;
  const double estSpacing = est.curveLength / perLayer;
  std::vector<int> fixedNodes;
  for (int n : boundary.nodes)
    for (Eigen::Index s = 0; s < est.attachments.rows(); ++s)
      if ((mesh.V.row(n) - est.attachments.row(s)).norm() < kFixedRadius) {
        fixedNodes.push_back(n);
        break;
      }
  if (fixedNodes.empty()) throw InputError(name + ": no boundary node near the ligament");
  result.fixedNodes = static_cast<int>(fixedNodes.size());

  writeTetMesh((dir / "coarse.vtu").string(), coarse.mesh);
  writeTetMesh((dir / "fine.vtu").string(), fine.mesh);
  writePointsCsv((dir / "curve.csv").string(), curve);
  writePointsCsv((dir / "markers.csv").string(), markers);
  writePointsCsv((dir / "validation.csv").string(), validation);
  writePointsCsv((dir / "tumours.csv").string(), tumours);
  {
    std::ofstream f(dir / "anatomy.csv");
    f << "center_x,center_y,center_z,anterior_x,anterior_y,anterior_z,superior_x,superior_y,"
         "superior_z,lateral_x,lateral_y,lateral_z\n";
    for (const Vec3* v : {&a.center, &a.anterior, &a.superior, &a.lateral})
      f << fmt::format("{}{:.9g},{:.9g},{:.9g}", v == &a.center ? "" : ",", (*v)(0), (*v)(1),
                       (*v)(2));
    f << "\n";
  }

  // Stiffness per spring: (N/m per m of curve) x spacing / layers; cubic term from the
  // stiffening stretch e0 (ka e0^3 = kg e0).
  const double e0 = o.stiffeningStretch;
  auto perSpring = [&](double spacing) { return o.ligamentStiffness * spacing / lo.layers; };
  const std::string coarseModel = fmt::format(
      "mesh: {{file: coarse.vtu}}\nmaterial: {{model: stvk, young_modulus: {}, poisson_ratio: {}}}"
      "   # Pa, -\nsolver: {{type: factorized-pcg, tolerance: 1.0e-8}}\n",
      kEstimationYoung, kEstimationNu);
  std::string ligament = "  - region: {nodes: [";  // the baseline's ligament
  for (size_t i = 0; i < fixedNodes.size(); ++i)
    ligament += fmt::format("{}{}", i ? ", " : "", fixedNodes[i]);
  ligament += "]}\n";
  // Peak forces: given, or such that the coarse model held by the vessels alone (no ligament)
  // moves each lobe by lobeDisplacement (static, linearised by a small calibration force); the
  // ligament then holds back part of that motion.
  double rightForce = o.rightLobeForce, leftForce = o.leftLobeForce;
  if (rightForce <= 0 || leftForce <= 0) {
    const std::string held =
        coarseModel + fmt::format("fixed:\n  - region: {{sphere: {{center: {}, radius: {}}}}}\n",
                                  formatVec3(a.hilum), a.vesselRadius);
    constexpr double probe = 0.05;  // N
    if (rightForce <= 0)
      rightForce = probe * o.lobeDisplacement /
                   staticDisplacement(held, a.rightLoad, a.loadRadius, -probe * a.superior, dir);
    if (leftForce <= 0)
      leftForce = probe * o.lobeDisplacement /
                  staticDisplacement(held, a.leftLoad, a.loadRadius, -probe * a.anterior, dir);
  }
  result.rightForce = rightForce;
  result.leftForce = leftForce;
  const std::string common = commonScene(o, a, rightForce, leftForce);
  const std::string header = fmt::format(
      "# Generated by `bcassim liver prepare` from {} (thesis §5.1). Frame found from the\n"
      "# falciform curve{}: lateral (to the right lobe) {}, anterior {}, superior {}.\n",
      name, hasRidge ? " and the ridge" : "", formatVec3(a.lateral), formatVec3(a.anterior),
      formatVec3(a.superior));
  {
    std::ofstream t(dir / "truth.yaml");
    t << header
      << "# Ground truth: fine mesh, Ogden liver, dense ligament springs whose stiffness varies\n"
         "# along the curve. Run: bcassim simulate truth.yaml --out truth\n";
    t << "mesh: {file: fine.vtu}\n";
    const double kappa = 2 * kTruthShear * (1 + kTruthNu) / (3 * (1 - 2 * kTruthNu));
    t << fmt::format("material: {{model: ogden, mu: {}, alpha: {}, kappa: {:.6g}}}   # Pa, -, Pa\n",
                     kTruthShear, kTruthAlpha, kappa);
    t << "solver: {type: factorized-pcg, refresh_every: 10, tolerance: 1.0e-8}\n";
    t << "springs:\n  groups:\n";
    for (int g = 0; g < kTruthGroups; ++g) {
      const double s = (g + 0.5) / kTruthGroups;
      const double profile = 1.0 + 0.6 * std::cos(2 * std::numbers::pi * s);  // 0.4 .. 1.6
      const double kg = profile * perSpring(kTruthSpacing);
      t << fmt::format("    - {{coefficients: [{:.6g}, 0, {:.6g}]}}\n", kg / (e0 * e0), kg);
    }
    t << fmt::format("  ligament: {{curve: curve.csv, length: {}, spacing: {}, layers: 2}}\n",
                     o.ligamentLength, kTruthSpacing);
    t << common << "output: {every: 20}\n";
  }
  const double kgPrior = o.priorFactor * perSpring(estSpacing);
  const double kaKnown = perSpring(estSpacing) / (e0 * e0);
  {
    std::ofstream e(dir / "estimate.yaml");
    e << header
      << fmt::format(
             "# Estimation: coarse StVK liver, the ligament as {} springs in {} groups; ROUKF\n"
             "# estimates k_gamma of each group from the {} markers (cubic term known).\n"
             "# Run: bcassim assimilate estimate.yaml --out estimate\n",
             est.springs.springs().size(), o.groups, o.markers);
    e << coarseModel << "springs:\n  groups:\n";
    for (int g = 0; g < o.groups; ++g)
      e << fmt::format("    - {{coefficients: [{:.6g}, 0, {:.6g}]}}\n", kaKnown, kgPrior);
    e << fmt::format("  ligament: {{curve: curve.csv, length: {}, layers: 2}}\n", o.ligamentLength);
    e << common << "output: {every: 20}\n";
    e << "assimilation:\n  filter: roukf\n";
    e << fmt::format("  threads: {}\n", o.threads);
    e << "  state: {positions: true, velocities: true}\n";
    // Real time (issue 4): every sigma point steps with the elastic tangent of the analysed
    // mean and its own springs; the tangent is built every other step on a thread of its own
    // while the next step runs, so it is 1 or 2 steps old (older ones can go unstable on this
    // nearly incompressible liver, docs/liver.md).
    e << "  tangent: mean                 # own: each sigma point its own eq. 2.16 step (slower)\n"
         "  tangent_background: true\n  tangent_refresh_every: 2\n";
    e << "  parameters:\n";
    for (int g = 0; g < o.groups; ++g)
      e << fmt::format(
          "    - {{name: k_gamma_{}, spring: {{group: {}, coefficient: gamma}}, mean: {:.6g}, "
          "stddev: {:.6g}, transform: log}}\n",
          g, g, kgPrior, kgPrior);
    e << "  observations:\n    tracks: truth/markers.csv\n";
    e << fmt::format("    noise_stddev: {}                     # m\n    sigma: {}\n", o.noise,
                     std::max(o.noise, 1e-4));
    e << fmt::format("    until_step: {}\n", o.observedSteps);
    e << "  validation:\n    tracks: truth/validation.csv\n";
  }
  {
    std::ofstream b(dir / "baseline.yaml");
    b << header
      << "# Baseline (thesis §5.1 \"fixed BCs\"): the coarse liver with the ligament as fixed "
         "nodes.\n"
         "# Run: bcassim simulate baseline.yaml --out baseline\n";
    b << coarseModel << commonScene(o, a, rightForce, leftForce, ligament)
      << "output: {every: 20}\n";
  }
  return result;
}

}  // namespace bcassim
