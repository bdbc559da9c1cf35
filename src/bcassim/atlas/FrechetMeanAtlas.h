// Fréchet-mean shape of a set of surfaces, thesis eq. 4.8: template vertices and one momentum
// set per shape minimise sum_i [w D(phi_i(template), M_i) + a_i^T K(q0, q0) a_i], by L-BFGS.
#pragma once
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "bcassim/atlas/Registration.h"
#include "bcassim/mesh/TriMesh.h"

namespace bcassim {

struct AtlasResult {
  TriMesh mean;                           // template with optimised vertices (initial faces)
  Eigen::MatrixX3d controlPoints;         // q0, #q by 3
  std::vector<Eigen::MatrixX3d> momenta;  // a_i, #q by 3 each: template to shape i
  std::vector<double> data;               // D(phi_i(mean), M_i)
  double objective = 0.0;                 // value of eq. 4.8 at the result
  double initialObjective = 0.0;          // at the initial template and zero momenta
  int iterations = 0;
  bool converged = false;
};

// initialTemplate: starting shape and connectivity (e.g. a rigidly aligned database shape);
// shapes: the database, in the same frame (m). Uses the registration options (kernels, data
// term, shooting, L-BFGS; control points default to a grid over the initial template).
// curves (optional, one per shape): a curve on the template and on shape i, matched too
// (multi-object data term; an empty pair: that shape's surface alone).
// Throws InputError on an empty database or bad options.
AtlasResult buildFrechetMeanAtlas(const TriMesh& initialTemplate,
                                  const std::vector<TriMesh>& shapes,
                                  const RegistrationOptions& options = {},
                                  const std::vector<CurvePair>* curves = nullptr);

// Value of eq. 4.8 and its gradient, for tests and custom optimisers: x stacks the template
// vertices (#V rows) then each shape's momenta (#q rows each), as one #V + n #q by 3 matrix.
class AtlasObjective {
 public:
  AtlasObjective(const TriMesh& initialTemplate, const std::vector<TriMesh>& shapes,
                 const RegistrationOptions& options,
                 const std::vector<CurvePair>* curves = nullptr);
  ~AtlasObjective();  // out of line: Impl is complete only in the .cpp
  double evaluate(const Eigen::MatrixX3d& x, Eigen::MatrixX3d* grad,
                  std::vector<double>* data = nullptr) const;
  const Eigen::MatrixX3d& controlPoints() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace bcassim
