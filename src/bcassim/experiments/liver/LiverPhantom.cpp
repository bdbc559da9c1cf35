#include "bcassim/experiments/liver/LiverPhantom.h"

#include <cmath>

#include "bcassim/mesh/MeshGenerators.h"

namespace bcassim {

LiverPhantom makeLiverPhantom() {
  LiverPhantom p;
  TriMesh s = makeIcosphereSurface(1.0, 4);
  // Unit sphere -> liver-like wedge: wide and thick on the right (+x), thin on the left, flat
  // underneath (visceral side), domed on top.
  for (Eigen::Index i = 0; i < s.V.rows(); ++i) {
    const double x = s.V(i, 0), y = s.V(i, 1), z = s.V(i, 2);
    const double taper = 0.65 + 0.35 * x;  // 0.3 at the left tip, 1 at the right
    const double zz = z < 0 ? 0.6 * z : z;
    s.V.row(i) << 0.10 * x, 0.075 * y * (0.8 + 0.2 * taper), 0.055 * zz * taper;
  }
  p.surface = s;
  // Falciform: edges near the plane x = -0.02 on the anterior-superior quarter; ridge: edges on
  // the anterior-inferior rim.
  const auto edges = esegEdgeOrder(s);
  p.edges.edges = edges;
  p.edges.labels.assign(edges.size(), 1);
  auto falciform = [&](int v) {
    const double x = s.V(v, 0), y = s.V(v, 1), z = s.V(v, 2);
    return std::abs(x + 0.02) < 0.006 && y > 0.02 && z > -0.005;
  };
  auto ridge = [&](int v) {
    const double x = s.V(v, 0), y = s.V(v, 1), z = s.V(v, 2);
    return y > 0.04 && z < 0 && z > -0.015 && x > -0.06;
  };
  for (size_t e = 0; e < edges.size(); ++e) {
    const int a = edges[e][0], b = edges[e][1];
    if (falciform(a) && falciform(b))
      p.edges.labels[e] = 2;
    else if (ridge(a) && ridge(b))
      p.edges.labels[e] = 3;
  }
  return p;
}

}  // namespace bcassim
