#include "bcassim/atlas/AtlasLeaveOneOut.h"

#include <fmt/format.h>

#include <algorithm>

#include "bcassim/Error.h"
#include "bcassim/Stopwatch.h"
#include "bcassim/atlas/FrechetMeanAtlas.h"
#include "bcassim/atlas/RigidAlignment.h"
#include "bcassim/atlas/SurfaceAttachment.h"

namespace bcassim {

LeaveOneOutResult leaveOneOut(const std::vector<AtlasSubject>& subjects,
                              const LeaveOneOutOptions& o, const AtlasLog& log) {
  const auto n = static_cast<int>(subjects.size());
  if (n < 3) throw InputError(fmt::format("leave-one-out: need at least 3 subjects, got {}", n));
  if (o.templateSubject < 0 || o.templateSubject >= n) {
    throw InputError(
        fmt::format("leave-one-out: template subject {} out of range", o.templateSubject));
  }
  std::vector<int> held = o.heldOut;
  if (held.empty()) {
    for (int i = 0; i < n; ++i)
      if (i != o.templateSubject) held.push_back(i);
  }
  for (int h : held) {
    if (h < 0 || h >= n || h == o.templateSubject) {
      throw InputError(fmt::format("leave-one-out: cannot hold out subject {}", h));
    }
  }
  auto say = [&](const std::string& s) {
    if (log) log(s);
  };
  auto boxCentre = [](const Eigen::MatrixX3d& V) -> Eigen::RowVector3d {
    return 0.5 * (V.colwise().minCoeff() + V.colwise().maxCoeff());
  };
  TriMesh templ = subjects[o.templateSubject].surface;
  templ.V.rowwise() -= boxCentre(templ.V);

  LeaveOneOutResult res;
  res.alignmentRms.assign(n, 0.0);
  res.scale.assign(n, 1.0);
  res.dataRatio.assign(n, 0.0);
  res.registrationSeconds.assign(n, 0.0);
  std::vector<Eigen::MatrixX3d> curves(n), carried(n), deformed(n);
  std::vector<bool> isHeld(n, false);
  for (int h : held) isHeld[h] = true;
  // The template's and subject i's ridges, for the multi-object data term and the rigid fit; the
  // held-out liver's only with ridgeOnHeldOut (its one rigid pose serves it as a training liver
  // of the other folds too, so without ridgeOnHeldOut that pose is the surface's alone).
  auto ridgePair = [&](int i) {
    return CurvePair{subjects[o.templateSubject].ridge, subjects[i].ridge};
  };
  auto ridgeUsed = [&](int i) { return o.ridge && (!isHeld[i] || o.ridgeOnHeldOut); };
  // Size and rigid alignment onto the centred template subject (surface and curve together; the
  // ridges too where the registrations use them).
  std::vector<TriMesh> aligned(n);
  std::vector<Eigen::MatrixX3d> alignedCurves(n);
  // Subject i's own frame -> its aligned one: x -> pose[i]((x - centres[i]) scale[i]).
  std::vector<RigidTransform> pose(n);
  std::vector<Eigen::RowVector3d> centres(n);
  for (int i = 0; i < n; ++i) {
    TriMesh s = subjects[i].surface;
    Eigen::MatrixX3d c = subjects[i].curve;
    const Eigen::RowVector3d ci = boxCentre(s.V);
    centres[i] = ci;
    s.V.rowwise() -= ci;
    c.rowwise() -= ci;
    if (i != o.templateSubject) {
      if (o.scaleAlign) {
        res.scale[i] = areaMatchingScale(s, templ);
        s.V *= res.scale[i];
        c *= res.scale[i];
      }
      MultiStartReport rep;
      const CurvePair ridge{subjects[i].ridge, subjects[o.templateSubject].ridge};
      const RigidTransform t = alignRigidlyMultiStart(
          s, templ, {}, 8, &res.alignmentRms[i], o.atlas.maxRotationDegrees, &rep,
          ridgeUsed(i) ? &ridge : nullptr, o.atlas.registration.curveWeight);
      for (const std::string& doubt : poseDoubts(rep, o.atlas.maxRotationDegrees))
        say(fmt::format("{}: {}", subjects[i].name, doubt));
      s.V = t.apply(s.V);
      c = t.apply(c);
      pose[i] = t;
    }
    aligned[i] = s;
    alignedCurves[i] = c;
  }
  std::vector<Eigen::MatrixX3d> deformedHeld(n);  // template -> h as a held-out liver sees it
  if (o.frechetTemplate) {
    // Template shape: Fréchet mean of the surfaces (eq. 4.8), started from the template subject.
    const auto t0 = Clock::now();
    RegistrationOptions ro = o.atlas.registration;
    ro.lbfgs.maxIterations = o.templateIterations;
    std::vector<CurvePair> ridges(n);
    for (int i = 0; i < n; ++i) ridges[i] = ridgePair(i);
    const AtlasResult fm = buildFrechetMeanAtlas(templ, aligned, ro, o.ridge ? &ridges : nullptr);
    templ = fm.mean;
    say(fmt::format(
        "Frechet-mean template of {} surfaces: {} iterations, objective {:.4g} -> {:.4g}, "
        "{:.1f} s",
        n, fm.iterations, fm.initialObjective, fm.objective, secondsSince(t0)));
  }
  for (int i = 0; i < n; ++i) {
    const auto t0 = Clock::now();
    const TriMesh& s = aligned[i];
    const Eigen::MatrixX3d& c = alignedCurves[i];
    if (i != o.templateSubject || o.frechetTemplate) {
      const CurvePair ridge = ridgePair(i);
      const RegistrationResult r =
          registerSurface(templ, s, o.atlas.registration, o.ridge ? &ridge : nullptr);
      deformed[i] = r.deformedVertices;
      res.dataRatio[i] = r.data / r.initialData;
      deformedHeld[i] = deformed[i];
      if (o.ridge && !ridgeUsed(i) && ridge.present()) {  // the held-out role, without it
        deformedHeld[i] = registerSurface(templ, s, o.atlas.registration).deformedVertices;
      }
    } else {
      deformed[i] = templ.V;
      deformedHeld[i] = templ.V;
    }
    curves[i] = c;
    carried[i] = SurfaceAttachment(TriMesh{deformed[i], templ.F}, c).positions(templ.V);
    res.registrationSeconds[i] = secondsSince(t0);
    say(fmt::format("{:>3}/{} {}: rigid RMS {:.1f} mm, data left {:.1f} %, {:.1f} s", i + 1, n,
                    subjects[i].name, 1e3 * res.alignmentRms[i], 100.0 * res.dataRatio[i],
                    res.registrationSeconds[i]));
  }
  // Distances on subject h in its own size (its curve and deformed template are scaled by
  // scale[h]).
  auto compare = [&](int h, const Eigen::MatrixX3d& predicted, const CuttingPlaneFamily& planes,
                     bool toBand = false) {
    CurveDistance d;
    if (!toBand) {
      d = compareCurves(curves[h], predicted, planes);
    } else if (subjects[h].band.rows() > 0) {
      d = compareCurveToBand(aligned[h].V, subjects[h].band, predicted, planes);
    }
    const double back = 1.0 / res.scale[h];
    d.planeMean *= back;
    d.planeMax *= back;
    d.pointMean *= back;
    d.pointMax *= back;
    return d;
  };
  // The atlas mean carried onto subject h by the deformation V of the template.
  auto predict = [&](int h, const CurveAtlas& atlas, const Eigen::MatrixX3d& V) {
    const CarriedCurve c = carryCurve(atlas, V);
    return o.projectOntoSubject ? projectOnto(c, aligned[h]).mean : c.mean;
  };
  // The fusion templates' own leave-one-outs: their curves for each held-out liver, in its frame.
  std::vector<std::vector<Eigen::MatrixX3d>> fromOthers(n);
  for (int other : o.fusionTemplates) {
    if (other < 0 || other >= n || other == o.templateSubject)
      throw InputError(fmt::format("leave-one-out: cannot fuse template subject {}", other));
    LeaveOneOutOptions oo = o;
    oo.templateSubject = other;
    oo.fusionTemplates.clear();
    oo.nearestCounts.clear();
    oo.heldOut.clear();
    for (int h : held)
      if (h != other) oo.heldOut.push_back(h);
    say(fmt::format("fusion: leave-one-out with template {}", subjects[other].name));
    for (LeaveOneOutFold& f : leaveOneOut(subjects, oo, log).folds)
      fromOthers[f.subject].push_back(std::move(f.predicted));
  }
  const auto toAligned = [&](int h, const Eigen::MatrixX3d& own) {
    Eigen::MatrixX3d c = own;
    c.rowwise() -= centres[h];
    return pose[h].apply(c * res.scale[h]);
  };
  const auto toOwn = [&](int h, const Eigen::MatrixX3d& inAligned) {
    Eigen::MatrixX3d c = pose[h].inverse().apply(inAligned) / res.scale[h];
    c.rowwise() += centres[h];
    return c;
  };
  for (int h : held) {
    std::vector<Eigen::MatrixX3d> others;
    for (int i = 0; i < n; ++i)
      if (i != h) others.push_back(carried[i]);
    const CurveAtlas atlas = ligamentCurveAtlas(templ, others, o.atlas);
    LeaveOneOutFold f;
    f.subject = h;
    f.atlasPoints = static_cast<int>(atlas.mean.size());
    const Eigen::MatrixX3d predicted = predict(h, atlas, deformedHeld[h]);
    f.distance = compare(h, predicted, atlas.planes);
    f.band = compare(h, predicted, atlas.planes, true);
    f.predicted = toOwn(h, predicted);
    f.rigidOnly = compare(h, predict(h, atlas, templ.V), atlas.planes);
    if (!o.fusionTemplates.empty()) {
      std::vector<Eigen::MatrixX3d> transferred{predicted};
      for (const Eigen::MatrixX3d& c : fromOthers[h]) transferred.push_back(toAligned(h, c));
      f.fusedCurves = static_cast<int>(transferred.size());
      const CurveAtlas fused = buildCurveAtlas(aligned[h], transferred, atlas.planes, 1,
                                               o.atlas.centre, o.atlas.outlierMads);
      const Eigen::MatrixX3d curve = fused.mean.positions(aligned[h].V);
      f.fused = compare(h, curve, atlas.planes);
      f.fusedBand = compare(h, curve, atlas.planes, true);
    }
    LigamentAtlasOptions om = o.atlas;
    om.centre = CurveCentre::Median;
    const CurveAtlas medianAtlas = ligamentCurveAtlas(templ, others, om);
    f.median = compare(h, predict(h, medianAtlas, deformedHeld[h]), medianAtlas.planes);
    om.centre = CurveCentre::Mean;
    const CurveAtlas meanAtlas = ligamentCurveAtlas(templ, others, om);
    f.plainMean = compare(h, predict(h, meanAtlas, deformedHeld[h]), meanAtlas.planes);
    if (!o.nearestCounts.empty()) {
      std::vector<std::pair<double, int>> byShape;
      for (int i = 0; i < n; ++i)
        if (i != h) byShape.emplace_back((deformed[i] - deformedHeld[h]).squaredNorm(), i);
      std::sort(byShape.begin(), byShape.end());
      for (int k : o.nearestCounts) {
        std::vector<Eigen::MatrixX3d> nearest;
        for (size_t j = 0; j < byShape.size() && static_cast<int>(j) < k; ++j)
          nearest.push_back(carried[static_cast<size_t>(byShape[j].second)]);
        const CurveAtlas a = ligamentCurveAtlas(templ, nearest, o.atlas);
        const Eigen::MatrixX3d p = predict(h, a, deformedHeld[h]);
        f.nearest.push_back(compare(h, p, a.planes));
        f.nearestBand.push_back(compare(h, p, a.planes, true));
      }
    }
    // No plane crossed by both curves: the per-plane distance is undefined, not 0 mm.
    const auto perPlane = [](const CurveDistance& d) {
      return d.planes == 0 ? std::string("no plane shared, distance undefined")
                           : fmt::format("{} planes, mean {:.1f} mm, max {:.1f} mm", d.planes,
                                         1e3 * d.planeMean, 1e3 * d.planeMax);
    };
    say(fmt::format("held out {}: {} (rigid only: {}; to the whole band: {})", subjects[h].name,
                    perPlane(f.distance), perPlane(f.rigidOnly), perPlane(f.band)));
    res.folds.push_back(f);
  }
  return res;
}

}  // namespace bcassim
