// One process's part in an MPI job (MPI_COMM_WORLD): initialised on construction, finalised on
// destruction. Only the thread that made it calls MPI (MPI_THREAD_FUNNELED).
#pragma once
#include <string>

namespace bcassim {

class MpiSession {
 public:
  // Started by mpirun or alone (a singleton job of one rank). MPI errors are returned, not fatal,
  // so that the callers can say what failed (checkMpi).
  MpiSession();
  ~MpiSession();
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }

 private:
  int rank_ = 0, size_ = 1;
};

// Throws std::runtime_error "MPI: <what>: <MPI's reason>" unless rc is MPI_SUCCESS.
void checkMpi(int rc, const std::string& what);

// Waits until a message from `source` (-1: any) with `tag` can be received, and returns its
// source. Polls every 50 us instead of spinning in MPI_Recv (OpenMPI's busy wait), so that a rank
// waiting for the others leaves its core to them and to its own threads: ranks x threads share
// the cores of a node.
int waitForMessage(int source, int tag, const std::string& what);

}  // namespace bcassim
