// Scene files: defaults, every section turned into the model, variants, and located errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "bcassim/Error.h"
#include "bcassim/io/MeshWriter.h"
#include "bcassim/mesh/MeshGenerators.h"
#include "bcassim/scene/NodePoints.h"
#include "bcassim/scene/SceneLoader.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

using test::freshDir;
using test::writeText;

Scene load(const std::string& yaml, const std::string& dir = ".") {
  return loadSceneFromString(yaml, "scene.yaml", dir);
}

// The InputError message of loading `yaml`, or "" when it loads.
std::string loadError(const std::string& yaml, const std::string& dir = ".") {
  try {
    load(yaml, dir);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
std::string errorOf(const std::string& yaml) { return loadError(yaml); }

const char* kBox = "mesh: {generator: box, size: [0.1, 0.02, 0.02], cells: [5, 1, 1]}\n";

TEST(SceneLoader, DefaultsFillEverythingButTheMesh) {
  const Scene s = load(kBox);
  EXPECT_EQ(s.model.mesh->numNodes(), 6 * 2 * 2);
  EXPECT_EQ(s.steps, 100);
  EXPECT_DOUBLE_EQ(s.dt(), 0.01);
  EXPECT_EQ(s.integrator, IntegratorKind::ImplicitEuler);
  EXPECT_EQ(s.implicitEuler.newtonIterations, 0);
  EXPECT_EQ(s.solver.type, "cholmod");
  EXPECT_STREQ(materialName(s.model.elasticity.material(0)), "stvk");
  EXPECT_FALSE(s.model.elasticity.hasMeanDilatation());
  EXPECT_TRUE(load(std::string(kBox) + "mean_dilatation: {patch_tets: 4}")
                  .model.elasticity.hasMeanDilatation());
  EXPECT_EQ(s.output.every, 10);
  EXPECT_TRUE(s.output.pvd);
  EXPECT_TRUE(s.markers.points.empty());
  EXPECT_TRUE(s.model.springs.springs().empty());
  EXPECT_TRUE(s.model.dirichlet.empty());
  EXPECT_TRUE(s.model.gravity.isZero());
  EXPECT_EQ(s.model.mass.kind(), MassKind::Lumped);
  EXPECT_TRUE(s.variants.empty());
}

TEST(SceneLoader, CylinderGeneratorHitsTheNodeTarget) {
  const Scene s =
      load("mesh: {generator: cylinder, radius: 0.015, length: 0.18, target_nodes: 300}");
  EXPECT_NEAR(static_cast<double>(s.model.mesh->numNodes()), 300.0, 30.0);
  EXPECT_NEAR(s.model.mesh->V.col(2).maxCoeff(), 0.18, 1e-12);
}

TEST(SceneLoader, SectionsBecomeTheModel) {
  const Scene s = load(std::string(kBox) + R"(
material: {model: neohookean, young_modulus: 5000, poisson_ratio: 0.4}
density: 1100
mass: consistent
gravity: [0, 0, -9.81]
damping: {rayleigh_mass: 0.1, rayleigh_stiffness: 0.01}
time: {dt: 0.005, steps: 7}
integrator: {type: implicit-euler, newton_iterations: 2, tolerance: 1e-8}
solver: {type: factorized-pcg, refresh_every: 5, max_iterations: 30, tolerance: 1e-9,
         precision: double, refresh_in_background: true}
fixed:
  - region: {box: {min: [-1, -1, -1], max: [0.001, 1, 1]}}
    components: [x, z]
loads:
  - region: {half_space: {point: [0.099, 0, 0], normal: [1, 0, 0]}}
    total_force: [0, 0.4, 0]
    profile: {kind: square, period: 2, phase: 0.5}
output: {every: 3, pvd: false}
)");
  EXPECT_STREQ(materialName(s.model.elasticity.material(0)), "neohookean");
  EXPECT_EQ(s.model.mass.kind(), MassKind::Consistent);
  EXPECT_DOUBLE_EQ(s.model.gravity.z(), -9.81);
  EXPECT_DOUBLE_EQ(s.model.rayleighMass, 0.1);
  EXPECT_DOUBLE_EQ(s.model.rayleighStiffness, 0.01);
  EXPECT_EQ(s.steps, 7);
  EXPECT_DOUBLE_EQ(s.dt(), 0.005);
  EXPECT_EQ(s.implicitEuler.newtonIterations, 2);
  EXPECT_DOUBLE_EQ(s.implicitEuler.newtonTolerance, 1e-8);
  EXPECT_EQ(s.solver.type, "factorized-pcg");
  EXPECT_EQ(s.solver.policy.everyNMatrices, 5);
  EXPECT_EQ(s.solver.policy.maxIterations, 30);
  EXPECT_DOUBLE_EQ(s.solver.policy.relTol, 1e-9);
  EXPECT_FALSE(s.solver.policy.singlePrecision);
  EXPECT_TRUE(s.solver.policy.background);
  // 4 nodes at x = 0, x and z held: 8 dofs.
  EXPECT_EQ(s.model.dirichlet.constrainedDofs().size(), 8u);
  ASSERT_EQ(s.model.loads.size(), 1u);
  const NodalLoad& load = s.model.loads[0];
  EXPECT_EQ(load.nodes.size(), 4u);
  EXPECT_NEAR(load.forcePerNode.y() * load.nodes.size(), 0.4, 1e-15);
  EXPECT_EQ(load.profile.kind, TimeProfile::Kind::Square);
  EXPECT_DOUBLE_EQ(load.profile.period, 2.0);
  EXPECT_DOUBLE_EQ(load.profile.phase, 0.5);
  EXPECT_EQ(s.output.every, 3);
  EXPECT_FALSE(s.output.pvd);
}

TEST(SceneLoader, SurfaceDistributionSharesTheForceByArea) {
  // The end face x = 0.1 m of a 0.02 x 0.02 m box, two triangles of equal area: the two nodes on
  // their shared diagonal carry 1/3 of the force each, the other two 1/6 (an even split: 1/4).
  const Scene s = load(std::string(kBox) + R"(loads:
  - region: {half_space: {point: [0.0999, 0, 0], normal: [1, 0, 0]}}
    total_force: [0, 0.4, 0]      # N
    distribution: surface
)");
  ASSERT_EQ(s.model.loads.size(), 1u);
  const NodalLoad& load = s.model.loads[0];
  ASSERT_EQ(load.nodes.size(), 4u);
  ASSERT_EQ(load.weights.size(), 4u);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(3 * s.model.mesh->numNodes());
  load.addTo(0.0, f);
  EXPECT_NEAR(f.sum(), 0.4, 1e-12);
  std::vector<double> w = load.weights;
  std::sort(w.begin(), w.end());
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(w[k], k < 2 ? 1.0 / 6 : 1.0 / 3, 1e-12);
}

TEST(SceneLoader, SpringsAreExtrudedAlongTheOutwardNormal) {
  // Top-face nodes of the middle row (y = 0.01, z = 0.02) at x = 0.04 and 0.06 have the normal
  // +z; nodes on the box's edges lean 45 degrees and are left out by max_angle_deg.
  const Scene s = load(R"(
mesh: {generator: box, size: [0.1, 0.02, 0.02], cells: [5, 2, 2]}
springs:
  groups: [{coefficients: [1, 2, 3]}, {cut_time: 1.5}]
  attachments:
    - region: {surface_patch: {box: {min: [0.039, -1, -1], max: [0.061, 1, 1]}, direction: [0, 0, 1], max_angle_deg: 10}}
      group: 1
      length: 0.02
)");
  const CubicSpringSet& set = s.model.springs;
  ASSERT_EQ(set.numGroups(), 2);
  EXPECT_DOUBLE_EQ(set.coefficients(0).kBeta, 2.0);
  EXPECT_DOUBLE_EQ(set.coefficients(1).kGamma, 20.0);  // default coefficients [4, 7, 20]
  EXPECT_TRUE(std::isinf(set.cutTime(0)));
  EXPECT_DOUBLE_EQ(set.cutTime(1), 1.5);
  ASSERT_EQ(set.springs().size(), 2u);
  const TetMesh& mesh = *s.model.mesh;
  for (size_t k = 0; k < set.springs().size(); ++k) {
    const CubicSpring& sp = set.springs()[k];
    EXPECT_EQ(sp.group, 1);
    EXPECT_DOUBLE_EQ(sp.restLength, 0.02);
    const Vec3 attachment = set.attachment(mesh, s.model.restPositions(), k);
    EXPECT_NEAR(attachment.y(), 0.01, 1e-12);
    EXPECT_NEAR(attachment.z(), 0.02, 1e-12);
    EXPECT_NEAR((sp.anchor - (attachment + Vec3(0, 0, 0.02))).norm(), 0.0, 1e-12);
  }
}

TEST(SceneLoader, MarkersFromRegionPointsAndFile) {
  const auto dir = freshDir();
  writeText(dir / "pts.csv", "x,y,z\n0.05,0.01,0.01\n0.02,0.01,0.01\n");
  const Scene s = load(std::string(kBox) + R"(
markers:
  - region: {box: {min: [-1, -1, -1], max: [1, 1, 1]}}
    count: 3
  - points: [[0.01, 0.01, 0.01]]
  - file: pts.csv
)",
                       dir.string());
  ASSERT_EQ(s.markers.points.size(), 6u);
  ASSERT_EQ(s.markers.rest.rows(), 6);
  const TetMesh& mesh = *s.model.mesh;
  for (size_t i = 0; i < 6; ++i)
    EXPECT_NEAR((interpolate(s.markers.points[i], mesh) - s.markers.rest.row(i).transpose()).norm(),
                0.0, 1e-12)
        << "marker " << i;
  EXPECT_NEAR(s.markers.rest(5, 0), 0.02, 1e-15);
}

TEST(SceneLoader, FarthestPointSamplingSpreadsOverTheNodes) {
  TetMesh line;
  line.V.resize(5, 3);
  for (int i = 0; i < 5; ++i) line.V.row(i) << 0.1 * i, 0, 0;
  const std::vector<int> taken = farthestPointSample(line, {0, 1, 2, 3, 4}, 3);
  ASSERT_EQ(taken.size(), 3u);
  EXPECT_EQ(taken[0], 0);  // ties with node 4: the first one found
  EXPECT_EQ(taken[1], 4);
  EXPECT_EQ(taken[2], 2);
  EXPECT_EQ(farthestPointSample(line, {1, 3}, 10).size(), 2u);
}

TEST(SceneLoader, ControlPointsFollowATrajectoryFile) {
  const auto dir = freshDir();
  writeText(dir / "traj.csv", "time,dx,dy,dz\n0,0,0,0\n1,0,0.01,0\n");
  const Scene s = load(std::string(kBox) + R"(
control_points:
  - region: {nodes: [22, 23]}
    trajectory: traj.csv
    stiffness: 500
)",
                       dir.string());
  ASSERT_EQ(s.model.controls.size(), 1u);
  EXPECT_EQ(s.model.controls[0].size(), 2);
  EXPECT_NEAR(s.model.controls[0].displacementAt(0.5).y(), 0.005, 1e-15);
}

