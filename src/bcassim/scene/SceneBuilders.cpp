#include "bcassim/scene/SceneBuilders.h"

#include "bcassim/scene/AssimilationSettingsReader.h"
#include "bcassim/scene/NodePoints.h"

namespace bcassim {

MarkerSet mappedPointSet(const TetMesh& mesh, const Eigen::MatrixX3d& points) {
  MarkerSet set;
  set.points = mapPoints(mesh, points);
  set.rest = points;
  return set;
}

MarkerSet nodePointSet(const TetMesh& mesh, const std::vector<int>& nodes) {
  const std::vector<int> tetOf = tetOfEachNode(mesh);
  MarkerSet set;
  set.rest.resize(static_cast<Eigen::Index>(nodes.size()), 3);
  for (size_t i = 0; i < nodes.size(); ++i) {
    set.points.push_back(mappedNode(mesh, tetOf, nodes[i]));
    set.rest.row(static_cast<Eigen::Index>(i)) = mesh.V.row(nodes[i]);
  }
  return set;
}

NodalLoad evenNodalLoad(std::vector<int> nodes, const Vec3& totalForce, TimeProfile profile) {
  NodalLoad load;
  load.forcePerNode = totalForce / static_cast<double>(nodes.size());
  load.nodes = std::move(nodes);
  load.profile = profile;
  return load;
}

std::vector<CubicSpring> ligamentSprings(const TetMesh& mesh, const Eigen::MatrixX3d& curve,
                                         LigamentOptions options, int groups) {
  options.numGroups = groups;
  return buildLigamentSprings(mesh, curve, options).springs.springs();
}

EstimatedParameter springParameter(int group, int coefficient, double mean, double stddev,
                                   ParameterTransform transform) {
  EstimatedParameter p;
  p.target = SpringCoefficientTarget{group, coefficient};
  p.name = defaultParameterName(p.target);
  p.mean = mean;
  p.stddev = stddev;
  p.transform = transform;
  return p;
}

TrackFrames readStepFrames(const std::string& file, int numPoints, const std::string& pointsName,
                           double dt, int steps, double timeOffset) {
  return toStepFrames(readMarkerTracks(file), file, numPoints, pointsName, dt, steps, timeOffset);
}

}  // namespace bcassim
