#include "bcassim/stream/IgtlServer.h"

#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "bcassim/Error.h"

namespace bcassim {

namespace {

// A client that does not take a frame's messages within this time is dropped: the server must
// not wait on one slow display.
constexpr double kSendTimeoutSeconds = 2.0;

}  // namespace

IgtlServer::IgtlServer(const std::string& host, int port, Log log)
    : log_(std::move(log)), listener_(TcpSocket::listenOn(host, port)), port_(listener_.port()) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC | O_NONBLOCK) != 0)
    throw InputError(fmt::format("listen on {}:{}: {}", host, port, std::strerror(errno)));
  wakeRead_ = fds[0];
  wakeWrite_ = fds[1];
  thread_ = std::thread([this] { networkLoop(); });
}

IgtlServer::~IgtlServer() {
  stop();
  ::close(wakeRead_);
  ::close(wakeWrite_);
}

void IgtlServer::stop() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stopped_ = true;
  }
  frameReady_.notify_all();
  const char byte = 0;
  [[maybe_unused]] const ssize_t ignored = ::write(wakeWrite_, &byte, 1);
  if (thread_.joinable()) thread_.join();
}

void IgtlServer::say(const std::string& line) {
  if (!log_) return;
  const std::lock_guard<std::mutex> lock(logMutex_);
  log_(line);
}

int IgtlServer::clients() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return static_cast<int>(clients_.size());
}

int IgtlServer::clientsEver() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return nextClientId_ - 1;
}

std::optional<ReceivedFrame> IgtlServer::nextFrame(std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(mutex_);
  frameReady_.wait_for(lock, timeout, [this] { return stopped_ || !frames_.empty(); });
  if (stopped_ || frames_.empty()) return std::nullopt;
  ReceivedFrame f = std::move(frames_.front());
  frames_.pop_front();
  return f;
}

int IgtlServer::broadcast(const std::string& message) {
  std::vector<std::shared_ptr<Client>> targets;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    for (const auto& [id, c] : clients_) targets.push_back(c);
  }
  const std::lock_guard<std::mutex> sending(sendMutex_);
  int sent = 0;
  for (const auto& c : targets) {
    if (c->socket.writeAll(message.data(), message.size())) {
      ++sent;
      continue;
    }
    // Gone, or not reading: the network thread sees the shut socket and forgets it.
    say(fmt::format("client {}: not taking the frames (gone, or not reading for {:g} s); dropped",
                    c->id, kSendTimeoutSeconds));
    c->socket.shutdown();
  }
  return sent;
}

void IgtlServer::acceptClient() {
  TcpSocket s = listener_.accept();
  if (!s.valid()) return;
  s.setSendTimeout(kSendTimeoutSeconds);
  auto c = std::make_shared<Client>();
  c->socket = std::move(s);
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    c->id = nextClientId_++;
    clients_[c->id] = c;
  }
  say(fmt::format("client {} connected", c->id));
}

void IgtlServer::forget(int id) {
  const std::lock_guard<std::mutex> lock(mutex_);
  clients_.erase(id);
}

void IgtlServer::readFrom(Client& c) {
  char chunk[65536];
  const ssize_t r = ::recv(c.socket.fd(), chunk, sizeof chunk, MSG_DONTWAIT);
  if (r < 0 && (errno == EAGAIN || errno == EWOULDBLOCK || errno == EINTR)) return;
  if (r <= 0) {
    forget(c.id);
    say(fmt::format("client {} disconnected", c.id));
    return;
  }
  c.buffer.append(chunk, static_cast<std::size_t>(r));
  consumeMessages(c);
}

void IgtlServer::consumeMessages(Client& c) {
  std::size_t at = 0;
  while (c.buffer.size() - at >= kIgtlHeaderSize) {
    const auto* header = reinterpret_cast<const unsigned char*>(c.buffer.data() + at);
    IgtlHeader h;
    try {
      h = decodeIgtlHeader(header);
    } catch (const InputError& e) {
      forget(c.id);
      say(fmt::format("client {}: {}; the stream cannot be followed, client dropped", c.id,
                      e.what()));
      return;
    }
    if (h.bodySize > kIgtlMaxBodyBytes) {
      forget(c.id);
      say(fmt::format(
          "client {}: {} '{}' announces a body of {} bytes (at most {}); client dropped", c.id,
          h.type, h.device, h.bodySize, kIgtlMaxBodyBytes));
      return;
    }
    if (c.buffer.size() - at < kIgtlHeaderSize + h.bodySize) break;  // the rest is on its way
    if (h.type == "POINT" || h.type == "POLYDATA") {
      try {
        ReceivedFrame f;
        f.points = h.type == "POINT" ? decodeIgtlPoints(header, header + kIgtlHeaderSize)
                                     : decodeIgtlPolyDataPoints(header, header + kIgtlHeaderSize);
        f.device = h.device;
        f.time = h.time;
        f.arrival = std::chrono::steady_clock::now();
        f.client = c.id;
        {
          const std::lock_guard<std::mutex> lock(mutex_);
          frames_.push_back(std::move(f));
        }
        frameReady_.notify_one();
      } catch (const InputError& e) {
        say(fmt::format("client {}: {}; message skipped", c.id, e.what()));
      }
    } else {
      say(fmt::format("client {}: {} message '{}' ignored (bcassim reads POINT and POLYDATA)", c.id,
                      h.type, h.device));
    }
    at += kIgtlHeaderSize + h.bodySize;
  }
  c.buffer.erase(0, at);
}

void IgtlServer::networkLoop() {
  for (;;) {
    std::vector<std::shared_ptr<Client>> polled;
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (stopped_) break;
      for (const auto& [id, c] : clients_) polled.push_back(c);
    }
    std::vector<pollfd> fds = {{wakeRead_, POLLIN, 0}, {listener_.fd(), POLLIN, 0}};
    for (const auto& c : polled) fds.push_back({c->socket.fd(), POLLIN, 0});
    if (::poll(fds.data(), fds.size(), -1) < 0) {
      if (errno == EINTR) continue;
      break;
    }
    if (fds[0].revents != 0) {
      char drain[64];
      while (::read(wakeRead_, drain, sizeof drain) > 0) {
      }
      continue;  // stop() or a new look at the clients
    }
    if (fds[1].revents & POLLIN) acceptClient();
    // A client that leaves or is dropped has taken itself off the list (forget).
    for (std::size_t i = 0; i < polled.size(); ++i)
      if (fds[i + 2].revents != 0) readFrom(*polled[i]);
  }
  const std::lock_guard<std::mutex> lock(mutex_);
  clients_.clear();
}

}  // namespace bcassim