TEST(SceneLoader, MaterialsPerRegionAndModelParameters) {
  const Scene s = load(std::string(kBox) + R"(
materials:
  - {region: 0, model: mooneyrivlin, c10: 1000, c01: 200, kappa: 50000}
)");
  const auto& mr = std::get<MooneyRivlinMaterial>(s.model.elasticity.material(0));
  EXPECT_DOUBLE_EQ(mr.c10, 1000);
  EXPECT_DOUBLE_EQ(mr.c01, 200);
  EXPECT_DOUBLE_EQ(mr.kappa, 50000);
  EXPECT_EQ(errorOf(std::string(kBox) + "materials:\n  - {region: 3, model: linear}\n"),
            "scene.yaml:3: materials[0].region: the mesh has no region 3 (it has regions 0)");
}

TEST(SceneLoader, MeshFileWithRegionsScaleAndMaterialPerRegion) {
  const auto dir = freshDir();
  // A box in millimetres, region 1 for the tets of the far half.
  TetMesh mesh = makeBoxMesh(Vec3(100, 20, 20), 4, 1, 1);
  mesh.region.resize(mesh.numTets());
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t)
    mesh.region(t) = mesh.V(mesh.T(t, 0), 0) + mesh.V(mesh.T(t, 1), 0) >= 100 ? 1 : 0;
  std::filesystem::create_directories(dir / "meshes");
  writeTetMesh((dir / "meshes" / "box.vtu").string(), mesh);
  const std::string meshKey = "mesh: {file: meshes/box.vtu, scale: 0.001}\n";
  const Scene s = load(meshKey + R"(
materials:
  - {region: 1, model: linear}
  - {region: 0, model: corotational, young_modulus: 3000}
)",
                       dir.string());
  EXPECT_NEAR(s.model.mesh->V.col(0).maxCoeff(), 0.1, 1e-15);
  ASSERT_EQ(s.model.elasticity.numRegions(), 2);
  EXPECT_STREQ(materialName(s.model.elasticity.material(0)), "corotational");
  EXPECT_STREQ(materialName(s.model.elasticity.material(1)), "linear");

  EXPECT_EQ(loadError(meshKey + "materials:\n  - {region: 1}\n", dir.string()),
            "scene.yaml:3: materials: no material for mesh region 0 (the mesh has regions 0, 1)");
  writeText(dir / "meshes" / "bad.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\nx\n");
  const std::string error = loadError("mesh:\n  file: meshes/bad.msh\n", dir.string());
  EXPECT_EQ(
      error.rfind("scene.yaml:2: mesh.file: " + (dir / "meshes" / "bad.msh").string() + ":", 0), 0u)
      << error;
  EXPECT_EQ(test::countLines(error), 0);
}

