// Surface repair with CGAL Polygon_mesh_processing and tetrahedralisation with CGAL Mesh_3. All
// CGAL includes of the project live in this file, so only it pays CGAL's compile time.
#include "bcassim/ligaments/SurfaceMesher.h"

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Mesh_complex_3_in_triangulation_3.h>
#include <CGAL/Mesh_criteria_3.h>
#include <CGAL/Mesh_triangulation_3.h>
#include <CGAL/Polygon_mesh_processing/connected_components.h>
#include <CGAL/Polygon_mesh_processing/measure.h>
#include <CGAL/Polygon_mesh_processing/orient_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/orientation.h>
#include <CGAL/Polygon_mesh_processing/polygon_soup_to_polygon_mesh.h>
#include <CGAL/Polygon_mesh_processing/repair.h>
#include <CGAL/Polygon_mesh_processing/repair_polygon_soup.h>
#include <CGAL/Polygon_mesh_processing/self_intersections.h>
#include <CGAL/Polygon_mesh_processing/stitch_borders.h>
#include <CGAL/Polygon_mesh_processing/triangulate_hole.h>
#include <CGAL/Polyhedral_mesh_domain_3.h>
#include <CGAL/Random.h>
#include <CGAL/Surface_mesh.h>
#include <CGAL/make_mesh_3.h>
#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <map>
#include <unordered_map>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/io/ObjFormat.h"
#include "bcassim/mesh/MeshQuality.h"
#include "bcassim/mesh/MeshValidation.h"

