// A TCP connection or listening socket (POSIX), owned: closed when destroyed. The transport under
// the OpenIGTLink messages of IgtlServer and IgtlReplay; knows nothing of their content.
#pragma once
#include <cstddef>
#include <string>

namespace bcassim {

class TcpSocket {
 public:
  TcpSocket() = default;
  explicit TcpSocket(int fd) : fd_(fd) {}
  ~TcpSocket();
  TcpSocket(TcpSocket&& other) noexcept;
  TcpSocket& operator=(TcpSocket&& other) noexcept;
  TcpSocket(const TcpSocket&) = delete;
  TcpSocket& operator=(const TcpSocket&) = delete;

  // Listens on `host` (e.g. "127.0.0.1", "0.0.0.0") and `port` (0: any free port, see port()).
  // Throws InputError naming the address when it cannot.
  static TcpSocket listenOn(const std::string& host, int port);
  // Connects to host:port. Throws InputError naming the address when it cannot.
  static TcpSocket connectTo(const std::string& host, int port);

  // The next waiting connection (blocks until there is one).
  TcpSocket accept() const;

  // Reads exactly n bytes; false when the peer closed the connection (or an error) first.
  bool readExactly(void* data, std::size_t n) const;
  // Writes all n bytes; false when the peer is gone or the send timeout passed.
  bool writeAll(const void* data, std::size_t n) const;
  // Sends give up after `seconds` (a client that stops reading cannot stall the sender).
  void setSendTimeout(double seconds) const;
  // Stops both directions; a thread blocked reading it wakes up.
  void shutdown() const;

  int fd() const { return fd_; }
  bool valid() const { return fd_ >= 0; }
  // The local port (for a socket listening on port 0).
  int port() const;

 private:
  int fd_ = -1;
};

// "HOST:PORT" split; throws InputError naming `what` (e.g. "--to") when it is not of that form.
void splitHostPort(const std::string& text, const std::string& what, std::string& host, int& port);

}  // namespace bcassim