TEST(SceneLoader, VariantsMergeIntoTheBase) {
  const Scene s = load(std::string(kBox) + R"(
material: {model: stvk, young_modulus: 6000}
markers: [{points: [[0.05, 0.01, 0.01]]}]
variants:
  - {name: lin, material: {model: linear}}
  - name: stiff
    material: {young_modulus: 12000}
)");
  ASSERT_EQ(s.variants.size(), 2u);
  EXPECT_EQ(s.variants[0].name, "lin");
  EXPECT_STREQ(materialName(s.variants[0].model.elasticity.material(0)), "linear");
  // young_modulus 6000 kept from the base: linear mu = E / (2 (1 + nu)) with nu = 0.49.
  EXPECT_NEAR(std::get<LinearMaterial>(s.variants[0].model.elasticity.material(0)).mu,
              6000 / (2 * 1.49), 1e-9);
  EXPECT_STREQ(materialName(s.variants[1].model.elasticity.material(0)), "stvk");
  EXPECT_TRUE(s.variants[1].variants.empty());
}

// time.min_dt: a failing step is halved down to it; dt / 64 unless set, never above dt, and the
// same fraction of a load step for statics.
TEST(SceneLoader, MinimumTimeStepDefaultsToDtOver64) {
  EXPECT_EQ(load(std::string(kBox) + "time: {dt: 0.02}").implicitEuler.minDt, 0.02 / 64);
  const Scene s =
      load(std::string(kBox) + "time: {dt: 0.02, min_dt: 0.005}\n" + "integrator: {type: static}");
  EXPECT_EQ(s.implicitEuler.minDt, 0.005);
  EXPECT_EQ(s.statics.minIncrementFraction, 0.25);
  EXPECT_EQ(errorOf(std::string(kBox) + "time: {dt: 0.01, min_dt: 0.02}"),
            "scene.yaml:2: time.min_dt: must be <= time.dt (s), got 0.02");
  EXPECT_EQ(errorOf(std::string(kBox) + "time: {min_dt: 0}"),
            "scene.yaml:2: time.min_dt: must be > 0 seconds, got 0");
}