namespace bcassim {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Surface = CGAL::Surface_mesh<Point>;
using Domain = CGAL::Polyhedral_mesh_domain_3<Surface, Kernel>;
// Sequential_tag: the parallel mesher's result depends on thread scheduling.
using Triangulation = CGAL::Mesh_triangulation_3<Domain, CGAL::Default, CGAL::Sequential_tag>::type;
using Complex = CGAL::Mesh_complex_3_in_triangulation_3<Triangulation>;
using Criteria = CGAL::Mesh_criteria_3<Triangulation>;

using Polygon = std::vector<std::size_t>;

int countDuplicatePoints(const std::vector<Point>& points) {
  std::map<std::array<double, 3>, int> seen;
  int duplicates = 0;
  for (const Point& p : points) {
    if (!seen.emplace(std::array<double, 3>{p.x(), p.y(), p.z()}, 0).second) ++duplicates;
  }
  return duplicates;
}

// Border loops of `mesh`, one halfedge each, with their edge counts.
std::vector<std::pair<Surface::Halfedge_index, int>> borderLoops(const Surface& mesh) {
  std::vector<std::pair<Surface::Halfedge_index, int>> loops;
  std::vector<bool> visited(mesh.number_of_halfedges(), false);
  for (Surface::Halfedge_index h : mesh.halfedges()) {
    if (!mesh.is_border(h) || visited[h.idx()]) continue;
    int size = 0;
    Surface::Halfedge_index g = h;
    do {
      visited[g.idx()] = true;
      ++size;
      g = mesh.next(g);
    } while (g != h && size <= static_cast<int>(mesh.number_of_halfedges()));
    loops.emplace_back(h, size);
  }
  return loops;
}

// Makes `surface` a closed, consistently outward oriented, single-component mesh, recording what it
// changed in `report`.
Surface repairSurface(const TriMesh& surface, double scale, int maxHoleEdges,
                      const std::string& source, SurfaceMeshingReport& report) {
  std::vector<Point> points;
  points.reserve(surface.V.rows());
  for (Eigen::Index i = 0; i < surface.V.rows(); ++i) {
    points.emplace_back(scale * surface.V(i, 0), scale * surface.V(i, 1), scale * surface.V(i, 2));
  }
  std::vector<Polygon> polygons;
  for (Eigen::Index f = 0; f < surface.F.rows(); ++f) {
    polygons.push_back({static_cast<std::size_t>(surface.F(f, 0)),
                        static_cast<std::size_t>(surface.F(f, 1)),
                        static_cast<std::size_t>(surface.F(f, 2))});
  }
  report.mergedVertices = countDuplicatePoints(points);
  // Merges duplicate points, drops degenerate and duplicate polygons and unused points.
  PMP::repair_polygon_soup(points, polygons);
  report.removedFaces = report.inputFaces - static_cast<int>(polygons.size());
  const std::vector<Polygon> beforeOrient = polygons;
  // Non-manifold vertices are duplicated here so that the soup becomes an orientable mesh.
  PMP::orient_polygon_soup(points, polygons);
  for (std::size_t f = 0; f < polygons.size(); ++f) {
    if (polygons[f] != beforeOrient[f]) ++report.flippedFaces;
  }
  Surface mesh;
  PMP::polygon_soup_to_polygon_mesh(points, polygons, mesh);
  if (mesh.is_empty()) throw InputError(source + ": no faces left after repair");
  PMP::stitch_borders(mesh);
  PMP::remove_degenerate_faces(mesh);
  mesh.collect_garbage();

  auto componentMap = mesh.add_property_map<Surface::Face_index, std::size_t>("f:cc").first;
  report.components = static_cast<int>(PMP::connected_components(mesh, componentMap));
  if (report.components > 1) {
    PMP::keep_largest_connected_components(mesh, 1);
    mesh.collect_garbage();
  }

  for (const auto& [h, size] : borderLoops(mesh)) {
    if (size > maxHoleEdges) {
      throw InputError(fmt::format("{}: a border loop of {} edges is too large to fill (limit {})",
                                   source, size, maxHoleEdges));
    }
    std::vector<Surface::Face_index> patch;
    PMP::triangulate_hole(mesh, h, std::back_inserter(patch));
    if (patch.empty()) {
      throw InputError(fmt::format("{}: a hole of {} edges could not be filled", source, size));
    }
    ++report.holesFilled;
  }
  if (!CGAL::is_closed(mesh)) throw InputError(source + ": the surface is still open after repair");

  std::vector<std::pair<Surface::Face_index, Surface::Face_index>> pairs;
  PMP::self_intersections(mesh, std::back_inserter(pairs));
  report.selfIntersections = static_cast<int>(pairs.size());
  if (!PMP::is_outward_oriented(mesh)) {
    PMP::reverse_face_orientations(mesh);
    report.flippedFaces = static_cast<int>(mesh.number_of_faces()) - report.flippedFaces;
  }
  const long euler = static_cast<long>(mesh.number_of_vertices()) -
                     static_cast<long>(mesh.number_of_edges()) +
                     static_cast<long>(mesh.number_of_faces());
  report.genus = static_cast<int>((2 - euler) / 2);
  report.surfaceVolume = PMP::volume(mesh);
  return mesh;
}

TriMesh toTriMesh(const Surface& mesh) {
  TriMesh out;
  out.V.resize(mesh.number_of_vertices(), 3);
  for (Surface::Vertex_index v : mesh.vertices()) {
    const Point& p = mesh.point(v);
    out.V.row(v.idx()) << p.x(), p.y(), p.z();
  }
  out.F.resize(mesh.number_of_faces(), 3);
  int f = 0;
  for (Surface::Face_index face : mesh.faces()) {
    int c = 0;
    for (Surface::Vertex_index v : CGAL::vertices_around_face(mesh.halfedge(face), mesh)) {
      if (c < 3) out.F(f, c) = static_cast<int>(v.idx());
      ++c;
    }
    ++f;
  }
  return out;
}

// Cells of the complex as a TetMesh, nodes numbered in order of first use, tets made positive.
TetMesh toTetMesh(const Complex& complex) {
  std::unordered_map<Triangulation::Vertex_handle, int> index;
  std::vector<Vec3> nodes;
  std::vector<Eigen::Vector4i> tets;
  for (auto c = complex.cells_in_complex_begin(); c != complex.cells_in_complex_end(); ++c) {
    Eigen::Vector4i tet;
    for (int i = 0; i < 4; ++i) {
      const auto v = c->vertex(i);
      auto [it, inserted] = index.emplace(v, static_cast<int>(nodes.size()));
      if (inserted) {
        const auto& p = v->point();
        nodes.emplace_back(p.x(), p.y(), p.z());
      }
      tet(i) = it->second;
    }
    const Vec3 &a = nodes[tet(0)], &b = nodes[tet(1)], &cc = nodes[tet(2)], &d = nodes[tet(3)];
    if ((b - a).cross(cc - a).dot(d - a) < 0) std::swap(tet(2), tet(3));
    tets.push_back(tet);
  }
  TetMesh mesh;
  mesh.V.resize(static_cast<Eigen::Index>(nodes.size()), 3);
  for (std::size_t i = 0; i < nodes.size(); ++i) mesh.V.row(i) = nodes[i].transpose();
  mesh.T.resize(static_cast<Eigen::Index>(tets.size()), 4);
  for (std::size_t t = 0; t < tets.size(); ++t) mesh.T.row(t) = tets[t].transpose();
  mesh.region = Eigen::VectorXi::Zero(mesh.T.rows());
  return mesh;
}

TetMesh runMesh3(const Surface& surface, double cellSize, const SurfaceMeshingOptions& options) {
  namespace params = CGAL::parameters;
  CGAL::Random rng(0);
  Domain domain(surface, &rng);
  // facet_distance 1/10 of the size keeps the enclosed volume within ~1-2 % of the surface's.
  Criteria criteria(params::facet_angle = options.facetAngleDeg, params::facet_size = cellSize,
                    params::facet_distance = 0.1 * cellSize,
                    params::cell_radius_edge_ratio = options.radiusEdgeRatio,
                    params::cell_size = cellSize);
  // Perturbation is skipped (bounded by wall time); exudation, optional, also varies between runs.
  Complex complex =
      options.exude
          ? CGAL::make_mesh_3<Complex>(domain, criteria, params::no_perturb(), params::exude())
          : CGAL::make_mesh_3<Complex>(domain, criteria, params::no_perturb(), params::no_exude());
  return toTetMesh(complex);
}

}  // namespace

