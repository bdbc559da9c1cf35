// The bad-input catalogue: every file of tests/data/bad/ run through the bcassim executable ends
// with exit code 2 and exactly the one-line message listed here (checkpoints and point-cloud CSVs:
// the InputError in-process), naming the file, the line, byte or element, and what was expected.
// One ctest case per class of bad input; docs/robustness.md says what each reader checks.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <ostream>
#include <set>
#include <string>
#include <vector>

#include "bcassim/Error.h"
#include "bcassim/io/BinaryArchive.h"
#include "bcassim/io/PointCloudFrames.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

// How a file is read: tet meshes by `mesh info`, surfaces by `atlas distance` (the file twice: the
// first read fails), scenes by `simulate`; checkpoints in-process, as `--resume` opens them
// (openCheckpoint).
constexpr const char* kMeshInfo = "mesh info {0}";
constexpr const char* kSurfaceRead = "atlas distance {0} {0}";
constexpr const char* kCheckpoint = "(openCheckpoint)";
constexpr const char* kCloudCsv = "(readCloudCsv)";  // observations.point_cloud
constexpr const char* kSimulate = "simulate {0} --out out --quiet";

struct BadInput {
  const char* file;     // in tests/data/bad/
  const char* command;  // {0} stands for the file's path, or kCheckpoint / kCloudCsv
  const char* message;  // after "bcassim: error: <path>"
};

