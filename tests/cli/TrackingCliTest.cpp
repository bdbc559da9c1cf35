// `bcassim track` and `bcassim register` as a user meets them: identities kept through an empty
// frame, a dropout, a NaN detection, a spurious one and a frame out of order (each bad input one
// line); a known rigid transform recovered by ICP and by Kabsch; exact one-line errors.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "bcassim/Types.h"
#include "bcassim/io/CsvTable.h"
#include "bcassim/io/CsvTracks.h"
#include "bcassim/io/MeshReader.h"
#include "bcassim/io/MeshWriter.h"
#include "bcassim/io/PointCsvWriter.h"
#include "bcassim/io/PointReader.h"
#include "bcassim/mesh/MeshGenerators.h"
#include "bcassim/mesh/RigidTransform.h"
#include "support/TestFiles.h"

namespace bcassim {
namespace {

using test::contains;
using test::freshDir;
using test::runBcassim;
using test::writeText;

// Marker i at frame k: three markers 5 cm apart moving 1 mm per frame along x.
Vec3 markerAt(int i, int k) {
  const Vec3 start[3] = {Vec3(0, 0, 0), Vec3(0.05, 0, 0), Vec3(0, 0.05, 0)};
  return start[i] + Vec3(0.001 * k, 0, 0);
}

std::string row(const std::string& time, const Vec3& p) {
  return fmt::format("{},{},{},{}\n", time, p.x(), p.y(), p.z());
}

// 20 frames, 0.1 s apart (times written as decimals), then one out of order. Frame 5 is empty,
// marker 1 drops out in frame 8, frame 10 has a NaN detection, frame 12 a spurious one far off;
// the detections of odd frames come in reverse order.
std::string detectionsCsv() {
  std::string csv = "time,x,y,z\n";
  for (int k = 0; k < 20; ++k) {
    const std::string t = fmt::format("{}.{}", k / 10, k % 10);
    if (k == 5) {
      csv += t + ",,,\n";
      continue;
    }
    std::vector<int> order = k % 2 ? std::vector<int>{2, 1, 0} : std::vector<int>{0, 1, 2};
    for (int i : order)
      if (!(k == 8 && i == 1)) csv += row(t, markerAt(i, k));
    if (k == 10) csv += t + ",nan,0,0\n";
    if (k == 12) csv += row(t, Vec3(1, 1, 1));
  }
  for (int i = 0; i < 3; ++i) csv += row("0.05", markerAt(i, 0));
  return csv;
}

TEST(TrackCli, KeepsIdentitiesAndReportsEveryBadInputOnOneLine) {
  const auto dir = freshDir();
  writeText(dir / "detections.csv", detectionsCsv());
  const test::CliResult r = runBcassim(dir, "track detections.csv --out out");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_EQ(r.err, "");
  // 20 frames of 3, less the empty frame's 3 and a dropout, plus the NaN and the spurious
  // detection, plus the 3 of the frame out of order.
  EXPECT_EQ(r.out,
            "frames: 21 (3 with bad input), detections: 61\n"
            "tracks confirmed: 3\n"
            "detections labelled: 56\n"
            "detections dropped as spurious (no confirmed track): 1\n"
            "detections dropped as bad input: 4\n"
            "bad input: frame 5 (t = 0.5 s): no detections; tracks coast through it\n"
            "bad input: frame 10 (t = 1 s), detection 3: non-finite coordinate (nan, 0, 0); "
            "detection dropped\n"
            "bad input: frame 20 (t = 0.05 s): earlier than the previous frame (t = 1.9 s); frame "
            "skipped\n"
            "wrote out/tracks.csv (time,marker,x,y,z: s, id, m; a marker not seen has no row)\n");

  // Ids in the order of the first frame's detections; every marker keeps its id throughout.
  const MarkerTracks tracks = readMarkerTracks((dir / "out" / "tracks.csv").string());
  ASSERT_EQ(tracks.numMarkers, 3);
  ASSERT_EQ(tracks.frames.size(), 19u);  // the empty frame has no row
  for (size_t f = 0; f < tracks.frames.size(); ++f) {
    const int k = static_cast<int>(std::lround(10 * tracks.times[f]));
    EXPECT_NE(k, 5);
    for (int i = 0; i < 3; ++i) {
      if (k == 8 && i == 1) {
        EXPECT_TRUE(tracks.frames[f].row(i).hasNaN()) << "frame " << k;
        continue;
      }
      EXPECT_EQ(tracks.frames[f].row(i), markerAt(i, k).transpose()) << "frame " << k;
    }
  }
}

TEST(TrackCli, GreedyMethodKeepsTheseWellSeparatedMarkersToo) {
  const auto dir = freshDir();
  writeText(dir / "detections.csv", detectionsCsv());
  const test::CliResult r = runBcassim(dir, "track detections.csv --out out --method greedy");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "tracks confirmed: 3\n")) << r.out;
  EXPECT_TRUE(contains(r.out, "detections labelled: 56\n")) << r.out;
}

