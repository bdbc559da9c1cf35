#include "bcassim/stream/TcpSocket.h"

#include <arpa/inet.h>
#include <fmt/format.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <utility>

#include "bcassim/Error.h"

namespace bcassim {

namespace {

// The IPv4 address of `host` (a dotted address or a name), for error lines naming host:port.
sockaddr_in addressOf(const std::string& host, int port, const std::string& what) {
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_port = htons(static_cast<uint16_t>(port));
  if (inet_pton(AF_INET, host.c_str(), &a.sin_addr) == 1) return a;
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  if (getaddrinfo(host.c_str(), nullptr, &hints, &found) != 0 || found == nullptr)
    throw InputError(fmt::format("{} {}:{}: unknown host", what, host, port));
  a.sin_addr = reinterpret_cast<sockaddr_in*>(found->ai_addr)->sin_addr;
  freeaddrinfo(found);
  return a;
}

void requirePort(int port, const std::string& what, const std::string& host) {
  if (port < 0 || port > 65535)
    throw InputError(
        fmt::format("{} {}:{}: the port must be between 0 and 65535", what, host, port));
}

}  // namespace

TcpSocket::~TcpSocket() {
  if (fd_ >= 0) ::close(fd_);
}

TcpSocket::TcpSocket(TcpSocket&& other) noexcept : fd_(std::exchange(other.fd_, -1)) {}

TcpSocket& TcpSocket::operator=(TcpSocket&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = std::exchange(other.fd_, -1);
  }
  return *this;
}

TcpSocket TcpSocket::listenOn(const std::string& host, int port) {
  requirePort(port, "listen on", host);
  const sockaddr_in a = addressOf(host, port, "listen on");
  TcpSocket s(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0));
  if (!s.valid())
    throw InputError(fmt::format("listen on {}:{}: {}", host, port, std::strerror(errno)));
  const int yes = 1;
  ::setsockopt(s.fd_, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof yes);
  if (::bind(s.fd_, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0 ||
      ::listen(s.fd_, 8) != 0)
    throw InputError(fmt::format("listen on {}:{}: {}", host, port, std::strerror(errno)));
  return s;
}

TcpSocket TcpSocket::connectTo(const std::string& host, int port) {
  requirePort(port, "connect to", host);
  const sockaddr_in a = addressOf(host, port, "connect to");
  TcpSocket s(::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0));
  if (!s.valid() || ::connect(s.fd_, reinterpret_cast<const sockaddr*>(&a), sizeof a) != 0)
    throw InputError(fmt::format("connect to {}:{}: {}", host, port, std::strerror(errno)));
  // Frames are small and must leave at once, not wait for Nagle's coalescing.
  const int yes = 1;
  ::setsockopt(s.fd_, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
  return s;
}

TcpSocket TcpSocket::accept() const {
  int fd = -1;
  do {
    fd = ::accept4(fd_, nullptr, nullptr, SOCK_CLOEXEC);
  } while (fd < 0 && errno == EINTR);
  if (fd >= 0) {
    const int yes = 1;
    ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &yes, sizeof yes);
  }
  return TcpSocket(fd);
}

bool TcpSocket::readExactly(void* data, std::size_t n) const {
  auto* p = static_cast<char*>(data);
  while (n > 0) {
    const ssize_t r = ::recv(fd_, p, n, 0);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return false;
    p += r;
    n -= static_cast<std::size_t>(r);
  }
  return true;
}

bool TcpSocket::writeAll(const void* data, std::size_t n) const {
  const auto* p = static_cast<const char*>(data);
  while (n > 0) {
    const ssize_t r = ::send(fd_, p, n, MSG_NOSIGNAL);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return false;
    p += r;
    n -= static_cast<std::size_t>(r);
  }
  return true;
}

void TcpSocket::setSendTimeout(double seconds) const {
  timeval t{};
  t.tv_sec = static_cast<time_t>(seconds);
  t.tv_usec = static_cast<suseconds_t>(1e6 * (seconds - std::floor(seconds)));
  ::setsockopt(fd_, SOL_SOCKET, SO_SNDTIMEO, &t, sizeof t);
}

void TcpSocket::shutdown() const {
  if (fd_ >= 0) ::shutdown(fd_, SHUT_RDWR);
}

int TcpSocket::port() const {
  sockaddr_in a{};
  socklen_t size = sizeof a;
  if (::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &size) != 0) return -1;
  return ntohs(a.sin_port);
}

void splitHostPort(const std::string& text, const std::string& what, std::string& host, int& port) {
  const size_t colon = text.rfind(':');
  const std::string portText = colon == std::string::npos ? "" : text.substr(colon + 1);
  char* end = nullptr;
  const long p = portText.empty() ? -1 : std::strtol(portText.c_str(), &end, 10);
  if (colon == 0 || portText.empty() || *end != '\0' || p < 1 || p > 65535)
    throw InputError(
        fmt::format("{} '{}': expected HOST:PORT with a port from 1 to 65535", what, text));
  host = text.substr(0, colon);
  port = static_cast<int>(p);
}

}  // namespace bcassim
