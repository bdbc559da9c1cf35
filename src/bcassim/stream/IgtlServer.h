// An OpenIGTLink server for navigation software (3D Slicer's OpenIGTLinkIF, PLUS, a tracker
// bridge): any number of clients connect and go; POINT and POLYDATA messages from any of them are
// tracked frames, queued with their arrival time; what the caller sends goes to every client. A
// client that sends a malformed message or stops reading is logged in one line (and, when the
// stream cannot be resynchronised, dropped); the server keeps serving. A network thread reads; the
// caller's thread takes frames and sends.
#pragma once
#include <chrono>
#include <condition_variable>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "bcassim/stream/IgtlMessages.h"
#include "bcassim/stream/TcpSocket.h"

namespace bcassim {

struct ReceivedFrame {
  std::string device;  // the POINT or POLYDATA message's device name
  double time = 0.0;   // its time stamp, s
  std::vector<NamedPoint> points;
  std::chrono::steady_clock::time_point arrival;  // when its last byte was read
  int client = 0;                                 // which connection sent it (1, 2, ...)
};

class IgtlServer {
 public:
  // One line per event (a client connected or gone, a message refused); from either thread,
  // never two calls at once.
  using Log = std::function<void(const std::string&)>;

  // Listens on host:port (port 0: any free one, see port()) and starts the network thread.
  // Throws InputError when it cannot listen.
  IgtlServer(const std::string& host, int port, Log log);
  ~IgtlServer();
  IgtlServer(const IgtlServer&) = delete;
  IgtlServer& operator=(const IgtlServer&) = delete;

  int port() const { return port_; }

  // The next tracked frame, waiting at most `timeout`; nullopt when none came by then or after
  // stop().
  std::optional<ReceivedFrame> nextFrame(std::chrono::milliseconds timeout);

  // Sends `message` (whole OpenIGTLink messages) to every connected client; a client that does
  // not take it within the send timeout is dropped (logged). Returns how many clients got it.
  int broadcast(const std::string& message);

  // Clients connected now, and connected so far.
  int clients() const;
  int clientsEver() const;

  // Ends the network thread: nextFrame returns nullopt from now on.
  void stop();

 private:
  struct Client {
    int id = 0;
    TcpSocket socket;
    std::string buffer;  // bytes read that do not make a whole message yet
  };
  void networkLoop();
  void acceptClient();
  // Reads what is waiting from `c`; a client that left is forgotten.
  void readFrom(Client& c);
  // Consumes the whole messages at the front of c.buffer; a stream that cannot be followed
  // drops (forgets) its client.
  void consumeMessages(Client& c);
  void say(const std::string& line);
  // Takes a client off the list before its line is logged, so that whoever reads the line
  // sees the count without it.
  void forget(int id);

  Log log_;
  TcpSocket listener_;
  int port_ = 0;
  int wakeRead_ = -1, wakeWrite_ = -1;  // a pipe that wakes the network thread for stop()

  mutable std::mutex mutex_;  // clients_, frames_, stopped_, counters
  std::condition_variable frameReady_;
  std::map<int, std::shared_ptr<Client>> clients_;
  std::deque<ReceivedFrame> frames_;
  bool stopped_ = false;
  int nextClientId_ = 1;
  std::mutex sendMutex_;  // one broadcast at a time
  std::mutex logMutex_;
  std::thread thread_;
};

}  // namespace bcassim
