// Leave-one-out validation of the ligament atlas (thesis §5.2, Table 5.1): for each held-out organ,
// the curve statistics of all the others are transferred to it and compared with its expert curve.
#pragma once
#include <vector>

#include "bcassim/atlas/CurveComparison.h"
#include "bcassim/atlas/LigamentAtlas.h"

namespace bcassim {

struct LeaveOneOutOptions {
  LigamentAtlasOptions atlas;  // registration, planes, per-plane centre; frechetMean is ignored
                               // (see frechetTemplate)
  int templateSubject = 0;  // the fixed template, or the start of the Fréchet mean (never held out)
  std::vector<int> heldOut;  // subjects to hold out; empty: every subject but the template
  // Size normalisation: each subject is scaled about its centre to the template's surface area
  // (areaMatchingScale) before the rigid alignment and the registration; distances to the expert
  // curve are measured back in the subject's own size.
  bool scaleAlign = false;
  // Template shape: false, the centred template subject itself; true, the Fréchet mean (eq. 4.8)
  // of every subject's aligned surface started from it (templateIterations L-BFGS iterations),
  // onto which every subject, the template subject included, is then registered. Only surfaces
  // enter the mean, never curves.
  bool frechetTemplate = false;
  int templateIterations = 60;
  // The carried mean curve is moved to its closest points on the held-out surface (projectOnto)
  // before it is compared with the expert curve, as transferAtlas(..., projectOntoPatient).
  bool projectOntoSubject = false;
  // Multi-object data term (MultiObjectDistance.h): the ridge (.eseg label 3) of the template
  // and of each subject is matched along with the surfaces (weight atlas.registration.curveWeight;
  // the Fréchet-mean template too). The training curves are carried by those registrations; the
  // held-out liver is registered once more from its surface alone, as a patient without labels,
  // unless ridgeOnHeldOut (a patient whose ridge is labelled or detected).
  bool ridge = false;
  bool ridgeOnHeldOut = false;
  // Also, for each k here, the fold's atlas from the k training livers nearest in shape to the
  // held-out one: the RMS distance between their deformed templates (the template's vertices
  // carried onto each, so in correspondence; the held-out one's from its surface alone) —
  // LeaveOneOutFold::nearest, in this order.
  std::vector<int> nearestCounts;
  // Multi-template fusion: the leave-one-out is run again with each of these subjects as the
  // template (every other option the same), and each fold's curve is the per-plane centre
  // (atlas.centre) of the curves the templates transferred onto the held-out liver, on this
  // template's planes, projected onto the liver — LeaveOneOutFold::fused. A fusion template is
  // never held out by its own run: its fold fuses the others'.
  std::vector<int> fusionTemplates;
};

struct LeaveOneOutFold {
  int subject = -1;
  int atlasPoints = 0;      // mean-curve points of this fold's atlas
  CurveDistance distance;   // transferred mean curve vs the expert curve (m)
  CurveDistance rigidOnly;  // same with the template only aligned rigidly (no LDDMM), for contrast
  CurveDistance median;     // LDDMM, per-plane geometric median instead of options' centre
  CurveDistance plainMean;  // LDDMM, per-plane mean of all crossings (the thesis' centre)
  CurveDistance band;       // distance, against the expert's whole annotated band (planes = 0
                            // when the subject has no band)
  std::vector<CurveDistance> nearest;      // per LeaveOneOutOptions::nearestCounts: distance
  std::vector<CurveDistance> nearestBand;  // and band, with the k nearest livers' atlas
  CurveDistance fused;      // with LeaveOneOutOptions::fusionTemplates: the fused curve's distance
  CurveDistance fusedBand;  // and band
  int fusedCurves = 0;      // curves fused (this template's and those of the fusion templates)
  Eigen::MatrixX3d predicted;  // the transferred mean curve in the subject's own frame (m)
};

struct LeaveOneOutResult {
  std::vector<LeaveOneOutFold> folds;
  std::vector<double> alignmentRms;         // per subject (m)
  std::vector<double> scale;                // per subject: size normalisation (1 without)
  std::vector<double> dataRatio;            // final / initial data term of template -> subject
  std::vector<double> registrationSeconds;  // per subject
};

// The template subject (centred on its bounding box) is registered once onto every subject after
// rigid multi-start alignment; subject i's curve is carried onto the template through that
// registration. Fold h builds the curve statistics from every carried curve but h's and carries
// the mean curve back onto subject h through the same template -> h registration, which never
// sees h's curve. With a fixed template this costs one registration per subject instead of one
// atlas per fold (the Fréchet-mean template of buildLigamentAtlas would differ per fold).
// Throws InputError on fewer than 3 subjects or bad indices.
LeaveOneOutResult leaveOneOut(const std::vector<AtlasSubject>& subjects,
                              const LeaveOneOutOptions& options = {}, const AtlasLog& log = {});

}  // namespace bcassim
