// libFuzzer target: .eseg edge labels of a small fixed surface (two triangles, 5 edges) through
// readEseg.
#include "FuzzInput.h"
#include "bcassim/ligaments/EsegLabels.h"

namespace {
bcassim::TriMesh twoTriangles() {
  bcassim::TriMesh mesh;
  mesh.V = Eigen::MatrixX3d::Zero(4, 3);
  mesh.V(1, 0) = mesh.V(2, 1) = mesh.V(3, 0) = mesh.V(3, 1) = 1.0;
  mesh.F.resize(2, 3);
  mesh.F << 0, 1, 2, 2, 1, 3;
  return mesh;
}
}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const bcassim::TriMesh surface = twoTriangles();
  const std::string path = bcassim::fuzz::writeInput(data, size, "input.eseg");
  bcassim::fuzz::expectOnlyInputErrors([&] { bcassim::readEseg(path, surface); });
  return 0;
}