// An output that cannot be written is not bad input: exit code 4, the file and the system's reason
// on one line.
TEST(TrackCli, FullDiskIsExitFourNamingTheFileAndTheReason) {
  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "no /dev/full";
  const auto dir = freshDir();
  writeText(dir / "detections.csv", detectionsCsv());
  std::filesystem::create_directories(dir / "out");
  std::filesystem::create_symlink("/dev/full", dir / "out" / "tracks.csv");
  const test::CliResult r = runBcassim(dir, "track detections.csv --out out");
  EXPECT_EQ(r.exitCode, 4);
  EXPECT_EQ(r.err, "bcassim: error: out/tracks.csv: cannot write file (No space left on device)\n");
}

void expectError(const std::filesystem::path& dir, const std::string& args,
                 const std::string& message) {
  SCOPED_TRACE(args);
  const test::CliResult r = runBcassim(dir, args);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.err, "bcassim: error: " + message + "\n");
  EXPECT_EQ(r.out, "");
}

TEST(TrackCli, BadDetectionFilesAreOneLocatedLine) {
  const auto dir = freshDir();
  expectError(dir, "track none.csv", "none.csv: cannot open file");
  writeText(dir / "field.csv", "time,x,y,z\n0,1,2,3\n0,1,a,3\n");
  expectError(dir, "track field.csv", "field.csv:3: field y is not a number ('a')");
  writeText(dir / "fields.csv", "0,1,2,3\n0,1,2\n");
  expectError(dir, "track fields.csv", "fields.csv:2: expected 4 fields (time,x,y,z), got 3");
  writeText(dir / "header.csv", "t,x,y,z\n0,1,2,3\n");
  expectError(dir, "track header.csv",
              "header.csv:1: header 't,x,y,z'; expected time,x,y,z (s, m)");
  writeText(dir / "empty.csv", "time,x,y,z\n");
  expectError(dir, "track empty.csv", "empty.csv: no rows; expected time,x,y,z rows (s, m)");
  writeText(dir / "ok.csv", "0,1,2,3\n");
  const test::CliResult r = runBcassim(dir, "track ok.csv --gate 0");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(test::countLines(r.err), 1) << r.err;
  EXPECT_TRUE(contains(r.err, "--gate")) << r.err;
}

// ---------------------------------------------------------------------------------------------
// register

// The model: a 10 x 6 x 4 cm box bent out of its symmetries (z += 0.3 x^2, y += 0.2 x z: a box
// has poses where part of a view fits exactly); the points: its surface nodes on three faces
// meeting at a corner (x = 0.1, y = 0, z = 0.04), given in a frame that `cameraToModel` brings
// back.
struct RegisterCase {
  std::filesystem::path dir;
  RigidTransform cameraToModel;
  std::vector<int> ids;  // model node of each point
  Eigen::MatrixX3d points;
};

