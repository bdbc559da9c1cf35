// A curve drawn on two surfaces (the liver's ridge, .eseg label 3) as edges of each: what the
// multi-object registration (MultiObjectDistance.h) and the rigid fit (RigidAlignment.h) match
// beside the surfaces.
#pragma once
#include <Eigen/Core>

namespace bcassim {

// source, target: vertex-index pairs into the source and the target surface. Either one empty:
// no curve term.
struct CurvePair {
  Eigen::MatrixX2i source, target;
  bool present() const { return source.rows() > 0 && target.rows() > 0; }
};

}  // namespace bcassim
