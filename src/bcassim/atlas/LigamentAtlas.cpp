#include "bcassim/atlas/LigamentAtlas.h"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <cmath>
#include <numbers>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/atlas/ControlPoints.h"
#include "bcassim/atlas/FrechetMeanAtlas.h"
#include "bcassim/atlas/GeodesicShooting.h"
#include "bcassim/atlas/RigidAlignment.h"

namespace bcassim {
namespace {
Eigen::RowVector3d boxCentre(const Eigen::MatrixX3d& V) {
  return 0.5 * (V.colwise().minCoeff() + V.colwise().maxCoeff());
}
}  // namespace

CurveAtlas ligamentCurveAtlas(const TriMesh& templ, const std::vector<Eigen::MatrixX3d>& carried,
                              const LigamentAtlasOptions& o) {
  if (carried.empty()) throw InputError("ligament atlas: no curves");
  // Radial planes around the transverse axis through the template centre; angle 0 points to the
  // mean of all carried curve points.
  const Eigen::Vector3d centre = boxCentre(templ.V).transpose();
  if (!(o.transverse.norm() > 0.0)) throw InputError("ligament atlas: zero transverse direction");
  const Eigen::Vector3d axis = o.transverse.normalized();
  Eigen::Vector3d towards = Eigen::Vector3d::Zero();
  Eigen::Index count = 0;
  for (const auto& c : carried) {
    towards += (c.rowwise() - centre.transpose()).colwise().sum().transpose();
    count += c.rows();
  }
  towards /= static_cast<double>(std::max<Eigen::Index>(count, 1));
  towards -= towards.dot(axis) * axis;
  if (towards.norm() < 1e-9) towards = axis.unitOrthogonal();
  CuttingPlaneFamily planes;
  if (o.planes == CuttingPlaneFamily::Kind::Parallel) {
    if (!(o.planeSpacing > 0.0)) throw InputError("ligament atlas: plane spacing must be positive");
    // Offsets from the centre along the axis, covering the template.
    const Eigen::VectorXd along = (templ.V.rowwise() - centre.transpose()) * axis;
    std::vector<double> offsets;
    for (double d = std::ceil(along.minCoeff() / o.planeSpacing) * o.planeSpacing;
         d <= along.maxCoeff(); d += o.planeSpacing)
      offsets.push_back(d);
    if (offsets.empty()) offsets.push_back(0.0);
    planes = parallelPlanes(centre, axis, offsets);
  } else {
    if (!(o.planeStepDegrees > 0.0)) {
      throw InputError("ligament atlas: plane step must be positive");
    }
    const double step = o.planeStepDegrees * std::numbers::pi / 180.0;
    const int half = static_cast<int>(std::floor(0.5 * std::numbers::pi / step + 1e-9));
    planes =
        radialPlanes(centre, axis, towards, evenAngles(-half * step, half * step, 2 * half + 1));
  }
  const auto n = static_cast<double>(carried.size());
  const int minCount = std::max(std::min(2, static_cast<int>(carried.size())),
                                static_cast<int>(std::ceil(o.minCrossingFraction * n)));
  return buildCurveAtlas(templ, carried, planes, minCount, o.centre, o.outlierMads);
}

LigamentAtlas buildLigamentAtlas(const std::vector<AtlasSubject>& subjects,
                                 const LigamentAtlasOptions& o, const AtlasLog& log) {
  auto say = [&](const std::string& s) {
    if (log) log(s);
  };
  const auto n = static_cast<int>(subjects.size());
  if (n < 2) throw InputError(fmt::format("ligament atlas: need at least 2 subjects, got {}", n));
  if (o.templateSubject < 0 || o.templateSubject >= n) {
    throw InputError(fmt::format("ligament atlas: template subject {} out of range (0..{})",
                                 o.templateSubject, n - 1));
  }
  for (const AtlasSubject& s : subjects) {
    if (s.surface.F.rows() == 0 || s.curve.rows() < 2) {
      throw InputError(
          fmt::format("ligament atlas: subject '{}' needs triangles and a curve of "
                      ">= 2 points",
                      s.name));
    }
  }
  LigamentAtlas atlas;
  atlas.templRidge = subjects[o.templateSubject].ridge;
  // 1. Rigid pre-alignment: the template subject centred on its bounding box, the others
  //    aligned onto it (surface and curve move together).
  const auto t0 = Clock::now();
  TriMesh initial = subjects[o.templateSubject].surface;
  const Eigen::RowVector3d c0 = boxCentre(initial.V);
  initial.V.rowwise() -= c0;
  std::vector<TriMesh> shapes(n);
  std::vector<Eigen::MatrixX3d> curves(n);
  atlas.alignmentRms.assign(n, 0.0);
  for (int i = 0; i < n; ++i) {
    const AtlasSubject& s = subjects[i];
    atlas.subjects.push_back(s.name);
    shapes[i] = s.surface;
    curves[i] = s.curve;
    const Eigen::RowVector3d ci = boxCentre(s.surface.V);
    shapes[i].V.rowwise() -= ci;
    curves[i].rowwise() -= ci;
    if (o.rigidAlign && i != o.templateSubject) {
      MultiStartReport rep;
      const CurvePair ridge{s.ridge, subjects[o.templateSubject].ridge};
      const RigidTransform t = alignRigidlyMultiStart(
          shapes[i], initial, {}, 8, &atlas.alignmentRms[i], o.maxRotationDegrees, &rep,
          o.ridge ? &ridge : nullptr, o.registration.curveWeight);
      for (const std::string& doubt : poseDoubts(rep, o.maxRotationDegrees))
        say(fmt::format("{}: {}", subjects[i].name, doubt));
      shapes[i].V = t.apply(shapes[i].V);
      curves[i] = t.apply(curves[i]);
    }
  }
  say(fmt::format("rigid alignment of {} subjects: {:.1f} s", n, secondsSince(t0)));

  // 2. Template and one deformation per subject.
  const auto t1 = Clock::now();
  RegistrationOptions ro = o.registration;
  if (ro.controlPoints.rows() == 0)
    ro.controlPoints = regularGridControlPoints(initial.V, ro.sigmaV);
  const GeodesicShooting shooting(ro.sigmaV, ro.shooting);
  std::vector<Eigen::MatrixX3d> deformed(n);  // template vertices flowed onto subject i
  atlas.data.assign(n, 0.0);
  std::vector<CurvePair> ridges(n);
  for (int i = 0; i < n; ++i) ridges[i] = {subjects[o.templateSubject].ridge, subjects[i].ridge};
  if (o.frechetMean) {
    const AtlasResult fm = buildFrechetMeanAtlas(initial, shapes, ro, o.ridge ? &ridges : nullptr);
    atlas.templ = fm.mean;
    for (int i = 0; i < n; ++i) {
      deformed[i] = shooting.flow(fm.controlPoints, fm.momenta[i], fm.mean.V);
      atlas.data[i] = fm.data[i];
    }
    say(fmt::format(
        "Frechet mean of {} shapes: {} iterations, objective {:.4g} -> {:.4g}, {:.1f} s", n,
        fm.iterations, fm.initialObjective, fm.objective, secondsSince(t1)));
  } else {
    atlas.templ = initial;
    for (int i = 0; i < n; ++i) {
      const auto ti = Clock::now();
      const RegistrationResult r =
          registerSurface(initial, shapes[i], ro, o.ridge ? &ridges[i] : nullptr);
      deformed[i] = r.deformedVertices;
      atlas.data[i] = r.data;
      say(fmt::format("  {}: data {:.3g} -> {:.3g}, {} iterations, {:.1f} s", subjects[i].name,
                      r.initialData, r.data, r.iterations, secondsSince(ti)));
    }
  }

  // 3. Each subject's curve onto the template: attached to the template flowed onto the subject,
  //    read back on the template's own vertices.
  for (int i = 0; i < n; ++i) {
    TriMesh phi{deformed[i], atlas.templ.F};
    atlas.carriedCurves.push_back(SurfaceAttachment(phi, curves[i]).positions(atlas.templ.V));
  }

  // 4. Statistics over radial planes.
  atlas.curve = ligamentCurveAtlas(atlas.templ, atlas.carriedCurves, o);
  const int minCount =
      std::max(2, static_cast<int>(std::ceil(o.minCrossingFraction * static_cast<double>(n))));
  say(fmt::format("curve statistics: {} of {} planes crossed by >= {} curves",
                  atlas.curve.mean.size(), atlas.curve.planes.planes.size(), minCount));
  return atlas;
}

}  // namespace bcassim
