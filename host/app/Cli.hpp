#pragma once
// Entry point of the `manylights` command: parses the subcommand and its flags,
// runs it, and turns UserErrors into one line on stderr and exit code 2.
namespace ml {
int runCli(int argc, char** argv);
}
