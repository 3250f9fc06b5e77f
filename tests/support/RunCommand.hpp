#pragma once
// Runs the manylights binary as a user would, capturing exit code and output.
#include <string>

namespace ml::test {

struct CommandResult {
  int exit_code = -1;
  std::string out;  // stdout
  std::string err;  // stderr
};

// `args` is appended to the binary path as-is (shell syntax); `env` is a
// prefix like "FOO=1 BAR=2".
CommandResult runManylights(const std::string& args, const std::string& env = "");
// Runs a shell command line (no redirections of its own) the same way.
CommandResult runShell(const std::string& command);
std::string tempDir();  // a fresh directory for this test process

}  // namespace ml::test
