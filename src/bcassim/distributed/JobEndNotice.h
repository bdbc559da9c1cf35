// The one line rank 0 prints when mpirun ends the job under it (it terminates every rank once one
// dies): a SIGTERM handler writes the line kept current here, then exits. The workers' SIGTERM
// waits for it.
#pragma once
#include <string>

namespace bcassim {

// Installs the handler (once per process). Until the first set(), a SIGTERM ends the process
// silently with `exitCode`.
void installJobEndNotice(int exitCode);
// The line the handler writes (a newline is added). Safe against a signal arriving meanwhile.
void setJobEndNotice(const std::string& line);

// A worker rank: a SIGTERM ends the process with `exitCode` only after a grace of a second.
// mpirun (OpenMPI 4) sends SIGTERM to every rank, waits odls_base_sigkill_timeout (1 s), then
// SIGKILL, but the first rank to exit cuts that wait short: a worker dying at its SIGTERM could
// bring rank 0 its SIGKILL before rank 0's handler had written the line. With the grace rank 0
// exits first; its exit brings the workers their SIGKILL.
void installWorkerTerminationGrace(int exitCode);

}  // namespace bcassim