RegisterCase makeRegisterCase(double angleDegrees, const Vec3& translation) {
  RegisterCase c;
  c.dir = freshDir();
  const TetMesh straight = makeBoxMesh(Vec3(0.1, 0.06, 0.04), 10, 6, 4);
  TetMesh box = straight;
  for (Eigen::Index i = 0; i < box.numNodes(); ++i) {
    const double x = straight.V(i, 0), z = straight.V(i, 2);
    box.V(i, 2) += 0.3 * x * x;
    box.V(i, 1) += 0.2 * x * z;
  }
  writeTetMesh((c.dir / "model.vtu").string(), box);
  c.cameraToModel.rotation =
      Eigen::AngleAxisd(angleDegrees * M_PI / 180, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  c.cameraToModel.translation = translation;
  std::string idList;
  for (Eigen::Index i = 0; i < box.numNodes(); ++i) {
    const Vec3 p = straight.V.row(i).transpose();
    if (std::abs(p.x() - 0.1) < 1e-12 || std::abs(p.y()) < 1e-12 ||
        std::abs(p.z() - 0.04) < 1e-12) {
      c.ids.push_back(static_cast<int>(i));
      idList += fmt::format("{}\n", i);
    }
  }
  writeText(c.dir / "ids.txt", idList);
  Eigen::MatrixX3d model(static_cast<Eigen::Index>(c.ids.size()), 3);
  for (size_t k = 0; k < c.ids.size(); ++k)
    model.row(static_cast<Eigen::Index>(k)) = box.V.row(c.ids[k]);
  c.points = c.cameraToModel.inverse().apply(model);
  writePointsCsv((c.dir / "points.csv").string(), c.points);
  return c;
}

// transform.csv: 4 rows of 4 numbers, [R t; 0 0 0 1].
RigidTransform readTransform(const std::filesystem::path& path) {
  const CsvTable t = readCsvTable(path.string());
  EXPECT_EQ(t.rows.rows(), 4);
  EXPECT_EQ(t.rows.cols(), 4);
  EXPECT_EQ(t.rows.row(3), Eigen::RowVector4d(0, 0, 0, 1));
  RigidTransform r;
  r.rotation = t.rows.topLeftCorner<3, 3>();
  r.translation = t.rows.topRightCorner<3, 1>();
  return r;
}

TEST(RegisterCli, IcpRecoversAKnownTransformFromPartOfTheSurface) {
  const RegisterCase c = makeRegisterCase(5.0, Vec3(0.004, -0.003, 0.005));
  const test::CliResult r = runBcassim(c.dir, "register model.vtu points.csv --out out");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(contains(
      r.out, "method: trimmed point-to-plane ICP, 46 starts probed, the best 4 to convergence"))
      << r.out;
  EXPECT_TRUE(contains(r.out, fmt::format("overlap: 100.0 % ({0} of {0} points)", c.ids.size())))
      << r.out;
  const RigidTransform t = readTransform(c.dir / "out" / "transform.csv");
  EXPECT_LT((t.rotation - c.cameraToModel.rotation).norm(), 1e-6);
  EXPECT_LT((t.translation - c.cameraToModel.translation).norm(), 1e-7);
  std::istringstream txt(test::readText(c.dir / "out" / "transform.txt"));
  Eigen::Matrix4d M;
  for (int i = 0; i < 16; ++i) txt >> M(i / 4, i % 4);
  EXPECT_TRUE(txt) << "transform.txt: expected 4 rows of 4 numbers";
  EXPECT_EQ((M.topLeftCorner<3, 3>()), t.rotation);
  EXPECT_EQ((M.topRightCorner<3, 1>()), t.translation);
  const Eigen::MatrixX3d moved = readPoints((c.dir / "out" / "moved_points.csv").string());
  EXPECT_LT((moved - c.cameraToModel.apply(c.points)).cwiseAbs().maxCoeff(), 1e-7);
}

// A dozen noisy markers: with --median-factor 0 every one of them is kept (none is an outlier,
// and each holds the pose); the pose is then as good as 0.3 mm of noise on 14 points allows.
TEST(RegisterCli, MedianFactorZeroKeepsEveryMarker) {
  const RegisterCase c = makeRegisterCase(10.0, Vec3(0.004, -0.003, 0.005));
  std::mt19937 rng(4);
  std::normal_distribution<double> noise(0.0, 3e-4);
  const auto step = static_cast<Eigen::Index>(c.points.rows() / 14);
  Eigen::MatrixX3d markers(14, 3);
  for (Eigen::Index k = 0; k < 14; ++k)
    markers.row(k) =
        c.points.row(k * step) + Eigen::RowVector3d(noise(rng), noise(rng), noise(rng));
  writePointsCsv((c.dir / "markers.csv").string(), markers);
  const test::CliResult trimmed = runBcassim(c.dir, "register model.vtu markers.csv --out t");
  ASSERT_EQ(trimmed.exitCode, 0) << trimmed.err;
  EXPECT_EQ(contains(trimmed.out, "overlap: 100.0 %"),
            !contains(trimmed.out,
                      "points out; markers without outliers hold the pose together: "
                      "--median-factor 0 keeps them all\n"))
      << trimmed.out;
  const test::CliResult r =
      runBcassim(c.dir, "register model.vtu markers.csv --median-factor 0 --out out");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "overlap: 100.0 % (14 of 14 points)")) << r.out;
  EXPECT_FALSE(contains(r.out, "note:")) << r.out;
  EXPECT_TRUE(contains(r.out, "iterations: ")) << r.out;
  const RigidTransform t = readTransform(c.dir / "out" / "transform.csv");
  EXPECT_LT((t.apply(markers) - c.cameraToModel.apply(markers)).rowwise().norm().maxCoeff(), 3e-3);
  const test::CliResult bad =
      runBcassim(c.dir, "register model.vtu markers.csv --median-factor -1");
  EXPECT_EQ(bad.exitCode, 2);
  EXPECT_EQ(bad.err,
            "bcassim: error: --median-factor: expected a number >= 0, got '-1' (see 'bcassim "
            "--help')\n");
}

TEST(RegisterCli, KabschWithModelIdsIsExact) {
  const RegisterCase c = makeRegisterCase(120.0, Vec3(0.3, -0.2, 0.1));
  const test::CliResult r =
      runBcassim(c.dir, "register model.vtu points.csv --model-ids ids.txt --out out");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(contains(r.out, fmt::format("method: Kabsch on {} pairs\n", c.ids.size()))) << r.out;
  EXPECT_TRUE(contains(r.out, "iterations: 0\n")) << r.out;
  const RigidTransform t = readTransform(c.dir / "out" / "transform.csv");
  EXPECT_LT((t.rotation - c.cameraToModel.rotation).norm(), 1e-12);
  EXPECT_LT((t.translation - c.cameraToModel.translation).norm(), 1e-12);
}

