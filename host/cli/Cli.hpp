#pragma once
// Entry point of the `manylights` command: parses the subcommand and its flags,
// runs it, and turns UserErrors into one line on stderr and exit code 2.
// parseCli parses exactly as runCli does and runs nothing (the fuzzer's entry
// point, fuzz/): -1 when a subcommand would run, else runCli's exit code.
namespace ml {
int runCli(int argc, char** argv);
int parseCli(int argc, char** argv);
}