SurfaceMeshingResult meshSurface(const TriMesh& surface, const SurfaceMeshingOptions& options,
                                 const std::string& source) {
  const auto start = Clock::now();
  if (options.targetNodes < 10) {
    throw InputError(
        fmt::format("{}: target node count {} is too small", source, options.targetNodes));
  }
  SurfaceMeshingResult result;
  SurfaceMeshingReport& report = result.report;
  report.inputVertices = static_cast<int>(surface.V.rows());
  report.inputFaces = static_cast<int>(surface.F.rows());
  for (Eigen::Index f = 0; f < surface.F.rows(); ++f) {
    for (int c = 0; c < 3; ++c) {
      if (surface.F(f, c) < 0 || surface.F(f, c) >= surface.V.rows()) {
        throw InputError(fmt::format("{}: face {} refers to vertex {}, but there are {} vertices",
                                     source, f, surface.F(f, c), surface.V.rows()));
      }
    }
  }
  const Surface repaired =
      repairSurface(surface, options.scale, options.maxHoleEdges, source, report);
  result.repaired = toTriMesh(repaired);
  if (!(report.surfaceVolume > 0)) {
    throw InputError(fmt::format("{}: the repaired surface encloses no volume", source));
  }

  // A Delaunay mesh of size h holds about 1.5 V / h^3 nodes (about 5.5 regular tets of volume
  // h^3 / 8.5 per node). Surface nodes grow only like h^-2, so corrections use the exponent 1/2.5.
  double cellSize = std::cbrt(1.5 * report.surfaceVolume / options.targetNodes);
  double bestError = std::numeric_limits<double>::infinity();
  for (int attempt = 0; attempt < std::max(1, options.maxAttempts); ++attempt) {
    TetMesh mesh = runMesh3(repaired, cellSize, options);
    ++report.attempts;
    const double ratio = static_cast<double>(mesh.numNodes()) / options.targetNodes;
    const double error = std::abs(ratio - 1.0);
    if (mesh.numTets() > 0 && error < bestError) {
      bestError = error;
      result.mesh = std::move(mesh);
      report.cellSize = cellSize;
    }
    if (error <= options.nodeTolerance || ratio <= 0) break;
    cellSize *= std::pow(ratio, 1.0 / 2.5);
  }
  if (result.mesh.numTets() == 0) throw InputError(source + ": Mesh_3 produced no tets");
  validateTetMesh(result.mesh, source);
  const MeshQuality quality = measureQuality(result.mesh);
  report.outputNodes = static_cast<int>(quality.numNodes);
  report.outputTets = static_cast<int>(quality.numTets);
  report.meshVolume = quality.totalVolume;
  report.minDihedralDeg = quality.minDihedralDeg;
  report.seconds = secondsSince(start);
  return result;
}

