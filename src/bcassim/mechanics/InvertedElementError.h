// The error an element evaluation throws when a tet has det F <= 0 under a law that takes no
// inverted state: outside its domain (the log of Neo-Hookean, the polar decomposition of
// corotational) or a spurious collapsed state (StVK); the linear law alone takes it (see
// HyperelasticMaterial.h). Carries the first such tet, its det F and how many there are.
#pragma once
#include <fmt/format.h>

#include <Eigen/Core>

#include "bcassim/Error.h"

namespace bcassim {

class InvertedElementError : public NumericalError {
 public:
  InvertedElementError(Eigen::Index element, double detF, Eigen::Index count)
      : NumericalError(describe(element, detF, count)),
        element_(element),
        detF_(detF),
        count_(count) {}

  Eigen::Index element() const { return element_; }  // the first inverted tet (mesh index)
  double detF() const { return detF_; }              // its det F (-)
  Eigen::Index count() const { return count_; }      // tets with det F <= 0

 private:
  static std::string describe(Eigen::Index element, double detF, Eigen::Index count) {
    return count > 1 ? fmt::format("element {} inverted (det F = {:.3g}; {} tets with det F <= 0)",
                                   element, detF, count)
                     : fmt::format("element {} inverted (det F = {:.3g})", element, detF);
  }

  Eigen::Index element_;
  double detF_;
  Eigen::Index count_;
};

}  // namespace bcassim
