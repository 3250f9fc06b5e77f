// manylights command line: see `manylights --help`.
#include "host/app/Cli.hpp"

int main(int argc, char** argv) { return ml::runCli(argc, argv); }
