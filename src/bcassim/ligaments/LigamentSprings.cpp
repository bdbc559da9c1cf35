// Extrusion of the attachment curve into cubic springs. Samples are snapped to the boundary
// because the curve comes from the CT surface, which Mesh_3 only approximates.
#include "bcassim/ligaments/LigamentSprings.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "bcassim/Error.h"
#include "bcassim/mesh/BarycentricMap.h"
#include "bcassim/mesh/BoundarySurface.h"
#include "bcassim/mesh/ClosestPoint.h"

namespace bcassim {
namespace {

struct Snapped {
  Vec3 point;
  Vec3 normal;
  double distance;
};

class SurfaceSnapper {
 public:
  SurfaceSnapper(const TetMesh& mesh, bool smooth)
      : boundary_(extractBoundary(mesh)),
        surface_(toTriMesh(mesh, boundary_)),
        locator_(surface_),
        smooth_(smooth) {}

  Snapped snap(const Vec3& p) const {
    const SurfacePoint sp = locator_.closest(p);
    Vec3 n = Vec3::Zero();
    if (smooth_) {
      for (int k = 0; k < 3; ++k) {
        const int node = boundary_.nodes[surface_.F(sp.face, k)];
        n += sp.barycentric(k) * boundary_.vertexNormals.row(node).transpose();
      }
    }
    if (n.norm() < 1e-12) n = boundary_.faceNormals.row(sp.face).transpose();
    return {sp.point, n.normalized(), sp.distance};
  }

  double meanEdgeLength() const {
    double sum = 0;
    for (Eigen::Index f = 0; f < surface_.F.rows(); ++f) {
      for (int k = 0; k < 3; ++k) {
        sum +=
            (surface_.V.row(surface_.F(f, k)) - surface_.V.row(surface_.F(f, (k + 1) % 3))).norm();
      }
    }
    return sum / (3.0 * surface_.F.rows());
  }

 private:
  BoundarySurface boundary_;
  TriMesh surface_;
  SurfaceLocator locator_;
  bool smooth_;
};

}  // namespace

LigamentSprings buildLigamentSprings(const TetMesh& mesh, const Eigen::MatrixX3d& curve,
                                     const LigamentOptions& options) {
  if (mesh.numTets() == 0) throw InputError("ligament: the tet mesh is empty");
  if (curve.rows() < 2) {
    throw InputError(
        fmt::format("ligament: the curve has {} points, at least 2 needed", curve.rows()));
  }
  if (!(options.length > 0) || options.numGroups < 1 || options.layers < 1 || options.layers > 2 ||
      options.spacing < 0 || options.layerOffset < 0) {
    throw InputError(fmt::format(
        "ligament: bad options (length {} m, groups {}, layers {}, spacing {} m, offset {} m); "
        "expected length > 0, groups >= 1, layers 1 or 2, spacing and offset >= 0",
        options.length, options.numGroups, options.layers, options.spacing, options.layerOffset));
  }
  const bool band = options.bandLower.rows() > 0 || options.bandUpper.rows() > 0;
  if (band && (options.bandLower.rows() != curve.rows() ||
               options.bandUpper.rows() != curve.rows() || options.layers != 2)) {
    throw InputError(fmt::format(
        "ligament: a band of {} lower and {} upper points with {} layer(s) for a curve of {} "
        "points; expected as many points on each edge as the curve has, and 2 layers",
        options.bandLower.rows(), options.bandUpper.rows(), options.layers, curve.rows()));
  }
  std::vector<double> cumulative(curve.rows(), 0.0);
  for (Eigen::Index i = 1; i < curve.rows(); ++i) {
    cumulative[i] = cumulative[i - 1] + (curve.row(i) - curve.row(i - 1)).norm();
  }
  const double length = cumulative.back();
  if (!(length > 0)) throw InputError("ligament: the curve has zero length");

  const SurfaceSnapper snapper(mesh, options.smoothNormals);
  const double spacing = options.spacing > 0 ? options.spacing : snapper.meanEdgeLength();
  const int n = std::max(options.numGroups, static_cast<int>(std::lround(length / spacing)));
  const int K = options.numGroups;

  // The curve's segment (points a, b) and fraction t at arc length s.
  struct Place {
    Eigen::Index a, b;
    double t;
  };
  auto placeAt = [&](double s) {
    const size_t i = std::min<size_t>(
        std::upper_bound(cumulative.begin(), cumulative.end(), s) - cumulative.begin(),
        cumulative.size() - 1);
    const size_t a = std::max<size_t>(i, 1) - 1;
    size_t b = a + 1;
    while (b + 1 < cumulative.size() && cumulative[b] <= cumulative[a]) ++b;  // skip repeats
    const double seg = cumulative[b] - cumulative[a];
    const double t = seg > 0 ? std::clamp((s - cumulative[a]) / seg, 0.0, 1.0) : 0.0;
    return Place{static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b), t};
  };
  auto pointOf = [](const Eigen::MatrixX3d& c, const Place& at) {
    const Vec3 pa = c.row(at.a).transpose(), pb = c.row(at.b).transpose();
    return Vec3(pa + at.t * (pb - pa));
  };

  std::vector<CubicSpring> springs;
  std::vector<Vec3> attachments, normals;
  LigamentSprings out;
  out.curveLength = length;
  const std::vector<double> offsets =
      options.layers == 1 ? std::vector<double>{0.0}
                          : std::vector<double>{options.layerOffset, -options.layerOffset};
  for (size_t layer = 0; layer < offsets.size(); ++layer) {
    const double offset = offsets[layer];
    for (int i = 0; i < n; ++i) {
      const double s = (i + 0.5) * length / n;
      const Place at = placeAt(s);
      const Vec3 tangent = (curve.row(at.b) - curve.row(at.a)).transpose().normalized();
      Snapped on = snapper.snap(pointOf(curve, at));
      out.maxSnapDistance = std::max(out.maxSnapDistance, on.distance);
      if (band) {
        // The edge's point across from this sample (the first layer on the lower edge).
        on = snapper.snap(pointOf(layer == 0 ? options.bandLower : options.bandUpper, at));
        out.maxSnapDistance = std::max(out.maxSnapDistance, on.distance);
      } else if (offset != 0) {
        // Across the curve within the tangent plane; re-snapped since the surface curves away.
        const Vec3 across = tangent.cross(on.normal).normalized();
        on = snapper.snap(on.point + offset * across);
      }
      CubicSpring spring;
      spring.weights = Vec4::Zero();  // set by the tet mapping below
      spring.anchor = on.point + options.length * on.normal;
      spring.restLength = options.length;
      spring.group = std::min(K - 1, static_cast<int>(std::floor(K * s / length)));
      springs.push_back(spring);
      attachments.push_back(on.point);
      normals.push_back(on.normal);
      out.arc.push_back(s);
    }
  }
  Eigen::MatrixX3d points(static_cast<Eigen::Index>(attachments.size()), 3);
  for (size_t i = 0; i < attachments.size(); ++i) points.row(i) = attachments[i].transpose();
  const std::vector<MappedPoint> mapped = mapPoints(mesh, points);
  for (size_t i = 0; i < springs.size(); ++i) {
    springs[i].tet = mapped[i].tet;
    springs[i].weights = mapped[i].weights;
  }
  out.attachments = points;
  out.normals.resize(points.rows(), 3);
  for (size_t i = 0; i < normals.size(); ++i) out.normals.row(i) = normals[i].transpose();
  out.springs = CubicSpringSet(std::move(springs),
                               std::vector<CubicSpringCoefficients>(K, options.coefficients));
  return out;
}

}  // namespace bcassim
