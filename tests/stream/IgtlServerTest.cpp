// The OpenIGTLink server on loopback: frames from a client arrive whole and in order; a damaged
// message is one log line and the server keeps serving; a client that goes and comes back is
// logged and served again; what is broadcast reaches every client; a client announcing an
// absurd body is dropped without harming the others.
#include <gtest/gtest.h>

#include <algorithm>
#include <iostream>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "bcassim/stream/IgtlMessages.h"
#include "bcassim/stream/IgtlServer.h"
#include "bcassim/stream/TcpSocket.h"

namespace bcassim {
namespace {

using std::chrono::milliseconds;

struct LogLines {
  std::mutex mutex;
  std::vector<std::string> lines;
  IgtlServer::Log sink() {
    return [this](const std::string& line) {
      const std::lock_guard<std::mutex> lock(mutex);
      lines.push_back(line);
    };
  }
  // Waits up to 5 s for `line`.
  bool waitFor(const std::string& line) {
    for (int i = 0; i < 500; ++i) {
      {
        const std::lock_guard<std::mutex> lock(mutex);
        if (std::find(lines.begin(), lines.end(), line) != lines.end()) return true;
      }
      std::this_thread::sleep_for(milliseconds(10));
    }
    const std::lock_guard<std::mutex> lock(mutex);
    for (const std::string& l : lines) std::cerr << "logged: " << l << "\n";
    return false;
  }
};

std::string framePoints(double t, double x) {
  return encodeIgtlPoints("Markers", t, "markers", {{"marker_0", {x, 0.0, 0.0}, 0.0}});
}

void send(const TcpSocket& s, const std::string& m) { ASSERT_TRUE(s.writeAll(m.data(), m.size())); }

TEST(IgtlServer, FramesArriveInOrderAndADamagedOneIsLoggedAndSkipped) {
  LogLines log;
  IgtlServer server("127.0.0.1", 0, log.sink());
  ASSERT_GT(server.port(), 0);
  const TcpSocket client = TcpSocket::connectTo("127.0.0.1", server.port());
  ASSERT_TRUE(log.waitFor("client 1 connected"));
  std::string damaged = framePoints(0.02, 0.5);
  damaged.back() ^= 0x01;
  send(client, framePoints(0.01, 0.25) + damaged);
  send(client, framePoints(0.03, 0.75));
  const auto first = server.nextFrame(milliseconds(5000));
  ASSERT_TRUE(first.has_value());
  EXPECT_EQ(first->device, "Markers");
  EXPECT_NEAR(first->time, 0.01, 1e-9);
  EXPECT_EQ(first->client, 1);
  ASSERT_EQ(first->points.size(), 1u);
  EXPECT_NEAR(first->points[0].position.x(), 0.25, 1e-9);
  const auto second = server.nextFrame(milliseconds(5000));
  ASSERT_TRUE(second.has_value());
  EXPECT_NEAR(second->time, 0.03, 1e-9);
  EXPECT_TRUE(log.waitFor(
      "client 1: POINT 'Markers': the body's CRC does not match its header; message skipped"));
  EXPECT_FALSE(server.nextFrame(milliseconds(50)).has_value());
}

TEST(IgtlServer, APolyDataIsAFrameOfItsPoints) {
  IgtlServer server("127.0.0.1", 0, {});
  const TcpSocket client = TcpSocket::connectTo("127.0.0.1", server.port());
  Eigen::MatrixX3d v(2, 3);
  v << 0.01, 0.02, 0.03, -0.01, 0, 0.5;
  send(client, encodeIgtlSurface("Tracker", 0.04, v, Eigen::MatrixX3i(0, 3)));
  const auto f = server.nextFrame(milliseconds(5000));
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->device, "Tracker");
  ASSERT_EQ(f->points.size(), 2u);
  EXPECT_LT((f->points[1].position - Eigen::Vector3d(-0.01, 0, 0.5)).norm(), 1e-7);
}

TEST(IgtlServer, AClientThatLeavesAndComesBackIsServedAgain) {
  LogLines log;
  IgtlServer server("127.0.0.1", 0, log.sink());
  {
    const TcpSocket first = TcpSocket::connectTo("127.0.0.1", server.port());
    send(first, framePoints(0.01, 0.1));
    ASSERT_TRUE(server.nextFrame(milliseconds(5000)).has_value());
  }
  ASSERT_TRUE(log.waitFor("client 1 disconnected"));
  EXPECT_EQ(server.clients(), 0);
  const TcpSocket again = TcpSocket::connectTo("127.0.0.1", server.port());
  send(again, framePoints(0.02, 0.2));
  const auto f = server.nextFrame(milliseconds(5000));
  ASSERT_TRUE(f.has_value());
  EXPECT_EQ(f->client, 2);
  EXPECT_TRUE(log.waitFor("client 2 connected"));
  EXPECT_EQ(server.clientsEver(), 2);
}

TEST(IgtlServer, BroadcastReachesEveryClientAndAnAbsurdBodyDropsOnlyItsSender) {
  LogLines log;
  IgtlServer server("127.0.0.1", 0, log.sink());
  const TcpSocket a = TcpSocket::connectTo("127.0.0.1", server.port());
  const TcpSocket b = TcpSocket::connectTo("127.0.0.1", server.port());
  ASSERT_TRUE(log.waitFor("client 2 connected"));
  // A header announcing a 2^32-byte body: the stream cannot be trusted beyond it.
  std::string bad = framePoints(0.01, 0.1).substr(0, kIgtlHeaderSize);
  for (int i = 42; i < 50; ++i) bad[static_cast<size_t>(i)] = 0;
  bad[45] = 0x01;  // body size, big-endian at bytes 42..49: 2^32
  send(b, bad);
  ASSERT_TRUE(
      log.waitFor("client 2: POINT 'Markers' announces a body of 4294967296 bytes (at "
                  "most 67108864); client dropped"));
  EXPECT_EQ(server.clients(), 1);  // the line is logged after the client is forgotten
  const std::string m = encodeIgtlPoints("bcassim_hidden", 0.5, "bcassim", {{"hidden_0", {}, 0}});
  EXPECT_EQ(server.broadcast(m), 1);
  std::string got(m.size(), '\0');
  ASSERT_TRUE(a.readExactly(got.data(), got.size()));
  EXPECT_EQ(got, m);
}

}  // namespace
}  // namespace bcassim