TEST(SceneLoader, ErrorsNameLineKeyAndExpectation) {
  const std::string b = kBox;
  EXPECT_EQ(errorOf(b + "time: {dt: 0.01, step: 3}"),
            "scene.yaml:2: unknown key 'step' in time; expected one of dt, steps, min_dt");
  EXPECT_EQ(errorOf(b + "time: {steps: 2.5}"),
            "scene.yaml:2: time.steps: expected an integer, got '2.5'");
  EXPECT_EQ(errorOf(b + "time: {dt: .inf}"),
            "scene.yaml:2: time.dt: expected a number in seconds (finite), got '.inf'");
  EXPECT_EQ(errorOf(b + "gravity: [0, 0]"),
            "scene.yaml:2: gravity: expected a list of 3 numbers in m/s^2, got a list of 2");
  EXPECT_EQ(errorOf(b + "mass: heavy"),
            "scene.yaml:2: mass: expected one of lumped, consistent, got 'heavy'");
  EXPECT_EQ(errorOf(b + "solver: {type: cholmod, tolerance: 1e-6}"),
            "scene.yaml:2: solver.tolerance: only for iterative solvers");
  EXPECT_EQ(errorOf(b + "solver: {type: factorized-pcg, precision: half}"),
            "scene.yaml:2: solver.precision: expected one of single, double, got 'half'");
  EXPECT_EQ(errorOf(b + "mean_dilatation: {patch_tets: 0}"),
            "scene.yaml:2: mean_dilatation.patch_tets: must be >= 1, got 0");
  EXPECT_EQ(errorOf(b + "material: {model: corotational}\nmean_dilatation: {patch_tets: 4}"),
            "scene.yaml:3: mean_dilatation: material 'corotational' has no volumetric split for "
            "mean dilatation; expected stvk or neohookean");
  EXPECT_EQ(errorOf(b + "solver: {type: cg, precision: double}"),
            "scene.yaml:2: solver.precision: only for type factorized-pcg");
  EXPECT_EQ(
      errorOf(b +
              "fixed:\n  - region: {box: {min: [0,0,0], max: [1,1,1]}}\n    components: [x, w]"),
      "scene.yaml:4: fixed[0].components[1]: expected one of x, y, z, got 'w'");
  EXPECT_EQ(errorOf(b + "loads:\n  - region: {cube: 1}"),
            "scene.yaml:3: unknown key 'cube' in loads[0].region; expected one of box, sphere, "
            "half_space, nodes, nodes_file, surface_patch");
  EXPECT_EQ(errorOf(b + "loads:\n  - region: {sphere: {center: [0,0,0], radius: 0.001}}\n"
                        "    total_force: [1,0,0]\n    force_per_node: [1,0,0]"),
            "scene.yaml:5: loads[0].force_per_node: expected either total_force or force_per_node, "
            "not both");
  EXPECT_EQ(
      errorOf(b + "loads:\n  - region: {sphere: {center: [0.05, 0.01, 0.01], radius: 0.001}}\n"
                  "    total_force: [1,0,0]\n    distribution: surface"),
      "scene.yaml:3: loads[0].region: the region holds no part of the boundary surface; "
      "expected a region that a surface load can act on");
  EXPECT_EQ(errorOf(b + "loads:\n  - region: {nodes: [0]}\n    force_per_node: [1,0,0]\n"
                        "    distribution: surface"),
            "scene.yaml:4: loads[0].force_per_node: expected total_force with distribution: "
            "surface");
  EXPECT_EQ(errorOf(b + "springs:\n  attachments:\n    - region: {nodes: [0]}\n      group: 2"),
            "scene.yaml:5: springs.attachments[0].group: expected a group index below 1 "
            "(springs.groups), got 2");
  EXPECT_EQ(errorOf(b + "material: {model: stvk, c10: 3}"),
            "scene.yaml:2: material.c10: only for model mooneyrivlin");
  EXPECT_EQ(errorOf("mesh: {generator: box, cells: [1, 1, 1]}\nmarkers:\n  - {count: 3}"),
            "scene.yaml:3: markers[0]: expected exactly one of region, points, file");
  EXPECT_EQ(errorOf("material: {}"),
            "scene.yaml:1: missing section 'mesh' (a generator or a file)");
  EXPECT_EQ(errorOf(b + "control_points:\n  - region: {nodes: [0]}\n    trajectory: none.csv"),
            "scene.yaml:4: control_points[0].trajectory: cannot open '" +
                std::filesystem::absolute("none.csv").lexically_normal().string() + "'");
  EXPECT_EQ(errorOf(b + "markers: [{points: [[0,0,0]]}]\nvariants:\n  - {name: base}"),
            "scene.yaml:4: variants[0].name: name 'base' is used twice");
  EXPECT_EQ(
      errorOf(b + "markers: [{points: [[0,0,0]]}]\nvariants:\n  - {name: v, time: {steps: 3}}"),
      "scene.yaml:4: variants[0]: a variant must keep the base's time.dt and time.steps");
}