namespace {

std::string describeRepairs(const SurfaceMeshingReport& r) {
  std::vector<std::string> parts;
  if (r.mergedVertices)
    parts.push_back(fmt::format("{} duplicate vertices merged", r.mergedVertices));
  if (r.removedFaces)
    parts.push_back(fmt::format("{} degenerate/duplicate faces removed", r.removedFaces));
  if (r.flippedFaces) parts.push_back(fmt::format("{} faces reoriented", r.flippedFaces));
  if (r.components > 1) parts.push_back(fmt::format("{} components, largest kept", r.components));
  if (r.holesFilled) parts.push_back(fmt::format("{} holes filled", r.holesFilled));
  if (r.genus) parts.push_back(fmt::format("genus {}", r.genus));
  if (r.selfIntersections) {
    parts.push_back(fmt::format("{} self-intersecting face pairs", r.selfIntersections));
  }
  std::string out;
  for (const std::string& p : parts) out += (out.empty() ? "" : "; ") + p;
  return out;
}

LiverMeshingOutcome meshOne(const std::filesystem::path& path, const std::string& name,
                            SurfaceMeshingOptions options, bool fitWidth) {
  LiverMeshingOutcome outcome;
  outcome.file = name;
  try {
    const TriMesh surface = readObj(path.string());
    if (fitWidth && surface.V.rows() > 0) {
      const double width =
          (surface.V.colwise().maxCoeff() - surface.V.colwise().minCoeff()).maxCoeff();
      options.scale = 0.20 / width;
    }
    const SurfaceMeshingResult result = meshSurface(surface, options, name);
    outcome.report = result.report;
    outcome.problem = describeRepairs(result.report);
    const double ratio = static_cast<double>(result.report.outputNodes) / options.targetNodes;
    // The mesh volume must match the surface's: a surface cut open by the orientation repair or
    // folded onto itself encloses a different volume than the organ, yet still meshes.
    const double volumeRatio = result.report.meshVolume / result.report.surfaceVolume;
    const bool volumeOk = std::abs(volumeRatio - 1) <= 0.05;
    if (!volumeOk) {
      outcome.problem += fmt::format("{}mesh volume {:.2f} x the surface's",
                                     outcome.problem.empty() ? "" : "; ", volumeRatio);
    }
    const bool nodesOk = std::abs(ratio - 1) <= options.nodeTolerance;
    outcome.ok = nodesOk && volumeOk;
    if (!nodesOk) {
      outcome.problem += fmt::format("{}node count {} outside +-{:.0f} % of {}",
                                     outcome.problem.empty() ? "" : "; ", result.report.outputNodes,
                                     100 * options.nodeTolerance, options.targetNodes);
    }
  } catch (const std::exception& e) {
    outcome.ok = false;
    outcome.problem = e.what();
  }
  return outcome;
}

}  // namespace

std::vector<LiverMeshingOutcome> meshAllLivers(const std::string& dataDir,
                                               const SurfaceMeshingOptions& options) {
  namespace fs = std::filesystem;
  const fs::path livers = fs::path(dataDir) / "livers";
  if (!fs::is_directory(livers)) {
    throw InputError(fmt::format("{}: no such directory (the liver data set)", livers.string()));
  }
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(livers)) {
    if (entry.path().extension() == ".obj") files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  std::vector<LiverMeshingOutcome> outcomes;
  outcomes.reserve(files.size() + 1);
  for (const fs::path& file : files) {
    outcomes.push_back(meshOne(file, "livers/" + file.filename().string(), options, false));
  }
  const fs::path sofa = fs::path(dataDir) / "sofa-liver" / "liver-smooth.obj";
  if (fs::exists(sofa))
    outcomes.push_back(meshOne(sofa, "sofa-liver/liver-smooth.obj", options, true));
  return outcomes;
}

}  // namespace bcassim
