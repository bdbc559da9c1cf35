// `bcassim mesh info FILE`: counts, regions, bounding box, volumes and element quality of a tet
// mesh, one "name: value" line each.
#include <fmt/format.h>

#include <CLI/CLI.hpp>
#include <map>

#include "bcassim/VectorFormat.h"
#include "bcassim/cli/Commands.h"
#include "bcassim/io/MeshReader.h"
#include "bcassim/mesh/MeshQuality.h"

namespace bcassim {
namespace {

class MeshInfoCommand : public Command {
 public:
  MeshInfoCommand() : Command({"mesh", "info"}, "Counts, regions, bounding box and quality") {}

  void declare(CLI::App& app) override {
    app.add_option("file", path_, "Tet mesh (.vtk, .vtu, .msh, .mesh), coordinates in metres")
        ->required();
    app.add_option("--region-field", regionField_, "Integer cell array holding the region ids");
  }

  int run() override {
    const TetMesh mesh = readTetMesh(path_, regionField_);
    const MeshQuality q = measureQuality(mesh);
    std::map<int, long> tetsPerRegion;
    for (Eigen::Index t = 0; t < mesh.numTets(); ++t) ++tetsPerRegion[mesh.regionOf(t)];
    std::string regions;
    for (const auto& [id, count] : tetsPerRegion)
      regions += fmt::format("{}{} ({} tets)", regions.empty() ? "" : ", ", id, count);
    fmt::print("file: {}\n", path_);
    fmt::print("nodes: {}\n", q.numNodes);
    fmt::print("tets: {}\n", q.numTets);
    fmt::print("regions: {}\n", regions.empty() ? "none" : regions);
    fmt::print("bounding box: {} .. {} m (size {} m)\n", formatVec3(q.bboxMin),
               formatVec3(q.bboxMax), formatVec3(q.bboxMax - q.bboxMin));
    fmt::print("volume: {:.6g} m^3\n", q.totalVolume);
    fmt::print("tet volume: min {:.6g} m^3, max {:.6g} m^3\n", q.minVolume, q.maxVolume);
    fmt::print("inverted tets: {}\n", q.numInverted);
    fmt::print("dihedral angle: min {:.3f} deg, max {:.3f} deg\n", q.minDihedralDeg,
               q.maxDihedralDeg);
    return 0;
  }

 private:
  std::string path_, regionField_;
};

}  // namespace

std::unique_ptr<Command> makeMeshInfoCommand() { return std::make_unique<MeshInfoCommand>(); }

}  // namespace bcassim