// An assimilation whose sigma points share worker 0's factorisation (reuse_factorization, true
// by default, with tangent: own) solves with factorized-pcg: it is the default solver then, and
// another solver.type is refused rather than swapped for it.
TEST(SceneLoader, SharedFactorizationNeedsFactorizedPcg) {
  const auto dir = freshDir();
  writeText(dir / "tracks.csv", "time,marker,x,y,z\n0,0,0.05,0.01,0.01\n");
  const std::string base = std::string(kBox) + "markers: [{points: [[0.05, 0.01, 0.01]]}]\n";
  auto assimilation = [](const std::string& keys) {
    return "assimilation:\n" + keys +
           "  parameters: [{young_modulus: {region: 0}, mean: 8000, stddev: 1000}]\n"
           "  observations: {tracks: tracks.csv}\n";
  };
  auto solverOf = [&](const std::string& yaml) { return load(yaml, dir.string()).solver.type; };
  EXPECT_EQ(solverOf(base), "cholmod");
  EXPECT_EQ(solverOf(base + assimilation("")), "factorized-pcg");
  EXPECT_EQ(solverOf(base + assimilation("  reuse_factorization: true\n")), "factorized-pcg");
  EXPECT_EQ(solverOf(base + assimilation("  reuse_factorization: false\n")), "cholmod");
  EXPECT_EQ(
      solverOf(base + "solver: {type: cg}\n" + assimilation("  reuse_factorization: false\n")),
      "cg");
  // tangent: mean: the sigma points step with the mean's own factorisation, not the solver.
  EXPECT_EQ(solverOf(base + assimilation("  tangent: mean\n")), "cholmod");
  EXPECT_EQ(solverOf(base + "solver: {type: cholmod}\n" + assimilation("  tangent: mean\n")),
            "cholmod");
  // Variants (forward runs, without the section) keep the base's solver.
  const Scene withVariant = load(
      base + assimilation("") + "variants:\n  - {name: soft, material: {young_modulus: 4000}}\n",
      dir.string());
  ASSERT_EQ(withVariant.variants.size(), 1u);
  EXPECT_EQ(withVariant.variants[0].solver.type, "factorized-pcg");

  EXPECT_EQ(
      loadError(base + "solver: {type: cholmod}\n" + assimilation("  reuse_factorization: true\n"),
                dir.string()),
      "scene.yaml:5: assimilation.reuse_factorization: needs solver.type factorized-pcg, got "
      "cholmod");
  EXPECT_EQ(loadError(base + "solver: {type: jacobi-pcg}\n" + assimilation(""), dir.string()),
            "scene.yaml:5: assimilation.reuse_factorization: needs solver.type factorized-pcg, got "
            "jacobi-pcg (true by default; false solves every sigma point with jacobi-pcg)");
  EXPECT_EQ(loadError(base + assimilation("  tangent: mean\n  reuse_factorization: false\n"),
                      dir.string()),
            "scene.yaml:5: assimilation.reuse_factorization: false does not go with tangent: mean "
            "(every sigma point steps with the mean's one factorisation)");
}

}  // namespace
}  // namespace bcassim
