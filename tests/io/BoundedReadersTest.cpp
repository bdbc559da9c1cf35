// The bounded readers' checks that the bad-input catalogue does not run through the executable:
// version 5 cell offsets, binary values, attribute sections, XML binary data and compression
// headers, STL values, sparse marker tracks, escaped CSV headers and checkpoint item sizes.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <limits>
#include <string>

#include "bcassim/Error.h"
#include "bcassim/io/BinaryArchive.h"
#include "bcassim/io/CsvTracks.h"
#include "bcassim/io/MeshReader.h"
#include "bcassim/io/PvdSeries.h"
#include "bcassim/io/SurfaceReader.h"
#include "io/IoTestSupport.h"

namespace bcassim {
namespace {

using test::cubeMesh;
using test::TempDir;
using test::writeText;

const std::string kCubePoints = "0 0 0\n1 0 0\n0 1 0\n1 1 0\n0 0 1\n1 0 1\n0 1 1\n1 1 1\n";

// The cube of IoTestSupport.h in the version 5 layout: OFFSETS and CONNECTIVITY arrays.
std::string cubeVersion5(const std::string& offsets, const std::string& connectivityCount = "20") {
  return "# vtk DataFile Version 5.1\ncube\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 8 float\n" +
         kCubePoints + "CELLS 6 " + connectivityCount + "\nOFFSETS vtktypeint64\n" + offsets +
         "\nCONNECTIVITY vtktypeint64\n0 1 2 4 1 3 2 7 1 5 7 4 2 7 6 4 1 2 4 7\n"
         "CELL_TYPES 5\n10\n10\n10\n10\n10\n";
}

TEST(LegacyVtkReader, Version5OffsetsAndConnectivity) {
  TempDir dir;
  const TetMesh mesh = readTetMesh(writeText(dir.file("cube.vtk"), cubeVersion5("0 4 8 12 16 20")));
  EXPECT_EQ(mesh.T, cubeMesh().T);
  const std::string late = writeText(dir.file("late.vtk"), cubeVersion5("2 4 8 12 16 20"));
  EXPECT_INPUT_ERROR(late + ":16: the first offset is 2; expected 0", readTetMesh(late));
  const std::string back = writeText(dir.file("back.vtk"), cubeVersion5("0 4 8 6 16 20"));
  EXPECT_INPUT_ERROR(back +
                         ":16: offset 3 is 6; expected a value from 8 to 20 (offsets never "
                         "decrease and end at the connectivity size)",
                     readTetMesh(back));
  const std::string shortEnd = writeText(dir.file("end.vtk"), cubeVersion5("0 4 8 12 16 19"));
  EXPECT_INPUT_ERROR(shortEnd + ":16: the last offset is 19; expected the connectivity size 20",
                     readTetMesh(shortEnd));
}

void putBigEndianFloat(std::string& out, float v) {
  uint32_t bits;
  std::memcpy(&bits, &v, 4);
  for (int k = 3; k >= 0; --k) out += static_cast<char>((bits >> (8 * k)) & 0xff);
}

TEST(LegacyVtkReader, BinaryNonFiniteCoordinateNamesItsByte) {
  TempDir dir;
  const std::string header =
      "# vtk DataFile Version 3.0\ncube\nBINARY\nDATASET UNSTRUCTURED_GRID\nPOINTS 8 float\n";
  std::string bytes = header;
  for (int i = 0; i < 24; ++i)
    putBigEndianFloat(bytes, i == 7 ? std::numeric_limits<float>::quiet_NaN() : 0.5f * (i % 3));
  const std::string path = dir.file("nan.vtk");
  writeText(path, bytes);
  EXPECT_INPUT_ERROR(fmt::format("{}: byte {}: value nan of POINTS is not a finite number", path,
                                 header.size() + 7 * 4),
                     readTetMesh(path));
}

std::string legacyCubeWith(const std::string& cellData) {
  return "# vtk DataFile Version 2.0\ncube\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS 8 float\n" +
         kCubePoints +
         "CELLS 5 25\n4 0 1 2 4\n4 1 3 2 7\n4 1 5 7 4\n4 2 7 6 4\n4 1 2 4 7\n"
         "CELL_TYPES 5\n10\n10\n10\n10\n10\n" +
         cellData;
}

TEST(LegacyVtkReader, AttributeSectionsAndMetadata) {
  TempDir dir;
  // A FIELD array with VTK 9's METADATA block, point data before the cell data, and a second
  // SCALARS array, which VTK (and so bcassim) does not keep.
  const std::string good = writeText(
      dir.file("good.vtk"),
      legacyCubeWith("POINT_DATA 8\nSCALARS temperature double\nLOOKUP_TABLE default\n"
                     "1 2 3 4 5 6 7 8\nCELL_DATA 5\nFIELD FieldData 1\nregion 1 5 int\n"
                     "1 1 1 1 2\nMETADATA\nINFORMATION 1\nNAME L2_NORM_RANGE LOCATION "
                     "vtkDataArray\nDATA 2 1 2\n\nSCALARS dataset float 1\nLOOKUP_TABLE default\n"
                     "7 7 7 7 7\nSCALARS other int 1\nLOOKUP_TABLE default\n0 0 0 0 0\n"));
  EXPECT_EQ(readTetMesh(good).region, (Eigen::VectorXi(5) << 7, 7, 7, 7, 7).finished());
  EXPECT_EQ(readTetMesh(good, "region").region, cubeMesh().region);
  EXPECT_INPUT_ERROR(good + ": no numeric cell field 'other'; the file has 'region', 'dataset'",
                     readTetMesh(good, "other"));

  const std::string count =
      writeText(dir.file("count.vtk"), legacyCubeWith("CELL_DATA 6\nSCALARS d float\n"));
  EXPECT_INPUT_ERROR(count + ":26: CELL_DATA 6; expected the number of cells (5)",
                     readTetMesh(count));
  const std::string tuples = writeText(
      dir.file("tuples.vtk"), legacyCubeWith("CELL_DATA 5\nFIELD f 1\nregion 1 3 int\n1 1 2\n"));
  EXPECT_INPUT_ERROR(tuples + ": cell field 'region' has 3 values; expected one per cell (5)",
                     readTetMesh(tuples));
  const std::string keyword =
      writeText(dir.file("keyword.vtk"), legacyCubeWith("CELL_DATA 5\nCOLOURS d float\n"));
  EXPECT_INPUT_ERROR(keyword +
                         ":27: unknown keyword 'COLOURS' in CELL_DATA; expected SCALARS, VECTORS, "
                         "NORMALS, TENSORS, TEXTURE_COORDINATES, COLOR_SCALARS, LOOKUP_TABLE, "
                         "FIELD, CELL_DATA or POINT_DATA",
                     readTetMesh(keyword));
}

// The ascii cube as VTK XML, with the points given as `pointsArray`.
std::string cubeVtu(const std::string& pointsArray, const std::string& vtkFileAttributes = "",
                    const std::string& appended = "") {
  return "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\"" +
         vtkFileAttributes +
         ">\n<UnstructuredGrid>\n<Piece NumberOfPoints=\"8\" NumberOfCells=\"5\">\n<Points>\n" +
         pointsArray +
         "\n</Points>\n<Cells>\n"
         "<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">"
         "0 1 2 4 1 3 2 7 1 5 7 4 2 7 6 4 1 2 4 7</DataArray>\n"
         "<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">4 8 12 16 20</DataArray>\n"
         "<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">10 10 10 10 10</DataArray>\n"
         "</Cells>\n</Piece>\n</UnstructuredGrid>\n" +
         appended + "</VTKFile>\n";
}

std::string base64(const std::string& bytes) {
  static const char* kAlphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (size_t i = 0; i < bytes.size(); i += 3) {
    uint32_t triple = static_cast<unsigned char>(bytes[i]) << 16;
    if (i + 1 < bytes.size()) triple |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    if (i + 2 < bytes.size()) triple |= static_cast<unsigned char>(bytes[i + 2]);
    out += kAlphabet[(triple >> 18) & 63];
    out += kAlphabet[(triple >> 12) & 63];
    out += i + 1 < bytes.size() ? kAlphabet[(triple >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? kAlphabet[triple & 63] : '=';
  }
  return out;
}

std::string littleEndianWords(std::initializer_list<uint32_t> words) {
  std::string out;
  for (uint32_t w : words)
    for (int k = 0; k < 4; ++k) out += static_cast<char>((w >> (8 * k)) & 0xff);
  return out;
}

TEST(VtkXmlReader, BinaryDataChecks) {
  TempDir dir;
  const std::string ascii =
      "<DataArray type=\"Float32\" Name=\"Points\" NumberOfComponents=\"3\" "
      "format=\"ascii\">" +
      kCubePoints + "</DataArray>";
  EXPECT_EQ(readTetMesh(writeText(dir.file("ascii.vtu"), cubeVtu(ascii))).T, cubeMesh().T);

  const std::string badChar =
      writeText(dir.file("char.vtu"),
                cubeVtu("<DataArray type=\"Float32\" Name=\"Points\" NumberOfComponents=\"3\" "
                        "format=\"binary\">YAAAAA*AAAA</DataArray>"));
  EXPECT_INPUT_ERROR(
      badChar + ":5: <DataArray Name=\"Points\">: its data hold a character that is not base64",
      readTetMesh(badChar));

  // zlib header: 1 block of 96 bytes (8 points x 3 Float32), 5 compressed bytes that are not zlib.
  const std::string header = base64(littleEndianWords({1, 96, 0, 5}));
  const std::string notZlib =
      writeText(dir.file("zlib.vtu"),
                cubeVtu("<DataArray type=\"Float32\" Name=\"Points\" NumberOfComponents=\"3\" "
                        "format=\"binary\">" +
                            header + base64("abcde") + "</DataArray>",
                        " compressor=\"vtkZLibDataCompressor\""));
  EXPECT_INPUT_ERROR(notZlib +
                         ":5: <DataArray Name=\"Points\">: compressed block 0 of 1 does not "
                         "decompress to its 96 bytes",
                     readTetMesh(notZlib));
  const std::string blocks =
      writeText(dir.file("blocks.vtu"),
                cubeVtu("<DataArray type=\"Float32\" Name=\"Points\" NumberOfComponents=\"3\" "
                        "format=\"binary\">" +
                            base64(littleEndianWords({3000000000u, 32768, 0})) + "</DataArray>",
                        " compressor=\"vtkZLibDataCompressor\""));
  EXPECT_INPUT_ERROR(blocks +
                         ":5: <DataArray Name=\"Points\">: compression header: 3000000000 blocks "
                         "of 32768 bytes; expected 96 bytes (24 values of Float32)",
                     readTetMesh(blocks));

  const std::string offset =
      writeText(dir.file("offset.vtu"),
                cubeVtu("<DataArray type=\"Float32\" Name=\"Points\" NumberOfComponents=\"3\" "
                        "format=\"appended\" offset=\"999\"/>",
                        "", "<AppendedData encoding=\"raw\">\n_abc\n</AppendedData>\n"));
  EXPECT_INPUT_ERROR(offset +
                         ":5: <DataArray Name=\"Points\">: offset=\"999\" is beyond the 31 bytes "
                         "of appended data",
                     readTetMesh(offset));
  const std::string type = writeText(
      dir.file("type.vtu"), cubeVtu("<DataArray type=\"Float128\" Name=\"Points\" "
                                    "NumberOfComponents=\"3\" format=\"ascii\">1</DataArray>"));
  EXPECT_INPUT_ERROR(type +
                         ":5: <DataArray Name=\"Points\">: type=\"Float128\"; expected Int8, "
                         "UInt8, Int16, UInt16, Int32, UInt32, Int64, UInt64, Float32 or Float64",
                     readTetMesh(type));
}

TEST(StlReader, NonFiniteAndMalformedVertices) {
  TempDir dir;
  std::string binary(80, ' ');
  binary += std::string("\x01\x00\x00\x00", 4);
  for (int i = 0; i < 12; ++i) {
    const float v = i == 5 ? std::numeric_limits<float>::infinity() : 0.25f * i;
    binary.append(reinterpret_cast<const char*>(&v), 4);  // little-endian hosts
  }
  binary += std::string(2, '\0');
  const std::string path = writeText(dir.file("inf.stl"), binary);
  EXPECT_INPUT_ERROR(path +
                         ": triangle 0 has a non-finite coordinate (inf); expected a finite "
                         "number",
                     readSurface(path));
  const std::string ascii =
      writeText(dir.file("two.stl"), "solid s\nfacet normal 0 0 1\nouter loop\nvertex 0 0\n");
  EXPECT_INPUT_ERROR(ascii + ":4: expected 3 coordinates after 'vertex', got 2",
                     readSurface(ascii));
}

TEST(MarkerTracks, MarkersNumberedFarApartAreRefused) {
  TempDir dir;
  const std::string path =
      writeText(dir.file("sparse.csv"),
                "time,marker,x,y,z\n0,999999,0,0,0\n1,999999,0,0,0\n2,999999,0,0,0\n");
  EXPECT_INPUT_ERROR(path +
                         ": 3 rows give 3 frames of 1000000 markers (3000000 marker rows, 2999997 "
                         "of them missing); expected markers numbered 0, 1, 2, ... with most "
                         "present in every frame",
                     readMarkerTracks(path));
}

TEST(MarkerTracks, HeaderBytesAreEscaped) {
  TempDir dir;
  const std::string path = writeText(dir.file("esc.csv"), "time,mark\x1b[0m,x,y,z\n0,0,1,2,3\n");
  EXPECT_INPUT_ERROR(path + ": header is 'time,mark\\x1b[0m,x,y,z'; expected time,marker,x,y,z",
                     readMarkerTracks(path));
}

TEST(BinaryArchive, SizesBeyondTheFileAreDamageNotAllocations) {
  TempDir dir;
  const std::string path = dir.file("checkpoint.bin");
  {
    ArchiveWriter out(path);
    out.text("short");
    out.commit();
  }
  std::string bytes = test::readText(path);
  const uint64_t huge = uint64_t{1} << 25;  // within the old 64 MiB bound, beyond the file
  std::memcpy(bytes.data() + 1, &huge, sizeof huge);
  writeText(path, bytes);
  EXPECT_INPUT_ERROR(path + ": damaged (expected a text)", ArchiveReader(path, "a test").text());

  std::string matrix = "M";
  const int64_t rows = int64_t{1} << 40, cols = 1;
  matrix.append(reinterpret_cast<const char*>(&rows), 8);
  matrix.append(reinterpret_cast<const char*>(&cols), 8);
  writeText(path, matrix);
  EXPECT_INPUT_ERROR(path + ": damaged (expected a matrix)",
                     ArchiveReader(path, "a test").matrix());

  // Found by fuzz_checkpoint: 0 rows of 2^62 columns allocate nothing, but checking their values
  // ran past 10 s.
  std::string empty = "M";
  const int64_t none = 0, wide = int64_t{1} << 62;
  empty.append(reinterpret_cast<const char*>(&none), 8);
  empty.append(reinterpret_cast<const char*>(&wide), 8);
  writeText(path, empty);
  EXPECT_INPUT_ERROR(path + ": damaged (expected a matrix)",
                     ArchiveReader(path, "a test").matrix());
}

// A damaged series index met on --resume: one line, never std::stoi's exception or a part number
// sized like memory.
TEST(PvdSeries, DamagedIndexOnResume) {
  TempDir dir;
  const std::string pvd = writeText(
      dir.file("liver.pvd"),
      "<VTKFile type=\"Collection\">\n<Collection>\n"
      "<DataSet timestep=\"0\" group=\"\" part=\"99999999999\" file=\"liver_000000.vtu\"/>\n"
      "</Collection>\n</VTKFile>\n");
  EXPECT_INPUT_ERROR(pvd +
                         ":3: expected timestep=\"<s>\" and part=\"<0 to 1000>\", got "
                         "'<DataSet timestep=\"0\" group=\"\" part=\"99999999999\" "
                         "file=\"liver_000000.vtu\"/>'",
                     PvdSeries::resume(dir.path(), "liver", 1));
}

}  // namespace
}  // namespace bcassim
