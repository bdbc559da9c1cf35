#include "bcassim/experiments/liver/LiverScenario.h"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <optional>

#include "bcassim/Error.h"
#include "bcassim/experiments/liver/AtlasCurve.h"
#include "bcassim/experiments/liver/LiverPhantom.h"
#include "bcassim/experiments/liver/LiverSceneFiles.h"
#include "bcassim/experiments/liver/LiverScenes.h"
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
#include "bcassim/scene/LigamentSpringPriors.h"
#include "bcassim/scene/NodePoints.h"
#include "bcassim/scene/SceneBuilders.h"

namespace bcassim {
namespace {

namespace fs = std::filesystem;

constexpr int kTruthGroups = 24;        // stretches over which the truth stiffness varies
constexpr double kFixedRadius = 0.006;  // m: baseline nodes held around each attachment

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

// Largest static displacement (m) of the coarse liver held by the vessels alone (no ligament)
// under `force` (N) spread over the nodes in the sphere: the loads are scaled from it so that
// every liver deforms alike whatever its size and shape.
double staticDisplacement(const LiverSceneSpec& spec, const Vec3& center, double radius,
                          const Vec3& force) {
  MechanicalModel model = makeCoarseLiverModel(spec);
  DirichletRegion vessels;
  vessels.nodes = sphereNodes(*model.mesh, spec.anatomy.hilum, spec.anatomy.vesselRadius,
                              "vessels (hilum / IVC)");
  model.dirichlet = DirichletConditions({vessels}, *model.pattern);
  model.loads = {evenNodalLoad(sphereNodes(*model.mesh, center, radius, "calibration load"), force,
                               TimeProfile{})};
  Eigen::VectorXd x = model.restPositions();
  StaticSolver solver(model, makeLinearSolver("cholmod"), StaticOptions{});
  if (!solver.solve(model, 0.0, x).converged)
    throw NumericalError("liver: the load calibration did not reach equilibrium");
  return (x - model.restPositions()).reshaped(3, x.size() / 3).colwise().norm().maxCoeff();
}

}  // namespace

LiverSceneSpec prepareLiverSceneSpec(const LiverScenarioOptions& o, const std::string& outDir,
                                     LiverScenario& result,
                                     const std::function<void(const std::string&)>& log) {
  if (o.groups < 1 || o.markers < 3 || o.validationPoints < 1 || o.tumours < 0 || o.steps < 1 ||
      o.observedSteps < 0 || o.dt <= 0 || o.scale <= 0 || !(o.stiffnessRandomWalk >= 0) ||
      !(o.priorSpread >= 0) || (o.springPriors.empty() && !(o.priorSpread > 0)))
    throw InputError(
        "liver: bad options (groups >= 1, markers >= 3, steps >= 1, dt > 0, stiffness random walk "
        ">= 0, prior spread > 0, or >= 0 with spring priors)");
  const fs::path dir(outDir);
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw OutputError(outDir + ": cannot create directory (" + ec.message() + ")");

  // Read first: a bad file is reported before minutes of meshing and atlas transfer.
  std::optional<LigamentSpringPriors> priors;
  if (!o.springPriors.empty()) priors = readLigamentSpringPriors(o.springPriors);

  TriMesh surface;
  LabelledEdges edges;
  std::string name;
  double scale = o.scale;
  const bool atlasMode = !o.atlas.empty() || !o.atlasLivers.empty();
  if (o.atlasBand && !atlasMode)
    throw InputError(
        "liver: --atlas-band spreads the springs over an atlas' band; it needs "
        "--atlas (or --atlas-livers)");
  bool annotated = true;
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
    name = fs::path(o.surface).filename().string();
    if (fs::exists(esegPath))
      edges = readEseg(esegPath, surface);
    else if (atlasMode)
      annotated = false;
    else
      throw InputError(esegPath +
                       ": missing edge labels (.eseg with label 2 = falciform); a liver without "
                       "them needs an atlas (--atlas)");
  }