const BadInput kCatalogue[] = {
    // Legacy VTK: the CELLS rows that overflowed VTK 9.1's heap (issue 18), one per line...
    {"vtk-cells-count-too-big.vtk", kMeshInfo, ":17: cell 2 has 4 point ids but its count says 5"},
    {"vtk-cells-count-zero.vtk", kMeshInfo, ":17: cell 2 has 4 point ids but its count says 0"},
    {"vtk-cells-count-negative.vtk", kMeshInfo,
     ":17: cell 2 has 4 point ids but its count says -1"},
    {"vtk-cells-extra-id.vtk", kMeshInfo, ":17: cell 2 has 5 point ids but its count says 4"},
    {"vtk-cells-missing-id.vtk", kMeshInfo, ":17: cell 2 has 3 point ids but its count says 4"},
    // ... and all on one line, as meshio writes them.
    {"vtk-cells-one-line-count-too-big.vtk", kMeshInfo,
     ":16: the CELLS rows end after 5 of their 6 cells (got 'CELL_TYPES'); a point count among "
     "them announces more ids than its row has"},
    {"vtk-cells-size-mismatch.vtk", kMeshInfo,
     ":14: CELLS 6 29 announces 29 values; its 6 rows hold 28"},
    // Counts that VTK would allocate ("Unable to allocate 6000000003 elements").
    {"vtk-cells-count-lies.vtk", kMeshInfo,
     ":14: CELLS 2000000001 6000000003 needs 6000000003 values (at least 12000000005 bytes), but "
     "the file has only 156 bytes left"},
    {"vtk-points-count-lies.vtk", kMeshInfo,
     ":5: POINTS 1000000000 needs 1000000000 x 3 values, but the file has only 215 bytes left"},
    // A binary file cut short (VTK: "Error reading binary data!").
    {"vtk-binary-truncated.vtk", kMeshInfo,
     ": byte 185: CELLS 6 28 needs 28 values (at least 112 bytes), but the file has only 41 bytes "
     "left"},
    // A cell list so long that its byte count would overflow a long long (make fuzz).
    {"vtk-cells-size-overflows-bytes.vtk", kMeshInfo,
     ": byte 232: CELLS 5 2833333333333333333 needs 2833333333333333333 values (4 bytes each), but "
     "the file has only 22 bytes left"},
    // A packed bit array whose tuple count overflowed when rounded up to bytes (make fuzz).
    {"vtk-bit-array-count-overflows.vtk", kMeshInfo,
     ": byte 161: FIELD array flags 9223372036854775807 x 1 bits, but the file has only 6 bytes "
     "left"},
    // Cell types: a hexahedron listed with 4 ids (VTK dropped it: a hole), one with 8 (not a tet),
    // a type VTK does not have.
    {"vtk-hexahedron-with-4-ids.vtk", kMeshInfo,
     ":17: cell 2 (hexahedron, VTK type 12) has 4 point ids; expected 8"},
    {"vtk-hexahedron.vtk", kMeshInfo,
     ":15: cell 0 is a hexahedron (VTK type 12); expected linear tetrahedra (VTK type 10), the "
     "only volume cells supported"},
    {"vtk-unknown-cell-type.vtk", kMeshInfo, ":23: cell 1 has the unknown VTK cell type 99"},
    {"vtk-point-id-out-of-range.vtk", kMeshInfo,
     ":17: cell 2 refers to point 8; the file has 8 points (0 to 7)"},
    {"vtk-nan-coordinate.vtk", kMeshInfo, ":8: value 'nan' is not a finite number"},
    // Raw escape bytes from a file are never printed to the terminal.
    {"vtk-escape-bytes-in-keyword.vtk", kMeshInfo,
     ":21: unknown keyword '\\x1b[31mCELL_TYPES'; expected POINTS, CELLS, CELL_TYPES, CELL_DATA, "
     "POINT_DATA or FIELD"},
    // VTK XML: an integer beyond 32 bits (VTK segfaulted), a huge component count (VTK hung).
    {"vtu-number-of-points-beyond-32-bits.vtu", kMeshInfo,
     ":4: <Piece>: NumberOfPoints=\"4294967297\"; expected an integer from 0 to 2147483647"},
    {"vtu-point-id-beyond-32-bits.vtu", kMeshInfo,
     ":11: <DataArray Name=\"connectivity\">: cell 0 refers to point 4294967300; the file has 8 "
     "points (0 to 7)"},
    {"vtu-huge-number-of-components.vtu", kMeshInfo,
     ":6: <DataArray Name=\"Points\">: NumberOfComponents=\"9999999999999\"; expected an integer "
     "from 0 to 65536"},
    {"vtu-offsets-decreasing.vtu", kMeshInfo,
     ":12: <DataArray Name=\"offsets\">: offset 2 is 6; expected at least 8 (offsets never "
     "decrease)"},
    {"vtu-binary-size-header-lies.vtu", kMeshInfo,
     ":6: <DataArray Name=\"Points\">: its data header says 1000000000 bytes; expected 96 (24 "
     "values of Float32)"},
    {"vtu-unclosed-element.vtu", kMeshInfo,
     ":15: </Piece> closes <Cells> (line 10); expected </Cells>"},
    {"vtu-deep-nesting.vtu", kMeshInfo, ":15: elements nested deeper than 64; expected a VTK file"},
    // Gmsh: what cannot be meant, named by the file's own tags and lines.
    {"msh-same-tet-twice.msh", kMeshInfo,
     ":24: element 8 has the same 4 nodes as element 4 (line 20); expected each tetrahedron once"},
    {"msh-unused-node.msh", kMeshInfo,
     ":14: node 18 belongs to no tetrahedron; expected every node in one (remove unused nodes "
     "from the file)"},
    {"msh-tet-repeats-node.msh", kMeshInfo,
     ":21: element 5 lists node 11 twice; expected 4 distinct nodes"},
    {"msh-flat-tet.msh", kMeshInfo,
     ":25: element 8 is degenerate (volume 0 m^3); expected a non-flat tetrahedron"},
    {"msh-hexahedron.msh", kMeshInfo,
     ":24: element 8 is a hexahedron (Gmsh type 5); expected linear tetrahedra (type 4), the only "
     "volume elements supported"},
    {"msh-hexahedron-with-4-nodes.msh", kMeshInfo,
     ":24: expected 13 fields in an element line (3, 2 tags, 8 nodes of type 5), got 9"},
    {"msh-truncated.msh", kMeshInfo,
     ": unexpected end of file in $Elements (line 22); expected 7 elements, read 6"},
    // Surfaces.
    {"stl-binary-count-lies.stl", kSurfaceRead,
     ": binary STL of 134 bytes announces 1000 triangles; expected 84 + 50 x 1000 = 50084 bytes"},
    {"stl-ascii-missing-endloop.stl", kSurfaceRead, ":7: expected 'endloop', got 'endfacet'"},
    {"obj-face-index-beyond-vertices.obj", kSurfaceRead,
     ":5: face refers to vertex 4, but the file defines 3 vertices"},
    {"obj-escape-bytes-in-coordinate.obj", kSurfaceRead,
     ":3: expected a number for vertex coordinate z, got '\\x1b[2J'"},
    {"vtk-polygon-with-2-points.vtk", kSurfaceRead,
     ":11: polygon 1 has 2 point ids; expected at least 3"},
    // Checkpoints: one flipped byte (in the number 30.0), a file cut short, format 1.
    {"checkpoint-flipped-byte.bin", kCheckpoint,
     ": damaged (checksum b582eb36); expected b4408101, the CRC-32 written at its end"},
    {"checkpoint-cut-short.bin", kCheckpoint,
     ": damaged (no checksum at its end: cut short?); expected a 'C' tag and a CRC-32 in its "
     "last 5 bytes"},
    {"checkpoint-format-1.bin", kCheckpoint,
     ": written by an older bcassim (checkpoint format 1, without a checksum); run without "
     "--resume"},
    // Found by fuzz_scene_yaml: yaml-cpp's message quoted a line break raw.
    {"scene-yaml-escape-of-a-line-break.yaml", kSimulate,
     ":6: invalid YAML: unknown escape character: \\x0a"},
    // Found by fuzz_checkpoint: the scene key stored in a checkpoint was printed raw.
    {"checkpoint-key-with-line-break.bin", kCheckpoint,
     ": written for another scene (\\x0a\\x00\\x00\\x00\\x00\\x00\\x00\\x00fuzz sceneN); "
     "this scene is fuzz scene"},
    // Found by fuzz_point_cloud: a field of a point-cloud CSV was quoted raw (a carriage return).
    {"cloud-csv-carriage-return-in-a-field.csv", kCloudCsv,
     ":3: field y is not a number ('0.\\x0d2')"},
};

