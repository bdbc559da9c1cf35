// Control points g_i of the LDDMM deformation (thesis eq. 4.1): by default a regular grid over
// the bounding box of the shape with the deformation kernel width as spacing.
#pragma once
#include <Eigen/Core>

namespace bcassim {

// Grid nodes, #q by 3, spaced by `spacing` (m) and centred on the bounding box of V (#V by 3);
// an axis shorter than the spacing gets one layer at its middle. Throws InputError on an empty V
// or a non-positive spacing.
Eigen::MatrixX3d regularGridControlPoints(const Eigen::MatrixX3d& V, double spacing);

}  // namespace bcassim
