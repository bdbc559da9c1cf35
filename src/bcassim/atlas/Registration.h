// Diffeomorphic registration of a source surface onto a target (thesis eq. 4.7): L-BFGS over the
// initial momenta of a geodesic on fixed control points, varifold (or current) data term.
#pragma once
#include <Eigen/Core>

#include "bcassim/atlas/CurvePair.h"
#include "bcassim/atlas/FaceKernelSum.h"
#include "bcassim/atlas/GeodesicShooting.h"
#include "bcassim/atlas/Lbfgs.h"
#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

struct RegistrationOptions {
  double sigmaV = 0.02;  // deformation kernel width (m); also the default control-point spacing
  double sigmaW = 0.01;  // data-term kernel width (m)
  FaceKernelKind dataTerm = FaceKernelKind::Varifold;
  double dataWeight = 0.0;  // weight of the data term; <= 0: 1 / sigmaW^2 as in eq. 4.7
  ShootingOptions shooting;
  LbfgsOptions lbfgs;               // firstStepMaxNorm <= 0: 0.05 sigmaV
  Eigen::MatrixX3d controlPoints;   // #q by 3; empty: regular grid over the source, spacing sigmaV
  Eigen::MatrixX3d initialMomenta;  // #q by 3; empty: zero
  // Weight of a curve drawn on both surfaces (CurvePair) in the multi-object data term,
  // relative to the surface's (MultiObjectDistance.h); 0: the surfaces alone.
  double curveWeight = 1.0;
};

struct RegistrationResult {
  Eigen::MatrixX3d controlPoints;     // q0, #q by 3
  Eigen::MatrixX3d momenta;           // a0, #q by 3
  Eigen::MatrixX3d deformedVertices;  // source vertices at t = 1, #V by 3
  double initialData = 0.0;           // D(S, T) before registration
  double data = 0.0;                  // D(phi(S), T)
  double regularity = 0.0;            // a0^T K a0
  int iterations = 0;
  int evaluations = 0;
  bool converged = false;
};

// curves (optional): a curve on both surfaces, matched too (multi-object data term).
// Throws InputError on bad options or meshes.
RegistrationResult registerSurface(const TriMesh& source, const TriMesh& target,
                                   const RegistrationOptions& options = {},
                                   const CurvePair* curves = nullptr);

}  // namespace bcassim
