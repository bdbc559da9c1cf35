// bcassim command-line program: parses arguments and hands over to bcassim::app.
#include "bcassim/app/Cli.h"

int main(int argc, char** argv) { return bcassim::runCli(argc, argv); }
