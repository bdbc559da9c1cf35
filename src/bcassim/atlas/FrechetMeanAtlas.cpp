#include "bcassim/atlas/FrechetMeanAtlas.h"

#include <fmt/format.h>

#include <memory>

#include "bcassim/Error.h"
#include "bcassim/atlas/ControlPoints.h"
#include "bcassim/atlas/Lbfgs.h"
#include "bcassim/atlas/MultiObjectDistance.h"
#include "bcassim/atlas/RegistrationObjective.h"

namespace bcassim {

struct AtlasObjective::Impl {
  TriMesh tmpl;
  GeodesicShooting shooting;
  Eigen::MatrixX3d q0;
  std::vector<std::unique_ptr<SurfaceDistance>> distances;
  std::vector<std::unique_ptr<RegistrationObjective>> terms;
};

AtlasObjective::AtlasObjective(const TriMesh& initialTemplate, const std::vector<TriMesh>& shapes,
                               const RegistrationOptions& o, const std::vector<CurvePair>* curves) {
  if (shapes.empty()) throw InputError("atlas: no shapes");
  if (curves && curves->size() != shapes.size()) {
    throw InputError(
        fmt::format("atlas: {} curve pairs for {} shapes", curves->size(), shapes.size()));
  }
  auto impl = std::make_unique<Impl>(
      Impl{initialTemplate,
           GeodesicShooting(o.sigmaV, o.shooting),
           o.controlPoints.rows() > 0 ? o.controlPoints
                                      : regularGridControlPoints(initialTemplate.V, o.sigmaV),
           {},
           {}});
  const double weight = o.dataWeight > 0.0 ? o.dataWeight : 1.0 / (o.sigmaW * o.sigmaW);
  for (size_t i = 0; i < shapes.size(); ++i) {
    impl->distances.push_back(makeDataTerm(shapes[i], o, curves ? &(*curves)[i] : nullptr));
    impl->terms.push_back(std::make_unique<RegistrationObjective>(
        impl->tmpl, *impl->distances.back(), impl->shooting, impl->q0, weight));
  }
  impl_ = std::move(impl);
}

AtlasObjective::~AtlasObjective() = default;

const Eigen::MatrixX3d& AtlasObjective::controlPoints() const { return impl_->q0; }

double AtlasObjective::evaluate(const Eigen::MatrixX3d& x, Eigen::MatrixX3d* grad,
                                std::vector<double>* data) const {
  const Eigen::Index nv = impl_->tmpl.V.rows(), nq = impl_->q0.rows();
  const auto n = static_cast<Eigen::Index>(impl_->terms.size());
  if (x.rows() != nv + n * nq) {
    throw InputError(fmt::format("atlas: {} rows, expected {}", x.rows(), nv + n * nq));
  }
  const Eigen::MatrixX3d V = x.topRows(nv);
  if (grad) grad->setZero(x.rows(), 3);
  if (data) data->assign(static_cast<size_t>(n), 0.0);
  double total = 0.0;
  Eigen::MatrixX3d gA, gV;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::MatrixX3d a = x.middleRows(nv + i * nq, nq);
    const RegistrationTerms t =
        impl_->terms[i]->evaluateAt(V, a, grad ? &gA : nullptr, grad ? &gV : nullptr);
    total += t.total;
    if (data) (*data)[i] = t.data;
    if (grad) {
      grad->topRows(nv) += gV;
      grad->middleRows(nv + i * nq, nq) = gA;
    }
  }
  return total;
}

AtlasResult buildFrechetMeanAtlas(const TriMesh& initialTemplate,
                                  const std::vector<TriMesh>& shapes,
                                  const RegistrationOptions& options,
                                  const std::vector<CurvePair>* curves) {
  const AtlasObjective objective(initialTemplate, shapes, options, curves);
  const Eigen::Index nv = initialTemplate.V.rows(), nq = objective.controlPoints().rows();
  const auto n = static_cast<Eigen::Index>(shapes.size());
  Eigen::MatrixX3d x0 = Eigen::MatrixX3d::Zero(nv + n * nq, 3);
  x0.topRows(nv) = initialTemplate.V;
  // L-BFGS works on one vector; rows are stacked as (x, y, z) triples.
  auto toVector = [](const Eigen::MatrixX3d& m) {
    Eigen::VectorXd v(m.size());
    for (Eigen::Index i = 0; i < m.rows(); ++i) v.segment<3>(3 * i) = m.row(i).transpose();
    return v;
  };
  auto toMatrix = [](const Eigen::VectorXd& v) {
    Eigen::MatrixX3d m(v.size() / 3, 3);
    for (Eigen::Index i = 0; i < m.rows(); ++i) m.row(i) = v.segment<3>(3 * i).transpose();
    return m;
  };
  LbfgsOptions lbfgs = options.lbfgs;
  if (lbfgs.firstStepMaxNorm <= 0.0) lbfgs.firstStepMaxNorm = 0.05 * options.sigmaV;
  AtlasResult r;
  r.initialObjective = objective.evaluate(x0, nullptr);
  const LbfgsResult opt = minimizeLbfgs(
      [&](const Eigen::VectorXd& v, Eigen::VectorXd* g) {
        Eigen::MatrixX3d gm;
        const double value = objective.evaluate(toMatrix(v), &gm);
        *g = toVector(gm);
        return value;
      },
      toVector(x0), lbfgs);
  const Eigen::MatrixX3d x = toMatrix(opt.x);
  r.objective = objective.evaluate(x, nullptr, &r.data);
  r.mean = initialTemplate;
  r.mean.V = x.topRows(nv);
  r.controlPoints = objective.controlPoints();
  for (Eigen::Index i = 0; i < n; ++i) r.momenta.push_back(x.middleRows(nv + i * nq, nq));
  r.iterations = opt.iterations;
  r.converged = opt.converged;
  return r;
}

}  // namespace bcassim