  // The springs' curve: the atlas' mean curve transferred onto this liver, or the annotation.
  Eigen::MatrixX3d springCurve, bandLower, bandUpper;
  if (atlasMode) {
    TriMesh patient = surface;
    patient.V *= scale;
    AtlasCurve transferred;
    if (o.atlasLivers.empty()) {
      transferred = transferredAtlasCurve(patient, o.atlas, o.atlasTransferIterations);
      result.atlas.source = o.atlas;
    } else {
      LeftOutAtlasOptions ao;
      ao.liverDir = o.atlasLivers;
      ao.scale = o.scale;
      ao.exclude = fs::path(o.surface).stem().string();
      ao.cacheDir = o.atlas.empty() ? (fs::path(outDir) / "atlas").string() : o.atlas;
      ao.transferIterations = o.atlasTransferIterations;
      transferred = leftOutAtlasCurve(patient, ao, log);
      result.atlas.source = fmt::format("{} without {}", ao.liverDir, ao.exclude);
    }
    for (const std::string& doubt : transferred.poseDoubts)
      if (log) log(fmt::format("atlas transfer onto {}: {}", name, doubt));
    springCurve = transferred.curve;
    if (o.atlasBand) {
      bandLower = transferred.lower;
      bandUpper = transferred.upper;
    }
    result.atlas.used = true;
    result.atlas.band = o.atlasBand;
    result.atlas.rotationDegrees = transferred.rotationDegrees;
    result.atlas.buildSeconds = transferred.buildSeconds;
    result.atlas.transferSeconds = transferred.transferSeconds;
    result.atlas.meanSigma = transferred.sigma.size() > 0 ? transferred.sigma.mean() : 0.0;
  }
  result.annotated = annotated;
  // The truth's ligament: the expert's curve, or the atlas' on a liver without annotation.
  const Eigen::MatrixX3d curve =
      annotated ? Eigen::MatrixX3d(scale * extractAttachmentCurve(surface, edges, 2, name).points)
                : springCurve;
  if (!atlasMode) springCurve = curve;
  if (atlasMode && annotated) {
    const std::vector<double> d = distancesToPolyline(springCurve, curve);
    result.atlas.expertDistanceMax = *std::max_element(d.begin(), d.end());
    result.atlas.expertDistanceMean = 0;
    for (double x : d) result.atlas.expertDistanceMean += x / static_cast<double>(d.size());
  }
  Eigen::MatrixX3d ridge;
  bool hasRidge = std::find(edges.labels.begin(), edges.labels.end(), 3) != edges.labels.end();
  if (hasRidge) ridge = scale * extractAttachmentCurve(surface, edges, 3, name).points;

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

  // The estimation springs size the prior and give the baseline's fixed nodes. The anatomy (the
  // synthetic experiment's loads and points) comes from the truth's ligament, so that atlas and
  // annotation modes face the same scenario.
  LigamentOptions lo;
  lo.length = o.ligamentLength;
  lo.numGroups = o.groups;
  // On the mean curve: the baseline's fixed nodes and the anatomy follow it. With the band the
  // estimation's springs sit on its edges (LiverScenes.cpp builds them), but with these samples,
  // groups and count, so these size their stiffness too.
  const LigamentSprings onCurve = buildLigamentSprings(mesh, springCurve, lo);
  result.curveLength = onCurve.curveLength;
  const Vec3 truthNormal =
      atlasMode ? buildLigamentSprings(mesh, curve, lo).normals.colwise().sum().transpose()
                : Vec3(onCurve.normals.colwise().sum().transpose());
  const LiverAnatomy a = findAnatomy(mesh, curve, truthNormal, hasRidge ? &ridge : nullptr);
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

  const double perLayer = static_cast<double>(onCurve.springs.springs().size()) / lo.layers;
  const double estSpacing = onCurve.curveLength / perLayer;
  std::vector<int> fixedNodes;
  for (int n : boundary.nodes)
    for (Eigen::Index s = 0; s < onCurve.attachments.rows(); ++s)
      if ((mesh.V.row(n) - onCurve.attachments.row(s)).norm() < kFixedRadius) {
        fixedNodes.push_back(n);
        break;
      }
  if (fixedNodes.empty()) throw InputError(name + ": no boundary node near the ligament");
  result.fixedNodes = static_cast<int>(fixedNodes.size());

  writeTetMesh((dir / "coarse.vtu").string(), coarse.mesh);
  writeTetMesh((dir / "fine.vtu").string(), fine.mesh);
  writePointsCsv((dir / "curve.csv").string(), curve);
  if (atlasMode) writePointsCsv((dir / "spring_curve.csv").string(), springCurve);
  if (o.atlasBand) {
    writePointsCsv((dir / kSpringBandLowerFile).string(), bandLower);
    writePointsCsv((dir / kSpringBandUpperFile).string(), bandUpper);
  }
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

