// bcassim command-line program: parses arguments and hands over to bcassim::app.
#include "bcassim/cli/Cli.h"

int main(int argc, char** argv) { return bcassim::runCli(argc, argv); }
