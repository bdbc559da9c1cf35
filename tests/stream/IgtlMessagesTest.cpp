// OpenIGTLink messages: points go out and come back in metres through the wire's millimetres and
// float32, with their time stamp; a damaged body is refused with its one line; frames name their
// markers or list them in order.
#include <gtest/gtest.h>
#include <igtl_util.h>

#include <cmath>
#include <limits>

#include "bcassim/Error.h"
#include "bcassim/stream/IgtlMessages.h"
#include "bcassim/stream/StepClock.h"

namespace bcassim {
namespace {

const unsigned char* bytes(const std::string& s) {
  return reinterpret_cast<const unsigned char*>(s.data());
}

std::string igtlPointsError(std::string message) {
  try {
    decodeIgtlPoints(bytes(message), bytes(message) + kIgtlHeaderSize);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(IgtlMessages, PointsRoundTripInMetresWithTheirStamp) {
  const std::vector<NamedPoint> sent = {{"hidden_0", {0.1234567, -0.05, 0.2}, 0.0042},
                                        {"hidden_1", {-0.3, 0.0, 1e-4}, 0.0}};
  const std::string m = encodeIgtlPoints("bcassim_hidden", 12.25, "bcassim", sent);
  const IgtlHeader h = decodeIgtlHeader(bytes(m));
  EXPECT_EQ(h.type, "POINT");
  EXPECT_EQ(h.device, "bcassim_hidden");
  EXPECT_NEAR(h.time, 12.25, 1e-9);
  ASSERT_EQ(h.bodySize + kIgtlHeaderSize, m.size());
  const std::vector<NamedPoint> got = decodeIgtlPoints(bytes(m), bytes(m) + kIgtlHeaderSize);
  ASSERT_EQ(got.size(), 2u);
  for (size_t i = 0; i < 2; ++i) {
    EXPECT_EQ(got[i].name, sent[i].name);
    // float32 millimetres: 2^-24 relative, far below a micrometre at organ scale.
    EXPECT_LT((got[i].position - sent[i].position).norm(), 1e-8);
    EXPECT_NEAR(got[i].radius, sent[i].radius, 1e-9);
  }
}

TEST(IgtlMessages, DamagedBodyIsRefusedByItsCrc) {
  std::string m = encodeIgtlPoints("Markers", 1.0, "markers", {{"marker_0", {0.1, 0.2, 0.3}, 0}});
  m[kIgtlHeaderSize + 100] ^= 0x5a;  // the first byte of the position
  EXPECT_EQ(igtlPointsError(m), "POINT 'Markers': the body's CRC does not match its header");
}

// Found by fuzz/igtl_message.cpp: a frame without points has an empty body (the decoder copied
// from a null pointer), and a device or point name is bytes from the wire, newlines included.
TEST(IgtlMessages, EmptyFrameDecodesToNoPoints) {
  const std::string m = encodeIgtlPoints("Markers", 1.0, "tracked", {});
  ASSERT_EQ(decodeIgtlHeader(bytes(m)).bodySize, 0u);
  const std::vector<unsigned char> header(m.begin(), m.end());
  EXPECT_TRUE(decodeIgtlPoints(header.data(), nullptr).empty());
}

TEST(IgtlMessages, NamesFromTheWireAreShownOnOneLine) {
  std::string m = encodeIgtlPoints("Mark\nrs", 1.0, "tracked", {{"a\rb", {0, 0, 0}, 0}});
  EXPECT_EQ(decodeIgtlHeader(bytes(m)).device, "Mark\\x0ars");
  EXPECT_EQ(decodeIgtlPoints(bytes(m), bytes(m) + kIgtlHeaderSize)[0].name, "a\\x0db");
  m[kIgtlHeaderSize] ^= 1;  // the body no longer matches its CRC
  EXPECT_EQ(igtlPointsError(m), "POINT 'Mark\\x0ars': the body's CRC does not match its header");
}

TEST(IgtlMessages, SurfaceIsAPolyDataOfItsTriangles) {
  Eigen::MatrixX3d v(3, 3);
  v << 0, 0, 0, 0.01, 0, 0, 0, 0.01, 0;
  Eigen::MatrixX3i f(1, 3);
  f << 0, 1, 2;
  const std::string m = encodeIgtlSurface("bcassim_surface", 2.0, v, f);
  const IgtlHeader h = decodeIgtlHeader(bytes(m));
  EXPECT_EQ(h.type, "POLYDATA");
  EXPECT_EQ(h.device, "bcassim_surface");
  // The points (3 float32 each) and the polygon (count + 3 ids, uint32) are in the body.
  EXPECT_GE(h.bodySize, 3u * 12u + 16u);
  EXPECT_EQ(h.bodySize + kIgtlHeaderSize, m.size());
  // A POLYDATA is also how a tracker may send the markers: its points come back in order.
  const std::vector<NamedPoint> p = decodeIgtlPolyDataPoints(bytes(m), bytes(m) + kIgtlHeaderSize);
  ASSERT_EQ(p.size(), 3u);
  for (Eigen::Index i = 0; i < 3; ++i)
    EXPECT_LT((p[static_cast<size_t>(i)].position - v.row(i).transpose()).norm(), 1e-9);
}

std::string polyDataError(const std::string& m) {
  try {
    decodeIgtlPolyDataPoints(bytes(m), bytes(m) + kIgtlHeaderSize);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(IgtlMessages, PolyDataWithADamagedBodyOrTooManyPointsIsRefused) {
  Eigen::MatrixX3d v = Eigen::MatrixX3d::Zero(2, 3);
  Eigen::MatrixX3i f(0, 3);
  std::string m = encodeIgtlSurface("Tracker", 1.0, v, f);
  std::string damaged = m;
  damaged[kIgtlHeaderSize + 45] ^= 0x10;
  EXPECT_EQ(polyDataError(damaged), "POLYDATA 'Tracker': the body's CRC does not match its header");
  // 1000 points announced in a body that holds 2, with its CRC made to match.
  m[kIgtlHeaderSize + 2] = 0x03;
  m[kIgtlHeaderSize + 3] = static_cast<char>(0xe8);
  const std::uint64_t crc = crc64(reinterpret_cast<unsigned char*>(m.data() + kIgtlHeaderSize),
                                  m.size() - kIgtlHeaderSize, 0);
  for (int i = 0; i < 8; ++i) m[static_cast<size_t>(57 - i)] = static_cast<char>(crc >> (8 * i));
  EXPECT_EQ(polyDataError(m), "POLYDATA 'Tracker': 1000 points do not fit in its body of " +
                                  std::to_string(m.size() - kIgtlHeaderSize) + " bytes");
}

TEST(IgtlMessages, HeaderOfAnotherVersionIsRefused) {
  std::string m = encodeIgtlPoints("Markers", 1.0, "markers", {});
  m[0] = 0x7f;
  m[1] = 0x01;
  try {
    decodeIgtlHeader(bytes(m));
    FAIL() << "accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(),
                 "OpenIGTLink header: version 32513 (expected 1 or 2, the protocol of "
                 "libopenigtlink 1.11)");
  }
}

std::string markersError(const std::vector<NamedPoint>& points, int markers) {
  try {
    markersFromPoints(points, markers);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(IgtlMessages, NamedMarkersGoToTheirRowsAndTheOthersAreMissing) {
  const Eigen::MatrixX3d m =
      markersFromPoints({{"marker_2", {1, 2, 3}, 0}, {"0", {4, 5, 6}, 0}}, 4);
  EXPECT_EQ(m.row(2), Eigen::RowVector3d(1, 2, 3));
  EXPECT_EQ(m.row(0), Eigen::RowVector3d(4, 5, 6));
  EXPECT_TRUE(m.row(1).array().isNaN().all());
  EXPECT_TRUE(m.row(3).array().isNaN().all());
  // Other names: in order; a NaN position is a missing marker.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Eigen::MatrixX3d o = markersFromPoints({{"tip", {1, 1, 1}, 0}, {"F-2", {nan, 0, 0}, 0}}, 3);
  EXPECT_EQ(o.row(0), Eigen::RowVector3d(1, 1, 1));
  EXPECT_TRUE(o.row(1).array().isNaN().all());
  EXPECT_EQ(markersError({{"marker_4", {0, 0, 0}, 0}}, 4),
            "point 'marker_4': marker 4 of the scene's 4 markers (0 to 3)");
  EXPECT_EQ(markersError({{"marker_1", {0, 0, 0}, 0}, {"1", {0, 0, 0}, 0}}, 4),
            "point '1': marker 1 given twice");
  EXPECT_EQ(markersError({{"a", {0, 0, 0}, 0}, {"b", {0, 0, 0}, 0}}, 1),
            "2 points for the scene's 1 markers");
}

TEST(StepClock, StampsRoundToTheNearestStep) {
  StepClock scene(0.02, 0.0);
  EXPECT_EQ(scene.stepOf(0.0), 0);
  EXPECT_EQ(scene.stepOf(0.0399), 2);
  EXPECT_EQ(scene.stepOf(0.051), 3);
  // A camera's clock: the first frame is step 1, whatever its stamp.
  StepClock camera(0.02, std::nullopt);
  EXPECT_EQ(camera.stepOf(1.7e9), 1);
  EXPECT_EQ(camera.stepOf(1.7e9 + 0.061), 4);
  EXPECT_NEAR(camera.stampOf(2), 1.7e9 + 0.02, 1e-6);
}

}  // namespace
}  // namespace bcassim
