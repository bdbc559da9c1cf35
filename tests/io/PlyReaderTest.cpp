// PLY files (io/PlyReader) through readSurface, readPoints and readCloudFile: hand-written ASCII
// and byte-built binary files of both byte orders read to the same numbers, files written by
// VTK's vtkPLYWriter read back as written, and every malformed case is its exact one-line error.
#include <gtest/gtest.h>
#include <vtkNew.h>
#include <vtkPLYWriter.h>
#include <vtkXMLPolyDataReader.h>

#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "bcassim/io/PointCloudFrames.h"
#include "bcassim/io/PointReader.h"
#include "bcassim/io/SurfaceReader.h"
#include "bcassim/mesh/MeshGenerators.h"
#include "io/IoTestSupport.h"

namespace bcassim {
namespace {

using test::TempDir;
using test::writeText;

// A unit square (two faces: a quad and, on top, a triangle), with normals, colours and an extra
// element the reader must skip.
const char* kAsciiSquare =
    "ply\r\n"
    "format ascii 1.0\r\n"
    "comment made by hand\r\n"
    "element vertex 5\r\n"
    "property float x\r\n"
    "property float y\r\n"
    "property double z\r\n"
    "property uchar red\r\n"
    "element face 2\r\n"
    "property list uchar int vertex_indices\r\n"
    "element edge 1\r\n"
    "property int vertex1\r\n"
    "property list uchar float weights\r\n"
    "end_header\r\n"
    "0 0 0 255\r\n"
    "1 0 0 0\r\n"
    "1 1 0 0\r\n"
    "0 1 0 0\r\n"
    "0.5 0.5 0.25 7\r\n"
    "4 0 1 2 3\r\n"
    "3 0 1 4\r\n"
    "0 2 0.5 1.5\r\n";

void expectSquare(const TriMesh& mesh) {
  Eigen::MatrixX3d V(5, 3);
  V << 0, 0, 0, 1, 0, 0, 1, 1, 0, 0, 1, 0, 0.5, 0.5, 0.25;
  Eigen::MatrixX3i F(3, 3);
  F << 0, 1, 2, 0, 2, 3, 0, 1, 4;  // the quad fanned from its first vertex
  EXPECT_EQ(mesh.V, V);
  EXPECT_EQ(mesh.F, F);
}

// Binary values of `bytes` bytes, least or most significant byte first.
class Bytes {
 public:
  explicit Bytes(bool bigEndian) : big_(bigEndian) {}
  Bytes& f32(float v) { return word(std::bit_cast<std::uint32_t>(v), 4); }
  Bytes& f64(double v) { return word(std::bit_cast<std::uint64_t>(v), 8); }
  Bytes& i32(std::int32_t v) { return word(static_cast<std::uint32_t>(v), 4); }
  Bytes& u8(std::uint8_t v) { return word(v, 1); }
  Bytes& u16(std::uint16_t v) { return word(v, 2); }
  std::string str() const { return s_; }

