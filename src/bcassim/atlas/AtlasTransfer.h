// Transfer of a ligament atlas to a patient (thesis §4.3.3, last step of Fig. 4.3): the template
// is aligned rigidly, then registered by LDDMM onto the patient's surface, and the mean curve and
// its ±sigma band follow by barycentric mapping.
#pragma once
#include "bcassim/atlas/LigamentAtlas.h"
#include "bcassim/atlas/RigidAlignment.h"

namespace bcassim {

struct AtlasTransfer {
  RigidTransform rigid;             // template frame -> patient frame
  double rigidRms = 0.0;            // residual of the rigid alignment (m)
  MultiStartReport rigidReport;     // its rotation, and a better fit refused as implausible
  RegistrationResult registration;  // of the rigidly moved template onto the patient
  TriMesh deformedTemplate;         // template at the end of the registration (patient frame)
  CarriedCurve curve;               // mean curve, band and sigma on the patient (m)
};

// patient: surface in its own frame (m). Control points default to a grid over the rigidly
// moved template. projectOntoPatient: the carried curve and band are moved to their closest
// points on the patient's surface (projectOnto). maxRotationDegrees: a rigid fit turning the
// template further is refused (RigidAlignment.h; kScannerFrameMaxRotationDegrees for CT livers,
// as the atlas commands do). patientRidge (optional): the patient's ridge as edges of `patient`,
// matched with the atlas' template ridge (multi-object data term, MultiObjectDistance.h).
// Throws InputError on a patient without faces, or a patient ridge the atlas has no ridge for.
AtlasTransfer transferAtlas(const LigamentAtlas& atlas, const TriMesh& patient,
                            const RegistrationOptions& options = {}, bool rigidAlign = true,
                            bool projectOntoPatient = false, double maxRotationDegrees = 180.0,
                            const Eigen::MatrixX2i* patientRidge = nullptr);

}  // namespace bcassim
