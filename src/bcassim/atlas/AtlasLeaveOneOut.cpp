#include "bcassim/atlas/AtlasLeaveOneOut.h"

#include <fmt/format.h>

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
  // Size and rigid alignment onto the centred template subject (surface and curve together).
  std::vector<TriMesh> aligned(n);
  std::vector<Eigen::MatrixX3d> alignedCurves(n);
  for (int i = 0; i < n; ++i) {
    TriMesh s = subjects[i].surface;
    Eigen::MatrixX3d c = subjects[i].curve;
    const Eigen::RowVector3d ci = boxCentre(s.V);
    s.V.rowwise() -= ci;
    c.rowwise() -= ci;
    if (i != o.templateSubject) {
      if (o.scaleAlign) {
        res.scale[i] = areaMatchingScale(s, templ);
        s.V *= res.scale[i];
        c *= res.scale[i];
      }
      MultiStartReport rep;
      const RigidTransform t = alignRigidlyMultiStart(s, templ, {}, 8, &res.alignmentRms[i],
                                                      o.atlas.maxRotationDegrees, &rep);
      if (rep.rejected)
        say(fmt::format(
            "{}: the best rigid fit turns it {:.0f} deg (RMS {:.1f} mm), implausible for livers in "
            "scanner axes; kept the best within {:.0f} deg: {:.0f} deg (RMS {:.1f} mm)",
            subjects[i].name, rep.rejectedRotationDegrees, 1e3 * rep.rejectedRms,
            o.atlas.maxRotationDegrees, rep.rotationDegrees, 1e3 * rep.rms));
      s.V = t.apply(s.V);
      c = t.apply(c);
    }
    aligned[i] = s;
    alignedCurves[i] = c;
  }
  if (o.frechetTemplate) {
    // Template shape: Fréchet mean of the surfaces (eq. 4.8), started from the template subject.
    const auto t0 = Clock::now();
    RegistrationOptions ro = o.atlas.registration;
    ro.lbfgs.maxIterations = o.templateIterations;
    const AtlasResult fm = buildFrechetMeanAtlas(templ, aligned, ro);
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
      const RegistrationResult r = registerSurface(templ, s, o.atlas.registration);
      deformed[i] = r.deformedVertices;
      res.dataRatio[i] = r.data / r.initialData;
    } else {
      deformed[i] = templ.V;
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
  auto compare = [&](int h, const Eigen::MatrixX3d& predicted, const CuttingPlaneFamily& planes) {
    CurveDistance d = compareCurves(curves[h], predicted, planes);
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
  for (int h : held) {
    std::vector<Eigen::MatrixX3d> others;
    for (int i = 0; i < n; ++i)
      if (i != h) others.push_back(carried[i]);
    const CurveAtlas atlas = ligamentCurveAtlas(templ, others, o.atlas);
    LeaveOneOutFold f;
    f.subject = h;
    f.atlasPoints = static_cast<int>(atlas.mean.size());
    f.distance = compare(h, predict(h, atlas, deformed[h]), atlas.planes);
    f.rigidOnly = compare(h, predict(h, atlas, templ.V), atlas.planes);
    LigamentAtlasOptions om = o.atlas;
    om.centre = CurveCentre::Median;
    const CurveAtlas medianAtlas = ligamentCurveAtlas(templ, others, om);
    f.median = compare(h, predict(h, medianAtlas, deformed[h]), medianAtlas.planes);
    om.centre = CurveCentre::Mean;
    const CurveAtlas meanAtlas = ligamentCurveAtlas(templ, others, om);
    f.plainMean = compare(h, predict(h, meanAtlas, deformed[h]), meanAtlas.planes);
    say(fmt::format(
        "held out {}: {} planes, mean {:.1f} mm, max {:.1f} mm (rigid only: mean {:.1f} mm)",
        subjects[h].name, f.distance.planes, 1e3 * f.distance.planeMean, 1e3 * f.distance.planeMax,
        1e3 * f.rigidOnly.planeMean));
    res.folds.push_back(f);
  }
  return res;
}

}  // namespace bcassim