 private:
  Bytes& word(std::uint64_t v, int n) {
    for (int k = 0; k < n; ++k) s_ += static_cast<char>((v >> (8 * (big_ ? n - 1 - k : k))) & 0xff);
    return *this;
  }
  bool big_;
  std::string s_;
};

std::string binarySquare(bool bigEndian) {
  std::string header = std::string("ply\nformat ") +
                       (bigEndian ? "binary_big_endian" : "binary_little_endian") +
                       " 1.0\n"
                       "element vertex 5\n"
                       "property float x\nproperty float y\nproperty double z\n"
                       "property ushort intensity\n"
                       "element face 2\n"
                       "property list uchar int vertex_indices\n"
                       "property list uchar uchar flags\n"
                       "end_header\n";
  Bytes b(bigEndian);
  const double xyz[5][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0.5, 0.5, 0.25}};
  for (const auto& p : xyz)
    b.f32(static_cast<float>(p[0])).f32(static_cast<float>(p[1])).f64(p[2]).u16(1000);
  b.u8(4).i32(0).i32(1).i32(2).i32(3).u8(1).u8(9);
  b.u8(3).i32(0).i32(1).i32(4).u8(0);
  return header + b.str();
}

TEST(PlyReader, AsciiAndBinaryOfBothByteOrdersReadAlike) {
  TempDir dir;
  expectSquare(readSurface(writeText(dir.file("ascii.ply"), kAsciiSquare)));
  expectSquare(readSurface(writeText(dir.file("le.ply"), binarySquare(false))));
  expectSquare(readSurface(writeText(dir.file("be.ply"), binarySquare(true))));
  // As points: every vertex, the faces ignored; the same through the cloud reader.
  const Eigen::MatrixX3d P = readPoints(dir.file("be.ply"));
  EXPECT_EQ(P.rows(), 5);
  EXPECT_EQ(P.row(4), Eigen::RowVector3d(0.5, 0.5, 0.25));
  std::vector<std::string> notices;
  EXPECT_EQ(readCloudFile(dir.file("ascii.ply"), notices), P);
  EXPECT_TRUE(notices.empty());
}

TEST(PlyReader, FilesWrittenByVtkReadBackAsWritten) {
  const TriMesh sphere = makeIcosphereSurface(0.07, 2);
  TempDir dir;
  // VTK's own poly data of the sphere: written by bcassim, read back by VTK's reader.
  writeSurface(dir.file("sphere.vtp"), sphere);
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(dir.file("sphere.vtp").c_str());
  reader->Update();
  int written = 0;
  for (const int mode : {VTK_ASCII, VTK_BINARY}) {
    for (const int order : {VTK_LITTLE_ENDIAN, VTK_BIG_ENDIAN}) {
      if (mode == VTK_ASCII && order == VTK_BIG_ENDIAN) continue;
      const std::string path = dir.file("sphere" + std::to_string(written++) + ".ply");
      vtkNew<vtkPLYWriter> writer;
      writer->SetFileName(path.c_str());
      writer->SetInputConnection(reader->GetOutputPort());
      writer->SetFileType(mode);
      writer->SetDataByteOrder(order);
      ASSERT_EQ(writer->Write(), 1);
      const TriMesh read = readSurface(path);
      // vtkPLYWriter stores points as float: the sphere rounded to float, bit for bit.
      EXPECT_EQ(read.V, sphere.V.cast<float>().cast<double>()) << path;
      EXPECT_EQ(read.F, sphere.F) << path;
    }
  }
}

TEST(PlyReader, NonFinitePointsAreDroppedFromCloudsAndRefusedElsewhere) {
  TempDir dir;
  const std::string path =
      writeText(dir.file("cloud.ply"),
                "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
                "property float z\nend_header\n0 0 0\nnan 0 0\n1 2 3\n");
  std::vector<std::string> notices;
  const Eigen::MatrixX3d P = readCloudFile(path, notices);
  ASSERT_EQ(P.rows(), 2);
  EXPECT_EQ(P.row(1), Eigen::RowVector3d(1, 2, 3));
  ASSERT_EQ(notices.size(), 1u);
  EXPECT_EQ(notices[0], "cloud.ply: 1 point not finite (vertex 1 first), dropped");
  EXPECT_THROW(readPoints(path), InputError);
  // A folder of .ply frames is a cloud sequence.
  writeText(dir.file("pc2.ply"), kAsciiSquare);
  const std::vector<std::string> files = cloudFrameFiles(dir.file("pc*.ply"));
  ASSERT_EQ(files.size(), 1u);
}

TEST(PlyReader, MalformedFilesAreOneLineErrors) {
  TempDir dir;
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\n"
      "property float z\n";
  const auto surface = [&](const std::string& text) {
    const std::string path = writeText(dir.file("bad.ply"), text);
    return [path] { readSurface(path); };
  };
  const std::string p = dir.file("bad.ply");
  const auto expectError = [&](const std::string& text, const std::string& message) {
    const auto read = surface(text);
    EXPECT_INPUT_ERROR(p + message, read());
  };
  expectError("solid x\n", ":1: 'solid x'; expected 'ply' (a PLY file's first line)");
  expectError("ply\nformat binary 1.0\n",
              ":2: 'format binary 1.0'; expected 'format ascii 1.0', 'format "
              "binary_little_endian 1.0' or 'format binary_big_endian 1.0'");
  expectError("ply\nformat ascii 1.0\nelement vertex 2\n",
              ": no 'end_header' line; expected the PLY header to end with one");
  expectError("ply\nformat ascii 1.0\nproperty float x\n",
              ":3: a property before any element; expected 'element' first");
  expectError("ply\nformat ascii 1.0\nelement vertex -1\n",
              ":3: 'element vertex -1'; expected 'element NAME COUNT' with a count in [0, 2^31)");
  expectError(head + "property half w\nend_header\n",
              ":7: property type 'half' unknown; expected char, uchar, short, ushort, int, uint, "
              "float, double (or int8, uint8, int16, uint16, int32, uint32, float32, float64)");
  expectError(head + "property float x\nend_header\n", ":7: property 'x' declared twice");
  expectError("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n0\n",
              ": no 'vertex' element with properties x, y and z; expected the points there");
  expectError(head + "end_header\n0 0 0\n1 abc 0\n",
              ":9: vertex 1: property 'y' is 'abc'; expected a number");
  expectError(head + "end_header\n0 0 0\n1 0\n",
              ": the file ends at vertex 1: property 'z'; expected 2 vertex elements");
  expectError(head + "end_header\n0 0 0\n1 0 0\n5\n",
              ":10: '5' after the last element (vertex); expected the file to end there");
  expectError(head + "end_header\n0 0 0\n1 0 0\n",
              ": no faces (2 vertices); expected a surface (a 'face' element with vertex_indices)");
  const std::string faces = head + "element face 1\nproperty list uchar int vertex_indices\n";
  expectError(faces + "end_header\n0 0 0\n1 0 0\n2 0 1\n",
              ": face 0 has 2 vertices; expected at least 3");
  expectError(faces + "end_header\n0 0 0\n1 0 0\n3 0 1 2\n",
              ": face 0 names vertex 2; expected an index in [0, 2) (the vertex count)");
  expectError(faces + "end_header\n0 0 0\n1 0 0\n3 0 1 1.5\n",
              ":12: face 0: property 'vertex_indices' is '1.5'; expected an integer");
  // Binary: data cut short, and data going on after the last element.
  std::string binary = binarySquare(false);
  expectError(binary.substr(0, binary.size() - 3),
              ": the file ends at face 1: property 'vertex_indices'; expected 2 face elements");
  expectError(binary + "xy",
              ": 2 bytes after the last element (face); expected the file to end "
              "there");
  expectError(
      "ply\nformat ascii 1.0\nelement vertex 1\nproperty list uchar float x\n"
      "property float y\nproperty float z\nend_header\n1 0 0 0\n",
      ": vertex property 'x' is a list; expected a number");
}

}  // namespace
}  // namespace bcassim