std::filesystem::path badDir() {
  return std::filesystem::path(BCASSIM_SOURCE_DIR) / "tests" / "data" / "bad";
}

// ctest names a case by its file, never by the struct's bytes (pointers, new every build).
void PrintTo(const BadInput& bad, std::ostream* out) { *out << bad.file; }

class BadInputCatalogue : public ::testing::TestWithParam<BadInput> {};

TEST_P(BadInputCatalogue, ExitCode2AndTheExactOneLineMessage) {
  const BadInput& bad = GetParam();
  const std::string path = (badDir() / bad.file).string();
  ASSERT_TRUE(std::filesystem::is_regular_file(path)) << path;
  if (bad.command == kCloudCsv) {
    try {
      bool byTime = false;
      std::vector<std::string> notices;
      readCloudCsv(path, byTime, notices);
      ADD_FAILURE() << "expected an InputError";
    } catch (const InputError& e) {
      EXPECT_EQ(e.what(), fmt::format("{}{}", path, bad.message));
    }
    return;
  }
  if (bad.command == kCheckpoint) {
    try {
      openCheckpoint(path, "simulation", "fuzz scene");
      ADD_FAILURE() << "expected an InputError";
    } catch (const InputError& e) {
      EXPECT_EQ(e.what(), fmt::format("{}{}", path, bad.message));
    }
    return;
  }
  const test::CliResult r =
      test::runBcassim(test::freshDir(), fmt::format(fmt::runtime(bad.command), "'" + path + "'"));
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.err, fmt::format("bcassim: error: {}{}\n", path, bad.message));
  EXPECT_EQ(r.out, "");
}

INSTANTIATE_TEST_SUITE_P(Files, BadInputCatalogue, ::testing::ValuesIn(kCatalogue),
                         [](const ::testing::TestParamInfo<BadInput>& info) {
                           std::string name = info.param.file;
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

// A file added to tests/data/bad/ without its expected message would go untested.
TEST(BadInputCatalogue, ListsEveryFileOfTheFolder) {
  std::set<std::string> listed;
  for (const BadInput& bad : kCatalogue) listed.insert(bad.file);
  for (const auto& entry : std::filesystem::directory_iterator(badDir())) {
    const std::string name = entry.path().filename().string();
    if (name == "README.md") continue;
    EXPECT_TRUE(listed.count(name)) << name << " is not in the catalogue";
  }
}

}  // namespace
}  // namespace bcassim
