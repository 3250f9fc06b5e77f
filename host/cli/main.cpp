// manylights command line: see `manylights --help`.
#include "host/cli/Cli.hpp"

int main(int argc, char** argv) { return ml::runCli(argc, argv); }
