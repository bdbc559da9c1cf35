// The one line rank 0 prints when mpirun ends the job under it (it terminates every rank once one
// dies): a SIGTERM handler writes the line kept current here, then exits.
#pragma once
#include <string>

namespace bcassim {

// Installs the handler (once per process). Until the first set(), a SIGTERM ends the process
// silently with `exitCode`.
void installJobEndNotice(int exitCode);
// The line the handler writes (a newline is added). Safe against a signal arriving meanwhile.
void setJobEndNotice(const std::string& line);

}  // namespace bcassim
