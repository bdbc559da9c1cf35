// Rigid pre-alignment before the LDDMM registration of thesis §4.3 (the atlas removes position
// and orientation, keeps shape): Procrustes for paired points, ICP for surfaces.
#pragma once
#include <Eigen/Core>

#include "bcassim/mesh/RigidTransform.h"
#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

// Rotation (det +1) and translation minimising sum |R p_i + t - q_i|^2: kabschFit() of
// mesh/PointSetAlignment.h with equal weights, under the name the atlas code uses. P, Q: #P by 3,
// #P >= 3. Throws InputError on mismatched or too few rows.
RigidTransform procrustes(const Eigen::MatrixX3d& P, const Eigen::MatrixX3d& Q);

struct IcpOptions {
  int maxIterations = 50;
  double tolerance = 1e-10;  // stop when the RMS closest-point distance changes by less (m)
};

// Rigid transform taking the source surface onto the target: centroids matched first, then
// point-to-closest-point ICP from the source vertices to the target surface.
RigidTransform alignRigidly(const TriMesh& source, const TriMesh& target,
                            const IcpOptions& options = {});

// Like alignRigidly, but ICP is started from each of the 24 rotations that map the coordinate
// axes onto themselves (about the centroid) and the best start (smallest RMS distance after
// `probeIterations`) is refined: shapes scanned in different orientations still align. The
// identity wins ties. rmsOut (optional) receives the final RMS closest-point distance (m).
RigidTransform alignRigidlyMultiStart(const TriMesh& source, const TriMesh& target,
                                      const IcpOptions& options = {}, int probeIterations = 8,
                                      double* rmsOut = nullptr);

// Isotropic scale factor that gives `source` the surface area of `target`: sqrt(area(target) /
// area(source)). Size normalisation before registration (as in Procrustes analysis with
// scaling): the registration is then left with shape differences only. Throws InputError when
// either surface has zero area.
double areaMatchingScale(const TriMesh& source, const TriMesh& target);

}  // namespace bcassim
