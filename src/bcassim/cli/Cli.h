// Entry point of the bcassim command-line program (subcommands simulate, mesh info, ...).
#pragma once

namespace bcassim {
// Runs the CLI; returns the process exit code. Errors are printed as one line on stderr.
int runCli(int argc, char** argv);
}  // namespace bcassim
