// bcassim command-line program: hands its arguments to runCli (Cli.cpp).
#include "bcassim/cli/Cli.h"

int main(int argc, char** argv) { return bcassim::runCli(argc, argv); }
