#include "bcassim/navigation/RealTimeModel.h"

namespace bcassim {

namespace {

Eigen::VectorXd priorMeans(const Scene& scene) {
  const std::vector<EstimatedParameter>& p = scene.assimilation->parameters;
  Eigen::VectorXd v(static_cast<Eigen::Index>(p.size()));
  for (size_t i = 0; i < p.size(); ++i) v(static_cast<Eigen::Index>(i)) = p[i].mean;
  return v;
}

}  // namespace

RealTimeModel::RealTimeModel(const Scene& scene)
    : scene_(scene), run_(scene, scene.assimilation->parameters, priorMeans(scene)) {}

void RealTimeModel::adopt(const Eigen::VectorXd& values, const Eigen::VectorXd& x,
                          const Eigen::VectorXd& v, int step) {
  run_.setValues(scene_.assimilation->parameters, values);
  MechanicalState s = run_.state();
  s.x = x;
  if (v.size() == x.size()) s.v = v;
  s.t = step * scene_.dt();
  run_.restore(s, step);
}

void RealTimeModel::adoptParameters(const Eigen::VectorXd& values) {
  run_.setValues(scene_.assimilation->parameters, values);
}

void RealTimeModel::advanceTo(int step) {
  while (run_.steps() < step) run_.step();
}

Eigen::MatrixX3d RealTimeModel::hiddenPositions() const {
  return run_.positionsOf(scene_.hidden.points);
}

}  // namespace bcassim