  LiverSceneSpec spec;
  spec.options = o;
  spec.dir = outDir;
  spec.sourceName = name;
  spec.anatomy = a;
  spec.fine = std::make_shared<const TetMesh>(fine.mesh);
  spec.coarse = std::make_shared<const TetMesh>(coarse.mesh);
  spec.curve = curve;
  spec.springCurve = springCurve;
  if (atlasMode) spec.springCurveFile = "spring_curve.csv";
  spec.springBandLower = bandLower;
  spec.springBandUpper = bandUpper;
  spec.markers = markers;
  spec.validation = validation;
  spec.tumours = tumours;
  spec.ligamentNodes = fixedNodes;
  spec.estimationSprings = static_cast<int>(onCurve.springs.springs().size());
  // Stiffness per spring: (N/m per m of curve) x spacing / layers; cubic term from the
  // stiffening stretch e0 (ka e0^3 = kg e0).
  const double e0 = o.stiffeningStretch;
  auto perSpring = [&](double spacing) { return o.ligamentStiffness * spacing / lo.layers; };
  for (int g = 0; g < kTruthGroups; ++g) {
    const double s = (g + 0.5) / kTruthGroups;
    const double profile = 1.0 + 0.6 * std::cos(2 * std::numbers::pi * s);  // 0.4 .. 1.6
    const double kg = profile * perSpring(spec.truthSpacing);
    spec.truthGroups.push_back({kg / (e0 * e0), 0.0, kg});
  }
  if (o.springPriors.empty()) {
    spec.priorStiffness = o.priorFactor * perSpring(estSpacing);
    spec.priorStddev = o.priorSpread * spec.priorStiffness;
    spec.estimationGroups.assign(
        static_cast<size_t>(o.groups),
        CubicSpringCoefficients{perSpring(estSpacing) / (e0 * e0), 0.0, spec.priorStiffness});
  } else {
    // A spring stands for `estSpacing` of curve, shared between the layers.
    const LigamentSpringPriors p = priors->forRestLength(o.ligamentLength);
    const double share = estSpacing / lo.layers;
    spec.priorStiffness = p.kGamma.mean * share;
    spec.priorStddev = std::hypot(p.kGamma.stddev, o.priorSpread * p.kGamma.mean) * share;
    spec.estimationGroups.assign(
        static_cast<size_t>(o.groups),
        CubicSpringCoefficients{p.kAlpha.mean * share, p.kBeta.mean * share, spec.priorStiffness});
  }
  result.priorStiffness = spec.priorStiffness;
  result.priorStddev = spec.priorStddev;

  // Peak forces: given, or such that the coarse model held by the vessels alone (no ligament)
  // moves each lobe by lobeDisplacement (static, linearised by a small calibration force); the
  // ligament then holds back part of that motion.
  spec.rightForce = o.rightLobeForce;
  spec.leftForce = o.leftLobeForce;
  constexpr double probe = 0.05;  // N
  if (spec.rightForce <= 0 || spec.leftForce <= 0) {
    if (spec.rightForce <= 0)
      spec.rightForce = probe * o.lobeDisplacement /
                        staticDisplacement(spec, a.rightLoad, a.loadRadius, -probe * a.superior);
    if (spec.leftForce <= 0)
      spec.leftForce = probe * o.lobeDisplacement /
                       staticDisplacement(spec, a.leftLoad, a.loadRadius, -probe * a.anterior);
  }
  result.rightForce = spec.rightForce;
  result.leftForce = spec.leftForce;
  return spec;
}

LiverScenario prepareLiverScenario(const LiverScenarioOptions& o, const std::string& outDir,
                                   const std::function<void(const std::string&)>& log) {
  LiverScenario result;
  const LiverSceneSpec spec = prepareLiverSceneSpec(o, outDir, result, log);
  result.truthScene = std::make_shared<const Scene>(makeLiverTruthScene(spec));
  result.estimateScene = std::make_shared<const Scene>(makeLiverEstimationScene(spec));
  result.baselineScene = std::make_shared<const Scene>(makeLiverBaselineScene(spec));
  writeLiverSceneFiles(spec);
  return result;
}

}  // namespace bcassim
