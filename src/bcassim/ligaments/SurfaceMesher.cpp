// Surface repair with CGAL Polygon_mesh_processing and tetrahedralisation with CGAL Mesh_3. All
// CGAL includes of the project live in this file, so only it pays CGAL's compile time.
#include "bcassim/ligaments/SurfaceMesher.h"

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Labeled_mesh_domain_3.h>
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
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <map>
#include <numbers>
#include <unordered_map>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/io/ObjFormat.h"
#include "bcassim/mesh/BoundarySurface.h"
#include "bcassim/mesh/MeshQuality.h"
#include "bcassim/mesh/MeshValidation.h"

namespace bcassim {
namespace {

namespace PMP = CGAL::Polygon_mesh_processing;
using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Point = Kernel::Point_3;
using Surface = CGAL::Surface_mesh<Point>;
using Domain = CGAL::Polyhedral_mesh_domain_3<Surface, Kernel>;
using ImplicitDomain = CGAL::Labeled_mesh_domain_3<Kernel>;
// Sequential_tag: the parallel mesher's result depends on thread scheduling.
template <class D>
using TriangulationOf =
    typename CGAL::Mesh_triangulation_3<D, CGAL::Default, CGAL::Sequential_tag>::type;
template <class D>
using ComplexOf = CGAL::Mesh_complex_3_in_triangulation_3<TriangulationOf<D>>;
using Triangle = Kernel::Triangle_3;
using TrianglePrimitive =
    CGAL::AABB_triangle_primitive<Kernel, std::vector<Triangle>::const_iterator>;
using TriangleTree = CGAL::AABB_tree<CGAL::AABB_traits<Kernel, TrianglePrimitive>>;

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
// changed in `report`. `soupPoints`/`soupPolygons` receive the soup after merging duplicates and
// dropping degenerate faces, before any orientation or hole filling.
Surface repairSurface(const TriMesh& surface, double scale, int maxHoleEdges,
                      const std::string& source, SurfaceMeshingReport& report,
                      std::vector<Point>& soupPoints, std::vector<Polygon>& soupPolygons) {
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
  soupPoints = points;
  soupPolygons = polygons;
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
template <class Complex>
TetMesh toTetMesh(const Complex& complex) {
  std::unordered_map<typename Complex::Triangulation::Vertex_handle, int> index;
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

template <class D>
TetMesh runMesh3(const D& domain, double cellSize, const SurfaceMeshingOptions& options) {
  namespace params = CGAL::parameters;
  using Complex = ComplexOf<D>;
  // facet_distance 1/10 of the size keeps the enclosed volume within ~1-2 % of the surface's.
  CGAL::Mesh_criteria_3<TriangulationOf<D>> criteria(
      params::facet_angle = options.facetAngleDeg, params::facet_size = cellSize,
      params::facet_distance = 0.1 * cellSize,
      params::cell_radius_edge_ratio = options.radiusEdgeRatio, params::cell_size = cellSize);
  // Perturbation is skipped (bounded by wall time); exudation, optional, also varies between runs.
  Complex complex =
      options.exude
          ? CGAL::make_mesh_3<Complex>(domain, criteria, params::no_perturb(), params::exude())
          : CGAL::make_mesh_3<Complex>(domain, criteria, params::no_perturb(), params::no_exude());
  return toTetMesh(complex);
}

// Points the ray-vote inside test says are inside: most of kRays rays from the point cross the
// soup an odd number of times. Parity needs no consistent orientation, and a ray that leaves
// through a small hole is outvoted by the others, so a soup that cannot be made a closed oriented
// mesh (an orientation seam, holes) still has a well-defined inside.
class RayVoteInsideTest {
 public:
  static constexpr int kRays = 7;

  explicit RayVoteInsideTest(std::vector<Triangle> triangles) : triangles_(std::move(triangles)) {
    tree_.rebuild(triangles_.begin(), triangles_.end());
    tree_.accelerate_distance_queries();
    // Fibonacci directions: spread over the sphere and, being irrational, unlikely to graze an
    // edge or a vertex of a soup on a grid (which would count one crossing twice).
    const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
    for (int i = 0; i < kRays; ++i) {
      const double z = 1 - (2 * i + 1.0) / kRays, r = std::sqrt(1 - z * z);
      directions_[i] = Kernel::Vector_3(r * std::cos(golden * i), r * std::sin(golden * i), z);
    }
  }

  // How many of the rays from p cross the soup an odd number of times (0..kRays).
  int oddRays(const Point& p) const {
    int odd = 0;
    for (const Kernel::Vector_3& d : directions_)
      odd += static_cast<int>(tree_.number_of_intersected_primitives(Kernel::Ray_3(p, d)) % 2);
    return odd;
  }
  // Stops as soon as one side has a majority (4 rays, 5.5 on average instead of 7). After
  // sampleGrid, a point in the empty ball around its cell's sample (no triangle nearer the sample)
  // takes the sample's vote when that was unanimous: nothing separates the two, and Mesh_3's
  // queries deep inside or far outside cost no ray at all.
  bool inside(const Point& p) const {
    if (!votes_.empty()) {
      const auto slab = [this](double x, double lo, int n) {
        return std::clamp(static_cast<int>(std::floor((x - lo) / h_)), 0, n - 1);
      };
      const int i = slab(p.x(), origin_.x(), nx_), j = slab(p.y(), origin_.y(), ny_),
                k = slab(p.z(), origin_.z(), nz_);
      const std::size_t cell = (static_cast<std::size_t>(i) * ny_ + j) * nz_ + k;
      const int vote = votes_[cell];
      if ((vote == 0 || vote == kRays) &&
          CGAL::squared_distance(p, samplePoint(i, j, k)) < clearance_[cell])
        return vote == kRays;
    }
    int odd = 0, even = 0;
    for (const Kernel::Vector_3& d : directions_) {
      if (tree_.number_of_intersected_primitives(Kernel::Ray_3(p, d)) % 2 == 1) {
        if (2 * ++odd > kRays) return true;
      } else if (2 * ++even > kRays) {
        return false;
      }
    }
    return false;
  }
  double distance(const Point& p) const { return std::sqrt(tree_.squared_distance(p)); }
  CGAL::Bbox_3 bbox() const { return tree_.bbox(); }

  // Where the segment [a, b] crosses the soup, ordered from a (a face lying in the segment's
  // line counts by its middle).
  std::vector<Point> crossings(const Point& a, const Point& b) const {
    using Hit =
        boost::optional<TriangleTree::Intersection_and_primitive_id<Kernel::Segment_3>::Type>;
    std::vector<Hit> hits;
    tree_.all_intersections(Kernel::Segment_3(a, b), std::back_inserter(hits));
    std::vector<std::pair<double, Point>> along;
    const Kernel::Vector_3 ab = b - a;
    for (const Hit& hit : hits) {
      if (!hit) continue;
      Point p;
      if (const Point* q = boost::get<Point>(&hit->first)) {
        p = *q;
      } else if (const auto* seg = boost::get<Kernel::Segment_3>(&hit->first)) {
        p = CGAL::midpoint(seg->source(), seg->target());
      } else {
        continue;
      }
      along.emplace_back((p - a) * ab, p);
    }
    std::sort(along.begin(), along.end(),
              [](const auto& x, const auto& y) { return x.first < y.first; });
    std::vector<Point> points;
    points.reserve(along.size());
    for (const auto& [t, p] : along) points.push_back(p);
    return points;
  }

  // Votes all cell centres of a grid over the bounding box, about `samples` along its longest
  // side, and keeps them for inside(). Returns the volume called inside and the share of close
  // calls (see InsideVolume).
  struct InsideVolume {
    double volume = 0, closeVotes = 0;
  };
  InsideVolume sampleGrid(int samples);

 private:
  Point samplePoint(int i, int j, int k) const {
    return {origin_.x() + (i + 0.5) * h_, origin_.y() + (j + 0.5) * h_,
            origin_.z() + (k + 0.5) * h_};
  }

  std::vector<Triangle> triangles_;
  TriangleTree tree_;
  std::array<Kernel::Vector_3, kRays> directions_;
  std::vector<std::uint8_t> votes_;  // odd rays per grid sample, i-major
  std::vector<double> clearance_;    // squared distance from each sample to the soup
  Point origin_;
  double h_ = 0;
  int nx_ = 0, ny_ = 0, nz_ = 0;
};

// A closed surface with a few defects gives near-unanimous votes (a ray that leaves through a
// small hole loses 6 to 1); inside an open bowl the votes split. So the close calls (won by one
// ray, 4 to 3 either way) per sample called inside say whether the soup has a clear inside.
RayVoteInsideTest::InsideVolume RayVoteInsideTest::sampleGrid(int samples) {
  const CGAL::Bbox_3 box = bbox();
  h_ = std::max({box.xmax() - box.xmin(), box.ymax() - box.ymin(), box.zmax() - box.zmin()}) /
       samples;
  const auto count = [this](double lo, double hi) {
    return std::max(1, static_cast<int>(std::ceil((hi - lo) / h_)));
  };
  nx_ = count(box.xmin(), box.xmax());
  ny_ = count(box.ymin(), box.ymax());
  nz_ = count(box.zmin(), box.zmax());
  origin_ = Point(box.xmin(), box.ymin(), box.zmin());
  std::vector<std::uint8_t> votes(static_cast<std::size_t>(nx_) * ny_ * nz_);
  std::vector<double> clearance(votes.size());
  tbb::parallel_for(0, nx_, [&](int i) {
    for (int j = 0; j < ny_; ++j) {
      for (int k = 0; k < nz_; ++k) {
        const std::size_t cell = (static_cast<std::size_t>(i) * ny_ + j) * nz_ + k;
        const Point sample = samplePoint(i, j, k);
        votes[cell] = static_cast<std::uint8_t>(oddRays(sample));
        clearance[cell] = tree_.squared_distance(sample);
      }
    }
  });
  clearance_ = std::move(clearance);
  long inside = 0, close = 0;
  for (const std::uint8_t odd : votes) {
    if (2 * odd > kRays) ++inside;
    if (std::abs(2 * odd - kRays) == 1) ++close;
  }
  votes_ = std::move(votes);
  return {static_cast<double>(inside) * h_ * h_ * h_,
          inside > 0 ? static_cast<double>(close) / static_cast<double>(inside) : 1.0};
}

// The tets of the largest face-connected component, nodes renumbered; `dropped` counts the
// other components (debris of the soup meshed as separate pieces).
TetMesh keepLargestTetComponent(const TetMesh& mesh, int& dropped) {
  const Eigen::Index nt = mesh.numTets();
  std::map<std::array<int, 3>, int> faceOwner;
  std::vector<int> parent(static_cast<std::size_t>(nt));
  for (Eigen::Index t = 0; t < nt; ++t) parent[t] = static_cast<int>(t);
  const auto root = [&parent](int t) {
    while (parent[t] != t) t = parent[t] = parent[parent[t]];
    return t;
  };
  for (Eigen::Index t = 0; t < nt; ++t) {
    for (int f = 0; f < 4; ++f) {
      std::array<int, 3> face{};
      for (int c = 0, k = 0; c < 4; ++c)
        if (c != f) face[k++] = mesh.T(t, c);
      std::sort(face.begin(), face.end());
      auto [it, inserted] = faceOwner.emplace(face, static_cast<int>(t));
      if (!inserted) parent[root(it->second)] = root(static_cast<int>(t));
    }
  }
  std::map<int, int> sizes;
  for (Eigen::Index t = 0; t < nt; ++t) ++sizes[root(static_cast<int>(t))];
  dropped = static_cast<int>(sizes.size()) - 1;
  if (dropped <= 0) return mesh;
  const int keep = std::max_element(sizes.begin(), sizes.end(), [](const auto& a, const auto& b) {
                     return a.second < b.second;
                   })->first;
  std::vector<int> node(static_cast<std::size_t>(mesh.numNodes()), -1);
  std::vector<Eigen::Vector4i> tets;
  int next = 0;
  for (Eigen::Index t = 0; t < nt; ++t) {
    if (root(static_cast<int>(t)) != keep) continue;
    Eigen::Vector4i tet;
    for (int c = 0; c < 4; ++c) {
      int& n = node[static_cast<std::size_t>(mesh.T(t, c))];
      if (n < 0) n = next++;
      tet(c) = n;
    }
    tets.push_back(tet);
  }
  TetMesh out;
  out.V.resize(next, 3);
  for (Eigen::Index n = 0; n < mesh.numNodes(); ++n)
    if (node[n] >= 0) out.V.row(node[n]) = mesh.V.row(n);
  out.T.resize(static_cast<Eigen::Index>(tets.size()), 4);
  for (std::size_t t = 0; t < tets.size(); ++t) out.T.row(static_cast<Eigen::Index>(t)) = tets[t];
  out.region = Eigen::VectorXi::Zero(out.T.rows());
  return out;
}

// Runs meshAt(cell size) (Mesh_3 on a domain) with a cell size guessed from `volume` (m^3),
// corrected up to options.maxAttempts times towards options.targetNodes; keeps the closest run in
// result.mesh.
template <class MeshAt>
void meshToTargetNodes(const MeshAt& meshAt, double volume, const SurfaceMeshingOptions& options,
                       const std::string& source, SurfaceMeshingResult& result) {
  SurfaceMeshingReport& report = result.report;
  // A Delaunay mesh of size h holds about 1.5 V / h^3 nodes (about 5.5 regular tets of volume
  // h^3 / 8.5 per node). Surface nodes grow only like h^-2, so corrections use the exponent 1/2.5.
  double cellSize = std::cbrt(1.5 * volume / options.targetNodes);
  double bestError = std::numeric_limits<double>::infinity();
  for (int attempt = 0; attempt < std::max(1, options.maxAttempts); ++attempt) {
    TetMesh mesh = meshAt(cellSize);
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
}

// A Mesh_3 function of the inside test: negative inside, as Labeled_mesh_domain_3 expects.
struct RayVoteFunction {
  const RayVoteInsideTest* test;
  double operator()(const Point& p) const { return test->inside(p) ? -1.0 : 1.0; }
};

// Mesh_3's domain of the ray-vote test whose surface points come from the soup itself: where the
// ends of a segment Mesh_3 probes are voted apart, the point returned is the first of the
// segment's crossings with the triangles at which the vote changes (one AABB query and a vote on
// each side), not the end of 20 halvings of the segment, each a vote of 4-7 rays. A segment whose
// vote changes away from any triangle (over a hole) is halved as before.
class RayVoteDomain : public ImplicitDomain {
 public:
  RayVoteDomain(const ImplicitDomain& base, const RayVoteInsideTest* test)
      : ImplicitDomain(base), test_(test) {}

  struct Construct_intersection {
    const RayVoteDomain* domain;
    Intersection operator()(const Segment_3& s) const { return domain->intersect(s); }
    Intersection operator()(const Ray_3& r) const {
      return domain->ImplicitDomain::construct_intersection_object()(r);
    }
    Intersection operator()(const Line_3& l) const {
      return domain->ImplicitDomain::construct_intersection_object()(l);
    }
  };
  Construct_intersection construct_intersection_object() const { return {this}; }

 private:
  Intersection intersect(const Segment_3& s) const {
    const bool sourceInside = test_->inside(s.source());
    if (sourceInside == test_->inside(s.target())) return Intersection();
    // The vote between consecutive crossings, from the source on: the first crossing it changes
    // at. A vote that changes between crossings (near a hole) sends the segment to halving.
    const std::vector<Point> points = test_->crossings(s.source(), s.target());
    if (!points.empty() && test_->inside(CGAL::midpoint(s.source(), points[0])) == sourceInside) {
      for (std::size_t i = 0; i < points.size(); ++i) {
        const Point after =
            CGAL::midpoint(points[i], i + 1 < points.size() ? points[i + 1] : s.target());
        if (test_->inside(after) != sourceInside) {
          // Labels 0 (outside) and 1 (inside): the one surface patch there is.
          return Intersection(points[i], index_from_surface_patch_index({0, 1}), 2);
        }
      }
    }
    return ImplicitDomain::construct_intersection_object()(s);
  }

  const RayVoteInsideTest* test_;
};

constexpr double kVolumeTolerance = 0.05;  // mesh volume against the volume it should enclose
constexpr int kVolumeSamples = 48;         // grid samples along the longest side
constexpr double kMaxCloseVotes = 0.05;

// The route for a soup the repair could not close (or whose repaired surface folds onto itself):
// Mesh_3 on the ray-vote inside test of the soup itself. `why` is the repair's problem, kept in
// the report and in the error when this route fails too.
void meshFromRayVotes(const std::vector<Point>& points, const std::vector<Polygon>& polygons,
                      const SurfaceMeshingOptions& options, const std::string& source,
                      const std::string& why, SurfaceMeshingResult& result) {
  SurfaceMeshingReport& report = result.report;
  std::vector<Triangle> triangles;
  triangles.reserve(polygons.size());
  for (const Polygon& p : polygons) {
    if (p.size() == 3) triangles.emplace_back(points[p[0]], points[p[1]], points[p[2]]);
  }
  if (triangles.empty()) throw InputError(fmt::format("{}: {}", source, why));
  RayVoteInsideTest test(std::move(triangles));
  const RayVoteInsideTest::InsideVolume inside = test.sampleGrid(kVolumeSamples);
  report.closeVotes = inside.closeVotes;
  if (!(inside.volume > 0)) {
    throw InputError(fmt::format(
        "{}: {}; nor does it enclose any volume (no point of a {}-point grid is inside by the "
        "rays' vote)",
        source, why, kVolumeSamples));
  }
  if (inside.closeVotes > kMaxCloseVotes) {
    throw InputError(fmt::format(
        "{}: {}; nor does it enclose a clear inside (votes 4 to 3 at {:.0f} % of the inside, "
        "limit {:.0f} %)",
        source, why, 100 * inside.closeVotes, 100 * kMaxCloseVotes));
  }
  report.insideTestDomain = true;
  report.repairProblem = why;
  report.flippedFaces = report.holesFilled = report.genus = report.selfIntersections = 0;
  report.components = 1;
  report.surfaceVolume = inside.volume;

  namespace params = CGAL::parameters;
  const CGAL::Bbox_3 box = test.bbox();
  const Point centre((box.xmin() + box.xmax()) / 2, (box.ymin() + box.ymax()) / 2,
                     (box.zmin() + box.zmax()) / 2);
  const double radius = 0.55 * std::sqrt(CGAL::square(box.xmax() - box.xmin()) +
                                         CGAL::square(box.ymax() - box.ymin()) +
                                         CGAL::square(box.zmax() - box.zmin()));
  CGAL::Random rng(0);
  const RayVoteDomain domain(ImplicitDomain::create_implicit_mesh_domain(
                                 RayVoteFunction{&test}, Kernel::Sphere_3(centre, radius * radius),
                                 params::relative_error_bound = 1e-5, params::p_rng = &rng),
                             &test);
  // One random stream over the attempts (the figures of docs/liver-meshing.md were made so).
  meshToTargetNodes([&](double h) { return runMesh3(domain, h, options); }, inside.volume, options,
                    source, result);
  int dropped = 0;
  result.mesh = keepLargestTetComponent(result.mesh, dropped);
  report.components = 1 + dropped;

  const BoundarySurface boundary = extractBoundary(result.mesh);
  result.repaired = toTriMesh(result.mesh, boundary);
  // Mesh_3 puts the boundary nodes on the surface by bisection; the faces between them stand off
  // by up to the facet distance, so their centroids are measured too.
  report.boundaryDeviation = 0;
  const auto deviate = [&](const Vec3& p) {
    report.boundaryDeviation =
        std::max(report.boundaryDeviation, test.distance(Point(p.x(), p.y(), p.z())));
  };
  for (int n : boundary.nodes) deviate(result.mesh.V.row(n).transpose());
  for (Eigen::Index f = 0; f < boundary.F.rows(); ++f) {
    Vec3 centroid = Vec3::Zero();
    for (int c = 0; c < 3; ++c) centroid += result.mesh.V.row(boundary.F(f, c)).transpose() / 3;
    deviate(centroid);
  }
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
  // The soup as the rays see it: duplicates merged, degenerate faces dropped, no orientation.
  std::vector<Point> soupPoints;
  std::vector<Polygon> soupPolygons;
  std::string problem;
  try {
    const Surface repaired = repairSurface(surface, options.scale, options.maxHoleEdges, source,
                                           report, soupPoints, soupPolygons);
    if (!(report.surfaceVolume > 0))
      throw InputError(source + ": the repaired surface encloses no volume");
    result.repaired = toTriMesh(repaired);
    // Each attempt starts its own random stream from the same seed, as route 1 always has: its
    // meshes, and every liver figure made from them, stay the same.
    const auto meshAt = [&](double h) {
      CGAL::Random rng(0);
      const Domain domain(repaired, &rng);
      return runMesh3(domain, h, options);
    };
    meshToTargetNodes(meshAt, report.surfaceVolume, options, source, result);
    const double meshVolume = measureQuality(result.mesh).totalVolume;
    if (std::abs(meshVolume / report.surfaceVolume - 1) > kVolumeTolerance) {
      // Hole fills along an orientation seam fold the repaired surface onto itself: its signed
      // volume is no longer the organ's, and the mesh of it is not the organ either.
      problem = fmt::format(
          "the repaired surface encloses {:.4g} m^3 but its mesh {:.4g} m^3 ({} self-intersecting "
          "face pairs)",
          report.surfaceVolume, meshVolume, report.selfIntersections);
    }
  } catch (const InputError& e) {
    problem = e.what();
    if (problem.rfind(source + ": ", 0) == 0) problem.erase(0, source.size() + 2);
  }
  if (!problem.empty()) {
    report.attempts = 0;
    result.mesh = TetMesh{};
    meshFromRayVotes(soupPoints, soupPolygons, options, source, problem, result);
  }
  validateTetMesh(result.mesh, source);
  const MeshQuality quality = measureQuality(result.mesh);
  report.outputNodes = static_cast<int>(quality.numNodes);
  report.outputTets = static_cast<int>(quality.numTets);
  report.meshVolume = quality.totalVolume;
  report.minDihedralDeg = quality.minDihedralDeg;
  report.seconds = secondsSince(start);
  return result;
}

std::string describeMeshing(const SurfaceMeshingReport& r) {
  std::vector<std::string> parts;
  if (r.insideTestDomain) {
    parts.push_back(fmt::format(
        "meshed from the ray-vote inside test ({}; votes 4 to 3 at {:.1f} % of the inside; "
        "boundary within {:.2f} mm of the input)",
        r.repairProblem, 100 * r.closeVotes, 1e3 * r.boundaryDeviation));
  }
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

namespace {

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
    outcome.problem = describeMeshing(result.report);
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
