#include "bcassim/scene/SceneLoader.h"

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include "bcassim/Error.h"
#include "bcassim/io/CsvTable.h"
#include "bcassim/io/CsvTracks.h"
#include "bcassim/io/MeshReader.h"
#include "bcassim/io/PointReader.h"
#include "bcassim/io/TextLines.h"
#include "bcassim/ligaments/LigamentSprings.h"
#include "bcassim/mesh/BoundarySurface.h"
#include "bcassim/mesh/MeshGenerators.h"
#include "bcassim/mesh/SurfaceTraction.h"
#include "bcassim/scene/AssimilationSettingsReader.h"
#include "bcassim/scene/NodePoints.h"
#include "bcassim/scene/RegionReader.h"
#include "bcassim/scene/SceneBuilders.h"
#include "bcassim/scene/YamlReader.h"

namespace bcassim {

namespace {

using yamlio::failAt;
using yamlio::listElements;
using yamlio::MapReader;
using yamlio::Range;
using yamlio::YamlSource;

std::string indexed(const std::string& path, size_t i) {
  return path + "[" + std::to_string(i) + "]";
}

// Scene defaults, documented in docs/scene-format.md.
constexpr double kDefaultYoungModulus = 8000.0;  // Pa, thesis cylinder
constexpr double kDefaultPoissonRatio = 0.49;
constexpr double kDefaultSpringLength = 0.03;  // m, thesis ligament springs
const CubicSpringCoefficients kDefaultSpringCoefficients{4.0, 7.0, 20.0};  // thesis cylinder truth

std::shared_ptr<const TetMesh> readMesh(const YamlSource& src, const MapReader& top,
                                        const SceneLimits& limits) {
  if (!top.has("mesh"))
    failAt(src, top.self(), "", "missing section 'mesh' (a generator or a file)");
  MapReader m(src, top.node("mesh"), "mesh",
              {"generator", "radius", "length", "target_nodes", "size", "cells", "target_tets",
               "file", "region_field", "scale", "max_nodes"});
  auto mesh = std::make_shared<TetMesh>();
  if (m.has("file")) {
    if (m.has("generator")) m.fail("generator", "expected either a generator or a file, not both");
    for (const char* k :
         {"radius", "length", "target_nodes", "size", "cells", "target_tets", "max_nodes"})
      m.rejectUnless(false, k, "a generated mesh (mesh.generator)");
    const std::string path = m.existingFile("file");
    const std::string field = m.text("region_field", "");
    const double scale = m.number("scale", 1.0, "m per file unit", Range::Positive);
    yamlio::withContext(src, m.node("file"), "mesh.file",
                        [&] { *mesh = readTetMesh(path, field); });
    mesh->V *= scale;
    return mesh;
  }
  if (!m.has("generator"))
    failAt(src, m.self(), "mesh", "expected a generator (cylinder, box) or a file");
  const std::string generator = m.choice("generator", "box", {"cylinder", "box"});
  m.rejectUnless(false, "region_field", "a mesh read from a file (mesh.file)");
  m.rejectUnless(false, "scale", "a mesh read from a file (mesh.file)");
  const bool cylinder = generator == "cylinder";
  for (const char* k : {"radius", "length", "target_nodes"})
    m.rejectUnless(cylinder, k, "generator cylinder");
  for (const char* k : {"size", "cells", "target_tets"})
    m.rejectUnless(!cylinder, k, "generator box");
  // Parameters are read (and their errors located) first; the generators only add their own.
  // A size beyond max_nodes is refused before any work: a typo must not run out of memory.
  const int maxNodes = m.integer("max_nodes", limits.maxGeneratedNodes, Range::AtLeastOne);
  const auto beyondMaxNodes = [&](const char* key, long long nodes, const std::string& asked) {
    if (nodes > maxNodes)
      m.fail(key, fmt::format("{}; expected at most {} nodes (mesh.max_nodes)", asked, maxNodes));
  };
  if (cylinder) {
    const double radius = m.number("radius", 0.015, "m", Range::Positive);
    const double length = m.number("length", 0.18, "m", Range::Positive);
    const int nodes = m.integer("target_nodes", 915, Range::AtLeastOne);
    beyondMaxNodes("target_nodes", nodes, fmt::format("{} nodes asked", nodes));
    yamlio::withContext(src, m.node("generator"), "mesh",
                        [&] { *mesh = makeCylinderMesh(radius, length, nodes); });
    return mesh;
  }
  const Vec3 size = m.vec3("size", Vec3(0.15, 0.03, 0.03), "m", Range::Positive);
  if (m.has("target_tets")) {
    if (m.has("cells")) m.fail("cells", "expected either cells or target_tets, not both");
    const int tets = m.integer("target_tets", 0, Range::AtLeastOne);
    // 6 tets per hexahedron, at least one node per hexahedron.
    beyondMaxNodes("target_tets", tets / 6,
                   fmt::format("{} tets make at least {} nodes", tets, tets / 6));
    yamlio::withContext(src, m.node("generator"), "mesh",
                        [&] { *mesh = makeBoxMeshWithTargetTets(size, tets); });
    return mesh;
  }
  int cells[3] = {20, 4, 4};
  if (m.has("cells")) {
    const YAML::Node c = m.node("cells");
    if (!c.IsSequence() || c.size() != 3)
      m.fail("cells",
             "expected a list of 3 integers (hexahedra along x, y, z), got " + yamlio::describe(c));
    for (int i = 0; i < 3; ++i)
      cells[i] = yamlio::parseInteger(src, c[i], indexed("mesh.cells", i), Range::AtLeastOne);
  }
  const long long boxNodes = (cells[0] + 1LL) * (cells[1] + 1LL) * (cells[2] + 1LL);
  beyondMaxNodes(
      "cells", boxNodes,
      fmt::format("{} x {} x {} cells make {} nodes", cells[0], cells[1], cells[2], boxNodes));
  yamlio::withContext(src, m.node("generator"), "mesh",
                      [&] { *mesh = makeBoxMesh(size, cells[0], cells[1], cells[2]); });
  return mesh;
}

// One material map; `inList` allows the key region (materials: list).
Material readMaterial(const YamlSource& src, const YAML::Node& node, const std::string& path,
                      bool inList) {
  std::vector<std::string> keys = {"model", "young_modulus", "poisson_ratio", "c10", "c01", "kappa",
                                   "mu",    "alpha"};
  if (inList) keys.insert(keys.begin(), "region");
  MapReader r(src, node, path, keys);
  const std::string model = r.choice(
      "model", "stvk", {"linear", "corotational", "stvk", "neohookean", "mooneyrivlin", "ogden"});
  const double E = r.number("young_modulus", kDefaultYoungModulus, "Pa", Range::Positive);
  const double nu = r.number("poisson_ratio", kDefaultPoissonRatio, "-");
  if (!(nu > -1.0 && nu < 0.5))
    r.fail("poisson_ratio", "must be in (-1, 0.5), got " + r.node("poisson_ratio").Scalar());
  for (const char* k : {"c10", "c01"})
    r.rejectUnless(model == "mooneyrivlin", k, "model mooneyrivlin");
  for (const char* k : {"mu", "alpha"}) r.rejectUnless(model == "ogden", k, "model ogden");
  r.rejectUnless(model == "mooneyrivlin" || model == "ogden", "kappa",
                 "models mooneyrivlin and ogden");
  Material material;
  yamlio::withContext(src, node, path, [&] { material = makeMaterial(model, E, nu); });
  if (auto* mr = std::get_if<MooneyRivlinMaterial>(&material)) {
    mr->c10 = r.number("c10", mr->c10, "Pa", Range::NonNegative);
    mr->c01 = r.number("c01", mr->c01, "Pa", Range::NonNegative);
    mr->kappa = r.number("kappa", mr->kappa, "Pa", Range::Positive);
  } else if (auto* og = std::get_if<OgdenMaterial>(&material)) {
    og->mu = r.number("mu", og->mu, "Pa", Range::Positive);
    og->alpha = r.number("alpha", og->alpha, "-");
    if (og->alpha == 0) r.fail("alpha", "must not be 0");
    og->kappa = r.number("kappa", og->kappa, "Pa", Range::Positive);
  }
  return material;
}

std::vector<Material> readMaterials(const YamlSource& src, const MapReader& top,
                                    const TetMesh& mesh) {
  if (top.has("material") && top.has("materials"))
    top.fail("materials", "expected either material (one for all tets) or materials, not both");
  if (!top.has("materials")) return {readMaterial(src, top.node("material"), "material", false)};
  std::set<int> meshRegions;
  for (Eigen::Index t = 0; t < mesh.numTets(); ++t) meshRegions.insert(mesh.regionOf(t));
  std::string ids;
  for (int id : meshRegions) ids += (ids.empty() ? "" : ", ") + std::to_string(id);
  std::map<int, Material> byRegion;
  const auto entries = listElements(src, top.node("materials"), "materials");
  for (size_t i = 0; i < entries.size(); ++i) {
    const std::string path = indexed("materials", i);
    MapReader e(src, entries[i], path,
                {"region", "model", "young_modulus", "poisson_ratio", "c10", "c01", "kappa", "mu",
                 "alpha"});
    if (!e.has("region")) failAt(src, entries[i], path, "missing key 'region' (mesh region id)");
    const int region = e.integer("region", 0);
    if (!meshRegions.count(region))
      e.fail("region",
             "the mesh has no region " + std::to_string(region) + " (it has regions " + ids + ")");
    if (byRegion.count(region))
      e.fail("region", "region " + std::to_string(region) + " given twice");
    byRegion.emplace(region, readMaterial(src, entries[i], path, true));
  }
  if (byRegion.empty()) top.fail("materials", "expected at least one material");
  for (int r : meshRegions)
    if (!byRegion.count(r))
      top.fail("materials", "no material for mesh region " + std::to_string(r) +
                                " (the mesh has regions " + ids + ")");
  std::vector<Material> materials(byRegion.rbegin()->first + 1, byRegion.begin()->second);
  for (const auto& [region, material] : byRegion) materials[region] = material;
  return materials;
}

TimeProfile readProfile(const YamlSource& src, const YAML::Node& node, const std::string& path) {
  MapReader r(src, node, path, {"kind", "period", "phase"});
  static const std::vector<std::pair<std::string, TimeProfile::Kind>> kinds = {
      {"constant", TimeProfile::Kind::Constant},  {"sine", TimeProfile::Kind::Sine},
      {"square", TimeProfile::Kind::Square},      {"pulse", TimeProfile::Kind::Pulse},
      {"half_sine", TimeProfile::Kind::HalfSine}, {"ramp", TimeProfile::Kind::Ramp}};
  std::vector<std::string> names;
  names.reserve(kinds.size());
  for (const auto& k : kinds) names.push_back(k.first);
  const std::string kind = r.choice("kind", "constant", names);
  TimeProfile profile;
  for (const auto& k : kinds)
    if (k.first == kind) profile.kind = k.second;
  profile.period = r.number("period", 1.0, "s", Range::Positive);
  profile.phase = r.number("phase", 0.0, "s");
  return profile;
}

std::vector<int> requiredRegion(const YamlSource& src, const MapReader& r, const TetMesh& mesh) {
  if (!r.has("region")) failAt(src, r.self(), r.pathOf("region"), "missing (which nodes)");
  return yamlio::selectRegionNodes(src, r.node("region"), r.pathOf("region"), mesh);
}

DirichletConditions readFixed(const YamlSource& src, const MapReader& top,
                              const MechanicalModel& model) {
  std::vector<DirichletRegion> regions;
  const auto entries = listElements(src, top.node("fixed"), "fixed");
  for (size_t i = 0; i < entries.size(); ++i) {
    MapReader r(src, entries[i], indexed("fixed", i),
                {"region", "displacement", "components", "profile"});
    DirichletRegion d;
    d.nodes = requiredRegion(src, r, *model.mesh);
    d.displacement = r.vec3("displacement", Vec3::Zero(), "m");
    d.profile = readProfile(src, r.node("profile"), r.pathOf("profile"));
    if (r.has("components")) {
      d.components = {false, false, false};
      const auto comps = listElements(src, r.node("components"), r.pathOf("components"));
      if (comps.empty()) r.fail("components", "expected a non-empty list of x, y, z");
      for (size_t c = 0; c < comps.size(); ++c) {
        const std::string s = comps[c].IsScalar() ? comps[c].Scalar() : "";
        if (s != "x" && s != "y" && s != "z")
          failAt(src, comps[c], indexed(r.pathOf("components"), c),
                 "expected one of x, y, z, got " + yamlio::describe(comps[c]));
        d.components[s[0] - 'x'] = true;
      }
    }
    regions.push_back(std::move(d));
  }
  return DirichletConditions(std::move(regions), *model.pattern);
}

// loads[].total_force_frames: one row (fx fy fz, N) per step, as readPoints reads points.
std::vector<Vec3> readForceFrames(const YamlSource& src, const MapReader& r) {
  const std::string file = r.existingFile("total_force_frames");
  Eigen::MatrixX3d F;
  yamlio::withContext(src, r.node("total_force_frames"), r.pathOf("total_force_frames"),
                      [&] { F = readPoints(file); });
  std::vector<Vec3> frames(static_cast<size_t>(F.rows()));
  for (Eigen::Index k = 0; k < F.rows(); ++k) frames[static_cast<size_t>(k)] = F.row(k);
  return frames;
}

std::vector<NodalLoad> readLoads(const YamlSource& src, const MapReader& top, const TetMesh& mesh,
                                 double dt) {
  std::vector<NodalLoad> loads;
  const auto entries = listElements(src, top.node("loads"), "loads");
  for (size_t i = 0; i < entries.size(); ++i) {
    MapReader r(src, entries[i], indexed("loads", i),
                {"region", "total_force", "total_force_frames", "force_per_node", "distribution",
                 "profile"});
    NodalLoad load;
    if (r.has("total_force") && r.has("force_per_node"))
      r.fail("force_per_node", "expected either total_force or force_per_node, not both");
    for (const char* other : {"total_force", "force_per_node"})
      if (r.has("total_force_frames") && r.has(other))
        r.fail(other, "expected either total_force_frames or " + std::string(other) + ", not both");
    const std::string distribution = r.choice("distribution", "nodes", {"nodes", "surface"});
    if (distribution == "surface") {
      if (r.has("force_per_node"))
        r.fail("force_per_node", "expected total_force with distribution: surface");
      if (!r.has("region")) failAt(src, r.self(), r.pathOf("region"), "missing (which surface)");
      const Region region = yamlio::parseRegion(src, r.node("region"), r.pathOf("region"));
      SurfaceTractionShares traction;
      yamlio::withContext(src, r.node("region"), r.pathOf("region"),
                          [&] { traction = surfaceTractionShares(mesh, region); });
      load.nodes = std::move(traction.nodes);
      load.weights = std::move(traction.shares);
      load.forcePerNode = r.vec3("total_force", Vec3::Zero(), "N");
      load.profile = readProfile(src, r.node("profile"), r.pathOf("profile"));
    } else if (r.has("force_per_node")) {
      load.nodes = requiredRegion(src, r, mesh);
      load.forcePerNode = r.vec3("force_per_node", Vec3::Zero(), "N");
      load.profile = readProfile(src, r.node("profile"), r.pathOf("profile"));
    } else {
      std::vector<int> nodes = requiredRegion(src, r, mesh);
      const Vec3 total = r.vec3("total_force", Vec3::Zero(), "N");
      const TimeProfile profile = readProfile(src, r.node("profile"), r.pathOf("profile"));
      load = evenNodalLoad(std::move(nodes), total, profile);
    }
    if (r.has("total_force_frames")) {
      // Stored per node, as forcePerNode is: split evenly, or shared by the surface weights.
      const double share =
          load.weights.empty() ? 1.0 / static_cast<double>(load.nodes.size()) : 1.0;
      for (const Vec3& total : readForceFrames(src, r)) load.frames.push_back(share * total);
      load.frameDt = dt;
    }
    loads.push_back(std::move(load));
  }
  return loads;
}

// springs.ligament: an attachment curve extruded into springs (thesis §5.1), one group per
// contiguous stretch of the curve, as many stretches as springs.groups has entries.
std::vector<CubicSpring> readLigament(const YamlSource& src, const MapReader& s,
                                      const TetMesh& mesh,
                                      const std::vector<CubicSpringCoefficients>& groups) {
  MapReader r(src, s.node("ligament"), "springs.ligament",
              {"curve", "length", "spacing", "layers", "layer_offset", "smooth_normals", "band"});
  auto readCurve = [&](const MapReader& m, const std::string& key) {
    const std::string path = m.existingFile(key);
    Eigen::MatrixX3d points;
    yamlio::withContext(src, m.node(key), m.pathOf(key), [&] { points = readPoints(path); });
    return points;
  };
  const Eigen::MatrixX3d curve = readCurve(r, "curve");
  LigamentOptions o;
  o.length = r.number("length", kDefaultSpringLength, "m", Range::Positive);
  o.spacing = r.number("spacing", 0.0, "m", Range::NonNegative);
  o.layers = r.integer("layers", 2);
  if (o.layers != 1 && o.layers != 2) r.fail("layers", "expected 1 or 2");
  o.layerOffset = r.number("layer_offset", o.layerOffset, "m", Range::NonNegative);
  o.smoothNormals = r.boolean("smooth_normals", true);
  if (r.has("band")) {
    if (o.layers != 2) r.fail("band", "expected 2 layers (the band's two edges), got 1");
    const MapReader band(src, r.node("band"), r.pathOf("band"), {"lower", "upper"});
    o.bandLower = readCurve(band, "lower");
    o.bandUpper = readCurve(band, "upper");
    for (const auto* edge : {&o.bandLower, &o.bandUpper})
      if (edge->rows() != curve.rows())
        band.fail(edge == &o.bandLower ? "lower" : "upper",
                  fmt::format("{} points, expected as many as the curve ({})", edge->rows(),
                              curve.rows()));
  }
  std::vector<CubicSpring> springs;
  yamlio::withContext(src, r.node("curve"), r.pathOf("curve"), [&] {
    springs = ligamentSprings(mesh, curve, o, static_cast<int>(groups.size()));
  });
  return springs;
}

CubicSpringSet readSprings(const YamlSource& src, const MapReader& top, const TetMesh& mesh) {
  MapReader s(src, top.node("springs"), "springs", {"groups", "attachments", "ligament"});
  std::vector<CubicSpringCoefficients> groups;
  std::vector<double> cutTimes;
  const auto groupNodes = listElements(src, s.node("groups"), "springs.groups");
  for (size_t g = 0; g < groupNodes.size(); ++g) {
    const std::string path = indexed("springs.groups", g);
    MapReader r(src, groupNodes[g], path, {"coefficients", "cut_time"});
    CubicSpringCoefficients k = kDefaultSpringCoefficients;
    if (r.has("coefficients")) {
      const YAML::Node c = r.node("coefficients");
      if (!c.IsSequence() || c.size() != 3)
        r.fail("coefficients", "expected a list of 3 numbers [ka N/m^3, kb N/m^2, kg N/m], got " +
                                   yamlio::describe(c));
      const std::string cp = r.pathOf("coefficients");
      k.kAlpha = yamlio::parseNumber(src, c[0], cp + "[0]", "N/m^3", Range::NonNegative);
      k.kBeta = yamlio::parseNumber(src, c[1], cp + "[1]", "N/m^2", Range::NonNegative);
      k.kGamma = yamlio::parseNumber(src, c[2], cp + "[2]", "N/m", Range::NonNegative);
    }
    groups.push_back(k);
    cutTimes.push_back(r.number("cut_time", std::numeric_limits<double>::infinity(), "s",
                                Range::NonNegative, true));
  }
  const auto attachments = listElements(src, s.node("attachments"), "springs.attachments");
  if (groups.empty() && !attachments.empty()) {
    groups.push_back(kDefaultSpringCoefficients);
    cutTimes.push_back(std::numeric_limits<double>::infinity());
  }
  if (groups.empty() && s.has("ligament")) {
    groups.push_back(kDefaultSpringCoefficients);
    cutTimes.push_back(std::numeric_limits<double>::infinity());
  }
  std::vector<CubicSpring> springs;
  if (s.has("ligament")) springs = readLigament(src, s, mesh, groups);
  if (!attachments.empty()) {
    const BoundarySurface boundary = extractBoundary(mesh);
    const std::vector<int> tetOf = tetOfEachNode(mesh);
    for (size_t a = 0; a < attachments.size(); ++a) {
      MapReader r(src, attachments[a], indexed("springs.attachments", a),
                  {"region", "group", "length"});
      const std::vector<int> nodes = requiredRegion(src, r, mesh);
      const int group = r.integer("group", 0);
      if (group >= static_cast<int>(groups.size()))
        r.fail("group", "expected a group index below " + std::to_string(groups.size()) +
                            " (springs.groups), got " + std::to_string(group));
      const double length = r.number("length", kDefaultSpringLength, "m", Range::Positive);
      const size_t before = springs.size();
      for (int n : nodes) {
        const Vec3 normal = boundary.vertexNormals.row(n).transpose();
        if (normal.squaredNorm() == 0) continue;  // interior node: no outward direction
        const MappedPoint mp = mappedNode(mesh, tetOf, n);
        springs.push_back(
            {mp.tet, mp.weights, mesh.V.row(n).transpose() + length * normal, length, group});
      }
      if (springs.size() == before)
        failAt(src, r.node("region"), r.pathOf("region"),
               "selects no boundary node (springs are extruded along the outward normal)");
    }
  }
  CubicSpringSet set(std::move(springs), std::move(groups));
  for (size_t g = 0; g < cutTimes.size(); ++g)
    if (std::isfinite(cutTimes[g])) set.cutGroupAt(static_cast<int>(g), cutTimes[g]);
  return set;
}

// Points given as a list [[x, y, z], ...] (m), mapped into the mesh.
Eigen::MatrixX3d readPointList(const YamlSource& src, const YAML::Node& node,
                               const std::string& path) {
  const auto rows = listElements(src, node, path);
  if (rows.empty())
    failAt(src, node, path, "expected a non-empty list of [x, y, z] points in metres");
  Eigen::MatrixX3d P(rows.size(), 3);
  for (size_t i = 0; i < rows.size(); ++i)
    P.row(i) = yamlio::parseVec3(src, rows[i], indexed(path, i), "m").transpose();
  return P;
}

// Mapped points and their rest positions from a region (nodes), a point list or a point file.
MarkerSet readMappedPoints(const YamlSource& src, const MapReader& r, const std::string& path,
                           const TetMesh& mesh, bool allowFile, int count) {
  Eigen::MatrixX3d P;
  if (r.has("region")) {
    std::vector<int> nodes = requiredRegion(src, r, mesh);
    if (r.has("count") && count < 1)
      r.fail("count", fmt::format("{} points asked; expected at least 1", count));
    if (count > static_cast<long long>(nodes.size()))
      r.fail("count",
             fmt::format("{} points asked, but the region has {} nodes; expected at most {}", count,
                         nodes.size(), nodes.size()));
    if (count > 0) nodes = farthestPointSample(mesh, nodes, count);
    MarkerSet set;
    yamlio::withContext(src, r.node("region"), r.pathOf("region"),
                        [&] { set = nodePointSet(mesh, nodes); });
    return set;
  }
  if (r.has("points")) {
    P = readPointList(src, r.node("points"), r.pathOf("points"));
  } else if (allowFile && r.has("file")) {
    const std::string file = r.existingFile("file");
    yamlio::withContext(src, r.node("file"), r.pathOf("file"), [&] { P = readPoints(file); });
    if (P.rows() == 0) r.fail("file", "'" + file + "' holds no point");
  } else {
    failAt(src, r.self(), path,
           std::string("expected one of region, points") + (allowFile ? ", file" : ""));
  }
  // A point outside the mesh follows the closest point of the nearest tet (documented).
  return mappedPointSet(mesh, P);
}

MarkerSet readMarkers(const YamlSource& src, const MapReader& top, const TetMesh& mesh) {
  MarkerSet all;
  const auto entries = listElements(src, top.node("markers"), "markers");
  std::vector<MarkerSet> parts;
  Eigen::Index total = 0;
  for (size_t i = 0; i < entries.size(); ++i) {
    MapReader r(src, entries[i], indexed("markers", i), {"region", "count", "points", "file"});
    const int given =
        (r.has("region") ? 1 : 0) + (r.has("points") ? 1 : 0) + (r.has("file") ? 1 : 0);
    if (given != 1)
      failAt(src, entries[i], indexed("markers", i),
             "expected exactly one of region, points, file");
    r.rejectUnless(r.has("region"), "count", "markers given by a region");
    parts.push_back(
        readMappedPoints(src, r, indexed("markers", i), mesh, true, r.integer("count", 0)));
    total += parts.back().rest.rows();
  }
  all.rest.resize(total, 3);
  Eigen::Index row = 0;
  for (const MarkerSet& p : parts) {
    all.points.insert(all.points.end(), p.points.begin(), p.points.end());
    all.rest.middleRows(row, p.rest.rows()) = p.rest;
    row += p.rest.rows();
  }
  return all;
}

// Validation or hidden points: every node (nodes: all), or one entry of the markers' kinds.
MarkerSet readValidationPoints(const YamlSource& src, const MapReader& top, const TetMesh& mesh,
                               const std::string& path = "validation_points") {
  if (!top.has(path)) return {};
  MapReader r(src, top.node(path), path, {"nodes", "region", "count", "points", "file"});
  const int given = (r.has("nodes") ? 1 : 0) + (r.has("region") ? 1 : 0) +
                    (r.has("points") ? 1 : 0) + (r.has("file") ? 1 : 0);
  if (given != 1)
    failAt(src, top.node(path), path, "expected exactly one of nodes (all), region, points, file");
  r.rejectUnless(r.has("region"), "count", "validation points given by a region");
  if (!r.has("nodes")) return readMappedPoints(src, r, path, mesh, true, r.integer("count", 0));
  if (r.text("nodes", "") != "all")
    r.fail("nodes", "expected 'all' (every mesh node), got " + yamlio::describe(r.node("nodes")));
  std::vector<int> all(static_cast<size_t>(mesh.numNodes()));
  for (size_t n = 0; n < all.size(); ++n) all[n] = static_cast<int>(n);
  MarkerSet set;
  yamlio::withContext(src, r.node("nodes"), r.pathOf("nodes"),
                      [&] { set = nodePointSet(mesh, all); });
  return set;
}

// The control trajectory CSV: time,dx,dy,dz (s, m), header optional.
void readTrajectory(const std::string& path, std::vector<double>& times, Eigen::MatrixX3d& d) {
  const CsvTable table = readCsvTable(path);
  int cols[4] = {0, 1, 2, 3};
  if (!table.header.empty()) {
    const char* names[2][4] = {{"time", "dx", "dy", "dz"}, {"time", "x", "y", "z"}};
    bool found = false;
    for (auto& set : names) {
      bool all = true;
      for (int c = 0; c < 4; ++c) all = all && table.column(set[c]) >= 0;
      if (!all || found) continue;
      for (int c = 0; c < 4; ++c) cols[c] = table.column(set[c]);
      found = true;
    }
    if (!found) throw InputError(path + ":1: expected columns time,dx,dy,dz (s, m)");
  } else if (table.rows.cols() != 4) {
    throw InputError(path + ": expected 4 columns time,dx,dy,dz (s, m), got " +
                     std::to_string(table.rows.cols()));
  }
  if (table.rows.rows() == 0) throw InputError(path + ": no trajectory row");
  d.resize(table.rows.rows(), 3);
  for (Eigen::Index i = 0; i < table.rows.rows(); ++i) {
    times.push_back(table.rows(i, cols[0]));
    if (i > 0 && !(times[i] > times[i - 1]))
      throw InputError(path + ":" + std::to_string(table.lines[i]) + ": times must increase, got " +
                       std::to_string(times[i]) + " after " + std::to_string(times[i - 1]));
    for (int c = 0; c < 3; ++c) d(i, c) = table.rows(i, cols[c + 1]);
  }
}

// control_points[] with tracks: each chosen marker of an observed tracks file (thesis §5.3, the
// tracked tackers used as prescribed points) becomes a control point of its own: mapped into the
// mesh where it is first seen, pulled along its track (displacements from there, in track time
// minus time_offset), held between and after its frames.
void readTrackedControls(const YamlSource& src, const MapReader& r, const TetMesh& mesh,
                         std::vector<ControlPointSet>& controls) {
  const std::string file = r.existingFile("tracks");
  MarkerTracks tracks;
  yamlio::withContext(src, r.node("tracks"), r.pathOf("tracks"),
                      [&] { tracks = readMarkerTracks(file); });
  std::vector<int> ids;
  if (r.has("markers")) {
    const auto list = listElements(src, r.node("markers"), r.pathOf("markers"));
    if (list.empty()) r.fail("markers", "expected a non-empty list of marker ids");
    for (size_t k = 0; k < list.size(); ++k) {
      const int id = yamlio::parseInteger(src, list[k], indexed(r.pathOf("markers"), k));
      if (id >= tracks.numMarkers)
        failAt(src, list[k], indexed(r.pathOf("markers"), k),
               fmt::format("'{}' has markers 0 to {}, got {}", file, tracks.numMarkers - 1, id));
      ids.push_back(id);
    }
  } else {
    for (int id = 0; id < tracks.numMarkers; ++id) ids.push_back(id);
  }
  const double offset = r.number("time_offset", 0.0, "s");
  const double stiffness = r.number("stiffness", 1000.0, "N/m", Range::Positive);
  for (int id : ids) {
    std::vector<double> times;
    std::vector<Vec3> seen;
    for (size_t f = 0; f < tracks.times.size(); ++f) {
      const Vec3 p = tracks.frames[f].row(id).transpose();
      if (!p.allFinite()) continue;
      times.push_back(tracks.times[f] - offset);
      seen.push_back(p);
    }
    if (seen.empty()) {
      // A marker never seen prescribes nothing; tracks from a tracker may hold such ids.
      if (r.has("markers"))
        r.fail("markers", fmt::format("marker {} is never seen in '{}'", id, file));
      continue;
    }
    Eigen::MatrixX3d start(1, 3), d(static_cast<Eigen::Index>(seen.size()), 3);
    start.row(0) = seen.front().transpose();
    for (size_t k = 0; k < seen.size(); ++k)
      d.row(static_cast<Eigen::Index>(k)) = (seen[k] - seen.front()).transpose();
    MarkerSet point = mappedPointSet(mesh, start);
    yamlio::withContext(src, r.node("tracks"), r.pathOf("tracks"), [&] {
      controls.emplace_back(std::move(point.points), std::move(point.rest), std::move(times),
                            std::move(d), stiffness);
    });
  }
}

std::vector<ControlPointSet> readControls(const YamlSource& src, const MapReader& top,
                                          const TetMesh& mesh) {
  std::vector<ControlPointSet> controls;
  const auto entries = listElements(src, top.node("control_points"), "control_points");
  for (size_t i = 0; i < entries.size(); ++i) {
    const std::string path = indexed("control_points", i);
    MapReader r(
        src, entries[i], path,
        {"region", "points", "trajectory", "tracks", "markers", "time_offset", "stiffness"});
    if (r.has("tracks")) {
      for (const char* key : {"region", "points", "trajectory"})
        r.rejectUnless(false, key, "control points given by a trajectory (not tracks)");
      readTrackedControls(src, r, mesh, controls);
      continue;
    }
    r.rejectUnless(false, "markers", "control points given by tracks");
    r.rejectUnless(false, "time_offset", "control points given by tracks");
    if (r.has("region") == r.has("points"))
      failAt(src, entries[i], path, "expected exactly one of region, points, tracks");
    MarkerSet points = readMappedPoints(src, r, path, mesh, false, 0);
    if (!r.has("trajectory"))
      failAt(src, entries[i], r.pathOf("trajectory"),
             "missing (CSV file time,dx,dy,dz in s and m)");
    const std::string csv = r.existingFile("trajectory");
    std::vector<double> times;
    Eigen::MatrixX3d d;
    yamlio::withContext(src, r.node("trajectory"), r.pathOf("trajectory"),
                        [&] { readTrajectory(csv, times, d); });
    const double stiffness = r.number("stiffness", 1000.0, "N/m", Range::Positive);
    yamlio::withContext(src, entries[i], path, [&] {
      controls.emplace_back(std::move(points.points), std::move(points.rest), std::move(times),
                            std::move(d), stiffness);
    });
  }
  return controls;
}

const std::vector<std::string> kSceneKeys = {
    "mesh",          "material",       "materials",      "density", "mass",     "gravity",
    "damping",       "time",           "integrator",     "solver",  "fixed",    "loads",
    "springs",       "control_points", "markers",        "output",  "variants", "validation_points",
    "hidden_points", "assimilation",   "mean_dilatation"};

// Whether the scene's assimilation section has its sigma points share one factorisation
// (reuse_factorization): that needs factorized-pcg, then the default solver.type, for the base
// and its variants alike (an explicit other type is refused with the section).
bool sharesFactorization(const YamlSource& src, const YAML::Node& root) {
  if (!root.IsMap() || !root["assimilation"].IsDefined()) return false;
  return yamlio::sharesSolverFactorization(src, root["assimilation"]);
}

// `sharedFactorization`: see sharesFactorization (of the base scene, for a variant).
Scene buildScene(const YamlSource& src, const YAML::Node& root, bool allowVariants,
                 bool sharedFactorization, const SceneLimits& limits) {
  if (!root.IsDefined() || root.IsNull())
    failAt(src, root, "", "the scene is empty; expected a map of sections (mesh, material, ...)");
  MapReader top(src, root, "", kSceneKeys);
  top.rejectUnless(allowVariants, "variants", "the scene itself, not inside a variant");

  std::shared_ptr<const TetMesh> mesh = readMesh(src, top, limits);
  std::vector<Material> materials = readMaterials(src, top, *mesh);
  const double density = top.number("density", 1000.0, "kg/m^3", Range::Positive);
  const MassKind mass = top.choice("mass", "lumped", {"lumped", "consistent"}) == "lumped"
                            ? MassKind::Lumped
                            : MassKind::Consistent;
  MapReader dilatation(src, top.node("mean_dilatation"), "mean_dilatation", {"patch_tets"});
  const int patchTets = dilatation.integer("patch_tets", 1, Range::AtLeastOne);
  std::optional<MechanicalModel> built;
  auto build = [&] {
    built.emplace(makeMechanicalModel(mesh, std::move(materials), density, mass, patchTets));
  };
  if (patchTets > 1)
    yamlio::withContext(src, top.node("mean_dilatation"), "mean_dilatation", build);
  else
    build();
  Scene scene(std::move(*built));
  scene.sourceFile = src.file;
  MechanicalModel& model = scene.model;
  model.gravity = top.vec3("gravity", Vec3::Zero(), "m/s^2");
  MapReader damping(src, top.node("damping"), "damping", {"rayleigh_mass", "rayleigh_stiffness"});
  model.rayleighMass = damping.number("rayleigh_mass", 0.0, "1/s", Range::NonNegative);
  model.rayleighStiffness = damping.number("rayleigh_stiffness", 0.0, "s", Range::NonNegative);

  MapReader time(src, top.node("time"), "time", {"dt", "steps", "min_dt"});
  scene.implicitEuler.dt = time.number("dt", 0.01, "s", Range::Positive);
  scene.steps = time.integer("steps", 100, Range::AtLeastOne);
  // A failing step is halved down to min_dt (the default allows six halvings).
  const double dt = scene.implicitEuler.dt;
  scene.implicitEuler.minDt = time.number("min_dt", dt / 64.0, "s", Range::Positive);
  if (scene.implicitEuler.minDt > dt)
    time.fail("min_dt", "must be <= time.dt (s), got " + time.node("min_dt").Scalar());

  MapReader integ(src, top.node("integrator"), "integrator",
                  {"type", "newton_iterations", "tolerance", "max_iterations", "load_steps"});
  const bool statics =
      integ.choice("type", "implicit-euler", {"implicit-euler", "static"}) == "static";
  scene.integrator = statics ? IntegratorKind::Static : IntegratorKind::ImplicitEuler;
  integ.rejectUnless(!statics, "newton_iterations", "type implicit-euler");
  integ.rejectUnless(statics, "max_iterations", "type static");
  integ.rejectUnless(statics, "load_steps", "type static");
  scene.implicitEuler.newtonIterations = integ.integer("newton_iterations", 0);
  scene.implicitEuler.newtonTolerance = integ.number("tolerance", 1e-10, "-", Range::Positive);
  scene.statics.relativeTolerance = scene.implicitEuler.newtonTolerance;
  scene.statics.maxIterations = integ.integer("max_iterations", 50, Range::AtLeastOne);
  scene.statics.loadSteps = integ.integer("load_steps", 1, Range::AtLeastOne);
  scene.statics.minIncrementFraction = scene.implicitEuler.minDt / dt;

  MapReader solver(src, top.node("solver"), "solver",
                   {"type", "refresh_every", "max_iterations", "tolerance", "precision",
                    "refresh_in_background"});
  scene.solver.type = solver.choice("type", sharedFactorization ? "factorized-pcg" : "cholmod",
                                    {"cholmod", "cg", "jacobi-pcg", "factorized-pcg"});
  scene.solver.policy.everyNMatrices = solver.integer("refresh_every", 0);
  scene.solver.policy.maxIterations = solver.integer("max_iterations", 20, Range::AtLeastOne);
  scene.solver.policy.relTol = solver.number("tolerance", 1e-10, "-", Range::Positive);
  scene.solver.policy.singlePrecision =
      solver.choice("precision", "single", {"single", "double"}) == "single";
  scene.solver.policy.background = solver.boolean("refresh_in_background", false);
  for (const char* key : {"precision", "refresh_in_background"})
    solver.rejectUnless(scene.solver.type == "factorized-pcg", key, "type factorized-pcg");
  solver.rejectUnless(scene.solver.type == "factorized-pcg", "refresh_every",
                      "type factorized-pcg");
  solver.rejectUnless(scene.solver.type == "factorized-pcg", "max_iterations",
                      "type factorized-pcg");
  solver.rejectUnless(scene.solver.type != "cholmod", "tolerance", "iterative solvers");

  model.dirichlet = readFixed(src, top, model);
  model.loads = readLoads(src, top, *mesh, scene.dt());
  model.springs = readSprings(src, top, *mesh);
  model.controls = readControls(src, top, *mesh);
  scene.markers = readMarkers(src, top, *mesh);
  scene.validation = readValidationPoints(src, top, *mesh);
  scene.hidden = readValidationPoints(src, top, *mesh, "hidden_points");

  MapReader output(src, top.node("output"), "output", {"every", "pvd"});
  scene.output.every = output.integer("every", 10, Range::AtLeastOne);
  scene.output.pvd = output.boolean("pvd", true);
  // Variants are forward runs only; their merged YAML leaves the section out.
  if (top.has("assimilation")) {
    const AssimilationContext context{model,
                                      static_cast<int>(scene.markers.points.size()),
                                      static_cast<int>(scene.validation.points.size()),
                                      scene.dt(),
                                      scene.steps,
                                      scene.solver.type,
                                      scene.integrator == IntegratorKind::Static};
    scene.assimilation = yamlio::readAssimilationSettings(src, top.node("assimilation"), context);
  }
  return scene;
}

// Folds `over` into `base`: maps merge key by key, anything else replaces.
void mergeInto(YAML::Node base, const YAML::Node& over) {
  for (const auto& kv : over) {
    const std::string key = kv.first.Scalar();
    YAML::Node b = base[key];
    if (b.IsDefined() && b.IsMap() && kv.second.IsMap())
      mergeInto(b, kv.second);
    else
      base[key] = kv.second;
  }
}

YAML::Node parse(const std::string& yaml, const YamlSource& src) {
  try {
    return YAML::Load(yaml);
  } catch (const YAML::ParserException& e) {
    // yaml-cpp quotes the offending character raw (a line break, an escape byte): escaped here.
    throw InputError(src.file + ":" + std::to_string(e.mark.line + 1) +
                     ": invalid YAML: " + io::excerpt(e.msg, 200));
  }
}

Scene loadFromText(const std::string& yaml, const YamlSource& src, const SceneLimits& limits) {
  const YAML::Node root = parse(yaml, src);
  const bool sharedFactorization = sharesFactorization(src, root);
  Scene scene = buildScene(src, root, true, sharedFactorization, limits);
  if (!root.IsMap() || !root["variants"].IsDefined()) return scene;
  const auto variants = listElements(src, root["variants"], "variants");
  if (!variants.empty() && scene.markers.points.empty())
    failAt(src, root["variants"], "variants",
           "comparing variants needs markers; add a markers: section");
  std::set<std::string> names = {scene.name};
  for (size_t i = 0; i < variants.size(); ++i) {
    const std::string path = indexed("variants", i);
    const YAML::Node& node = variants[i];
    if (!node.IsMap())
      failAt(src, node, path,
             "expected a map with a name and scene keys, got " + yamlio::describe(node));
    if (!node["name"].IsDefined())
      failAt(src, node, path + ".name", "missing (the variant's name)");
    const YAML::Node nameNode = node["name"];
    const std::string name = nameNode.IsScalar() ? nameNode.Scalar() : "";
    // The name becomes an output directory: keep it to characters safe in any file system.
    const bool wellFormed = !name.empty() && name.find_first_not_of(
                                                 "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUV"
                                                 "WXYZ0123456789_-") == std::string::npos;
    if (!wellFormed)
      failAt(src, nameNode, path + ".name",
             "expected a name of letters, digits, '_', '-', got " + yamlio::describe(nameNode));
    if (!names.insert(name).second)
      failAt(src, nameNode, path + ".name", "name '" + name + "' is used twice");
    YAML::Node merged = parse(yaml, src);  // a fresh copy: Clone() would lose the line numbers
    merged.remove("variants");
    merged.remove("assimilation");
    YAML::Node overrides(YAML::NodeType::Map);
    for (const auto& kv : node) {
      const std::string key = kv.first.Scalar();
      if (key == "name") continue;
      bool known = false;
      for (const std::string& k : kSceneKeys)
        known = known || (key == k && key != "variants" && key != "assimilation");
      if (!known) {
        std::string list = "name";
        for (const std::string& k : kSceneKeys)
          if (k != "variants" && k != "assimilation") list.append(", ").append(k);
        failAt(src, kv.first, "",
               fmt::format("unknown key '{}' in {}; expected one of {}", key, path, list));
      }
      overrides[key] = kv.second;
    }
    mergeInto(merged, overrides);
    Scene variant = buildScene(src, merged, false, sharedFactorization, limits);
    variant.name = name;
    if (variant.steps != scene.steps || variant.dt() != scene.dt())
      failAt(src, node, path, "a variant must keep the base's time.dt and time.steps");
    if (variant.markers.rest.rows() != scene.markers.rest.rows())
      failAt(src, node, path,
             "a variant must have as many markers as the base (" +
                 std::to_string(scene.markers.rest.rows()) + "), got " +
                 std::to_string(variant.markers.rest.rows()));
    scene.variants.push_back(std::move(variant));
  }
  return scene;
}

}  // namespace

Scene loadSceneFromString(const std::string& yaml, const std::string& sourceName,
                          const std::string& directory, const SceneLimits& limits) {
  return loadFromText(yaml, YamlSource{sourceName, directory}, limits);
}

Scene loadScene(const std::string& path, const SceneLimits& limits) {
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path + ": cannot open file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open file");
  std::ostringstream text;
  text << in.rdbuf();
  std::string directory = std::filesystem::path(path).parent_path().string();
  if (directory.empty()) directory = ".";
  return loadSceneFromString(text.str(), path, directory, limits);
}

}  // namespace bcassim
