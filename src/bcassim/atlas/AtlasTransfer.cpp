#include "bcassim/atlas/AtlasTransfer.h"

#include "bcassim/Error.h"

namespace bcassim {

AtlasTransfer transferAtlas(const LigamentAtlas& atlas, const TriMesh& patient,
                            const RegistrationOptions& options, bool rigidAlign,
                            bool projectOntoPatient, double maxRotationDegrees,
                            const Eigen::MatrixX2i* patientRidge) {
  if (patient.F.rows() == 0) throw InputError("atlas transfer: the patient surface has no faces");
  if (patientRidge && atlas.templRidge.rows() == 0) {
    throw InputError(
        "atlas transfer: the atlas has no template ridge to match the patient's (build it from "
        "livers whose .eseg labels the ridge, 3)");
  }
  AtlasTransfer t;
  const CurvePair ridges{atlas.templRidge, patientRidge ? *patientRidge : Eigen::MatrixX2i()};
  if (rigidAlign) {
    t.rigid = alignRigidlyMultiStart(atlas.templ, patient, {}, 8, &t.rigidRms, maxRotationDegrees,
                                     &t.rigidReport, patientRidge ? &ridges : nullptr,
                                     options.curveWeight);
  } else {
    t.rigid.translation = Eigen::Vector3d::Zero();
  }
  TriMesh moved = atlas.templ;
  moved.V = t.rigid.apply(atlas.templ.V);
  t.registration = registerSurface(moved, patient, options, patientRidge ? &ridges : nullptr);
  t.deformedTemplate = TriMesh{t.registration.deformedVertices, atlas.templ.F};
  t.curve = carryCurve(atlas.curve, t.registration.deformedVertices);
  if (projectOntoPatient) t.curve = projectOnto(t.curve, patient);
  return t;
}

}  // namespace bcassim