TEST(RegisterCli, OneFrameOfATracksCsvWithPairedPositions) {
  const RegisterCase c = makeRegisterCase(30.0, Vec3(0.1, 0, 0));
  // Two frames; the second (t = 0.2 s) holds the points, marker 1 unseen.
  std::string tracks = "time,marker,x,y,z\n";
  for (Eigen::Index m = 0; m < c.points.rows(); ++m) tracks += fmt::format("0.1,{},0,0,0\n", m);
  Eigen::MatrixX3d pairs = c.cameraToModel.apply(c.points);
  for (Eigen::Index m = 0; m < c.points.rows(); ++m)
    if (m != 1)
      tracks += fmt::format("0.2,{},{:.17g},{:.17g},{:.17g}\n", m, c.points(m, 0), c.points(m, 1),
                            c.points(m, 2));
  writeText(c.dir / "tracks.csv", tracks);
  writePointsCsv((c.dir / "pairs.csv").string(), pairs);
  const test::CliResult r =
      runBcassim(c.dir, "register model.vtu tracks.csv --time 0.2 --pairs pairs.csv --out out");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_TRUE(contains(r.out, "frame at t = 0.2 s of tracks.csv\n")) << r.out;
  EXPECT_TRUE(contains(r.out, fmt::format("method: Kabsch on {} pairs\n", c.ids.size() - 1)))
      << r.out;
  const RigidTransform t = readTransform(c.dir / "out" / "transform.csv");
  EXPECT_LT((t.rotation - c.cameraToModel.rotation).norm(), 1e-12);
  const CsvTable moved = readCsvTable((c.dir / "out" / "moved_points.csv").string());
  EXPECT_EQ(moved.header, (std::vector<std::string>{"x", "y", "z", "marker"}));
  EXPECT_EQ(moved.rows(1, 3), 2.0);  // marker 1 was not seen
}

TEST(RegisterCli, PointsInMillimetresAreTheTrackingRoomsOneLine) {
  const RegisterCase c = makeRegisterCase(5.0, Vec3::Zero());
  writePointsCsv((c.dir / "mm.csv").string(), 1000.0 * c.points);
  const Eigen::MatrixX3d mm = 1000.0 * c.points;
  const double points = (mm.colwise().maxCoeff() - mm.colwise().minCoeff()).norm();
  const TetMesh box = readTetMesh((c.dir / "model.vtu").string());
  const double surface = (box.V.colwise().maxCoeff() - box.V.colwise().minCoeff()).norm();
  expectError(c.dir, "register model.vtu mm.csv",
              fmt::format("point cloud bounding-box diagonal {:.4g} but the surface's is {:.4g} "
                          "(ratio {:.4g}): the points look like millimetres for a surface in "
                          "metres; expected both in metres",
                          points, surface, points / surface));
}

TEST(RegisterCli, BadInputsAreOneLineNamingTheFile) {
  const RegisterCase c = makeRegisterCase(5.0, Vec3::Zero());
  expectError(c.dir, "register none.vtu points.csv", "none.vtu: cannot open file");
  writeText(c.dir / "model.xyz", "1 2 3\n");
  expectError(
      c.dir, "register model.xyz points.csv",
      "model.xyz: unsupported model format '.xyz'; expected a tet mesh (.vtu, .msh, .mesh, .vtk) "
      "or a triangle surface (.obj, .stl, .ply, .vtp, .vtk)");
  // Too few points for ICP: 5 corners of the box spread over its size (units check passes).
  writeText(c.dir / "few.txt", "0 0 0\n0.1 0 0\n0 0.06 0\n0 0 0.04\n0.1 0.06 0.04\n");
  expectError(c.dir, "register model.vtu few.txt",
              "few.txt: point cloud of 5 points; expected at least 6 to register it rigidly to a "
              "surface");
  writeText(c.dir / "three.txt", "0 0\n");
  expectError(c.dir, "register model.vtu three.txt",
              "three.txt:1: expected 3 numbers (x y z), got 2 fields");
  expectError(c.dir, "register model.vtu points.csv --time 0.1",
              "--time 0.1 s: points.csv is not a tracks CSV (time,marker,x,y,z); expected --time "
              "only with one");
  writeText(c.dir / "ids2.txt", "0\n1\n");
  expectError(c.dir, "register model.vtu points.csv --model-ids ids2.txt",
              fmt::format("--model-ids ids2.txt: 2 ids for {} rows of points.csv; expected one per "
                          "row",
                          c.ids.size()));
}

}  // namespace
}  // namespace bcassim
