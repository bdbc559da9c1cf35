// Building a scene's parts from plain values (points, node sets, loads, a ligament curve,
// estimated spring coefficients): shared by the YAML loader and by scenes built in code
// (experiments/), so that a file and the code that wrote it make the same scene.
#pragma once
#include <Eigen/Core>
#include <string>
#include <vector>

#include "bcassim/ligaments/LigamentSprings.h"
#include "bcassim/mechanics/Loads.h"
#include "bcassim/scene/Scene.h"

namespace bcassim {

// Points (#points by 3, m) mapped into the rest mesh (markers, validation and hidden points); a
// point outside the mesh follows the closest point of the nearest tet.
MarkerSet mappedPointSet(const TetMesh& mesh, const Eigen::MatrixX3d& points);

// Mesh nodes as points that follow them (weight 1 on the node). Throws InputError "node <n>
// belongs to no tetrahedron".
MarkerSet nodePointSet(const TetMesh& mesh, const std::vector<int>& nodes);

// A load whose peak `totalForce` (N) is split evenly over `nodes` (loads: distribution: nodes).
NodalLoad evenNodalLoad(std::vector<int> nodes, const Vec3& totalForce, TimeProfile profile);

// Springs extruded from an attachment curve (#P by 3, m; springs.ligament, thesis §5.1) in
// `groups` groups of contiguous arc length; options.numGroups is set to it. Throws InputError as
// buildLigamentSprings.
std::vector<CubicSpring> ligamentSprings(const TetMesh& mesh, const Eigen::MatrixX3d& curve,
                                         LigamentOptions options, int groups);

// One estimated coefficient of a spring group (0 k_alpha N/m^3, 1 k_beta N/m^2, 2 k_gamma N/m),
// named by defaultParameterName: k_gamma_3 for coefficient 2 of group 3.
EstimatedParameter springParameter(int group, int coefficient, double mean, double stddev,
                                   ParameterTransform transform);

// Tracks of `numPoints` points read from `file` (CSV time,marker,x,y,z; s, m) on the scene's time
// grid (toStepFrames): the observed markers or the validation truth of an assimilation.
TrackFrames readStepFrames(const std::string& file, int numPoints, const std::string& pointsName,
                           double dt, int steps, double timeOffset);

}  // namespace bcassim
