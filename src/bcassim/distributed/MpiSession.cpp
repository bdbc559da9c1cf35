#include "bcassim/distributed/MpiSession.h"

#include <fmt/format.h>
#include <mpi.h>

#include <chrono>
#include <stdexcept>
#include <thread>

namespace bcassim {

MpiSession::MpiSession() {
  int provided = 0;
  checkMpi(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
  MPI_Comm_set_errhandler(MPI_COMM_WORLD, MPI_ERRORS_RETURN);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

MpiSession::~MpiSession() { MPI_Finalize(); }

void checkMpi(int rc, const std::string& what) {
  if (rc == MPI_SUCCESS) return;
  char reason[MPI_MAX_ERROR_STRING];
  int length = 0;
  MPI_Error_string(rc, reason, &length);
  throw std::runtime_error(fmt::format("MPI: {}: {}", what, std::string(reason, length)));
}

int waitForMessage(int source, int tag, const std::string& what) {
  for (;;) {
    int arrived = 0;
    MPI_Status status;
    checkMpi(
        MPI_Iprobe(source < 0 ? MPI_ANY_SOURCE : source, tag, MPI_COMM_WORLD, &arrived, &status),
        what);
    if (arrived) return status.MPI_SOURCE;
    std::this_thread::sleep_for(std::chrono::microseconds(50));
  }
}

}  // namespace bcassim
