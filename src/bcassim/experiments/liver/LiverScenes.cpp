#include "bcassim/experiments/liver/LiverScenes.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>

#include "bcassim/Error.h"
#include "bcassim/mechanics/FrozenTangent.h"
#include "bcassim/mesh/Region.h"
#include "bcassim/scene/SceneBuilders.h"

namespace bcassim {
namespace {

// The loads (thesis §5.1, as the surgeon's hand would): the right lobe pushed down only (a half
// sine, period 4 s), the left lobe up then down (a sine, period 3 s), each spread evenly over the
// nodes in its sphere.
std::vector<NodalLoad> lobeLoads(const LiverSceneSpec& spec, const TetMesh& mesh) {
  const LiverAnatomy& a = spec.anatomy;
  TimeProfile right, left;
  right.kind = TimeProfile::Kind::HalfSine;
  right.period = 4.0;
  left.kind = TimeProfile::Kind::Sine;
  left.period = 3.0;
  return {evenNodalLoad(sphereNodes(mesh, a.rightLoad, a.loadRadius, "right lobe load"),
                        spec.rightForce * -a.superior, right),
          evenNodalLoad(sphereNodes(mesh, a.leftLoad, a.loadRadius, "left lobe load"),
                        -spec.leftForce * a.anterior, left)};
}

DirichletRegion heldNodes(std::vector<int> nodes) {
  DirichletRegion d;
  d.nodes = std::move(nodes);
  return d;
}

// What the three scenes share: damping, time, the vessels held, the loads, the points, output.
// `extraFixed`: more held nodes (the baseline's ligament).
void addCommonParts(const LiverSceneSpec& spec, Scene& scene,
                    const std::vector<int>& extraFixed = {}) {
  MechanicalModel& model = scene.model;
  const TetMesh& mesh = *model.mesh;
  model.rayleighMass = spec.rayleighMass;
  model.rayleighStiffness = spec.rayleighStiffness;
  scene.implicitEuler.dt = spec.options.dt;
  scene.steps = spec.options.steps;
  scene.solver.type = "factorized-pcg";
  scene.solver.policy.relTol = spec.solverTolerance;
  std::vector<DirichletRegion> fixed = {heldNodes(
      sphereNodes(mesh, spec.anatomy.hilum, spec.anatomy.vesselRadius, "vessels (hilum / IVC)"))};
  if (!extraFixed.empty())
    fixed.push_back(heldNodes(selectNodes(mesh, IndexListRegion{extraFixed})));
  model.dirichlet = DirichletConditions(std::move(fixed), *model.pattern);
  model.loads = lobeLoads(spec, mesh);
  scene.markers = mappedPointSet(mesh, spec.markers);
  scene.validation = mappedPointSet(mesh, spec.validation);
  scene.hidden = mappedPointSet(mesh, spec.tumours);
  scene.output.every = spec.outputEvery;
}

LigamentOptions ligamentOptions(const LiverSceneSpec& spec, double spacing) {
  LigamentOptions o;
  o.length = spec.options.ligamentLength;
  o.spacing = spacing;
  o.layers = 2;
  return o;
}

}  // namespace

OgdenMaterial LiverSceneSpec::truthMaterial() const {
  const double kappa = 2 * truthShear * (1 + truthPoisson) / (3 * (1 - 2 * truthPoisson));
  return {truthShear, truthAlpha, kappa};
}

double LiverSceneSpec::observationSigma() const { return std::max(options.noise, 1e-4); }

std::string LiverSceneSpec::scenePath(const std::string& file) const {
  return (std::filesystem::path(dir) / file).string();
}

std::vector<int> sphereNodes(const TetMesh& mesh, const Vec3& center, double radius,
                             const std::string& what) {
  std::vector<int> nodes = selectNodes(mesh, SphereRegion{center, radius});
  if (nodes.empty())
    throw InputError(
        fmt::format("liver: the {} sphere (radius {:.3g} m) holds no mesh node", what, radius));
  return nodes;
}

MechanicalModel makeCoarseLiverModel(const LiverSceneSpec& spec) {
  return makeMechanicalModel(spec.coarse,
                             {makeMaterial("stvk", spec.estimationYoung, spec.estimationPoisson)},
                             spec.density, MassKind::Lumped);
}

Scene makeLiverTruthScene(const LiverSceneSpec& spec) {
  Scene scene(
      makeMechanicalModel(spec.fine, {spec.truthMaterial()}, spec.density, MassKind::Lumped));
  scene.sourceFile = spec.scenePath("truth.yaml");
  addCommonParts(spec, scene);
  scene.solver.policy.everyNMatrices = spec.truthRefreshEvery;
  const int groups = static_cast<int>(spec.truthGroups.size());
  scene.model.springs = CubicSpringSet(
      ligamentSprings(*spec.fine, spec.curve, ligamentOptions(spec, spec.truthSpacing), groups),
      spec.truthGroups);
  return scene;
}

Scene makeLiverEstimationScene(const LiverSceneSpec& spec) {
  Scene scene(makeCoarseLiverModel(spec));
  scene.sourceFile = spec.scenePath("estimate.yaml");
  addCommonParts(spec, scene);
  const int groups = static_cast<int>(spec.estimationGroups.size());
  // Spacing 0: the mean boundary edge length of the coarse mesh.
  LigamentOptions lo = ligamentOptions(spec, 0.0);
  lo.bandLower = spec.springBandLower;
  lo.bandUpper = spec.springBandUpper;
  scene.model.springs = CubicSpringSet(ligamentSprings(*spec.coarse, spec.springCurve, lo, groups),
                                       spec.estimationGroups);
  const size_t springs = scene.model.springs.springs().size();
  if (springs > static_cast<size_t>(FrozenTangent::kMaxCorrectedSprings))
    throw InputError(fmt::format(
        "liver: {} estimation springs; tangent: mean corrects at most {} (fewer, coarser springs)",
        springs, FrozenTangent::kMaxCorrectedSprings));

  // ROUKF estimates k_gamma of each group (the cubic term known) from the markers. Real time
  // (issue 4): every sigma point steps with the elastic tangent of the analysed mean and its own
  // springs; the tangent is built every other step on a thread of its own while the next step
  // runs, so it is 1 or 2 steps old (5-7 steps made this nearly incompressible liver go unstable;
  // adopted two steps later, 2-3 steps old, it cut the steps' tail but two livers' full-size
  // estimates got worse over five noise seeds: docs/liver.md, "How old a tangent may be").
  AssimilationSettings s;
  s.filter = FilterKind::Roukf;
  s.threads = spec.options.threads;
  s.carryPositions = true;
  s.carryVelocities = true;
  s.meanTangent = true;
  s.tangentInBackground = true;
  s.tangentRefreshEvery = 2;
  // Solves with the factor in float: ~40 % less solve time; on LiTS-3 the hidden points within
  // 4e-8 m and the validation error to 1e-5 mm of the double solves' (docs/benchmarks.md §7).
  s.tangentSinglePrecision = true;
  // Log space bounded smoothly (bounded-log, centred on the prior) with a random walk: see
  // LiverSceneSpec::stiffnessLower and LiverScenarioOptions::stiffnessRandomWalk.
  for (int g = 0; g < groups; ++g) {
    EstimatedParameter p = springParameter(
        g, 2, spec.priorStiffness, spec.priorStddev,
        ParameterTransform::boundedLog(spec.stiffnessLower(), spec.stiffnessUpper()));
    p.randomWalkPerStep = spec.stiffnessRandomWalk() * std::sqrt(spec.options.dt);
    s.parameters.push_back(p);
  }
  s.observations.noiseStddev = spec.options.noise;
  s.observations.sigma = spec.observationSigma();
  s.observations.untilStep = spec.options.observedSteps;
  scene.assimilation = std::move(s);
  return scene;
}

Scene makeLiverBaselineScene(const LiverSceneSpec& spec) {
  Scene scene(makeCoarseLiverModel(spec));
  scene.sourceFile = spec.scenePath("baseline.yaml");
  addCommonParts(spec, scene, spec.ligamentNodes);
  return scene;
}

Scene withTruthTracks(Scene estimation, const std::string& truthDir) {
  const std::filesystem::path dir(truthDir);
  AssimilationSettings& s = estimation.assimilation.value();
  s.observations.tracks = readStepFrames(
      (dir / "markers.csv").string(), static_cast<int>(estimation.markers.points.size()), "markers",
      estimation.dt(), estimation.steps, s.observations.timeOffset);
  s.validationTruth = readStepFrames(
      (dir / "validation.csv").string(), static_cast<int>(estimation.validation.points.size()),
      "validation points", estimation.dt(), estimation.steps, s.observations.timeOffset);
  return estimation;
}

}  // namespace bcassim
