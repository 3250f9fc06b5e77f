#pragma once
// Runs the manylights binary as a user would, capturing exit code and output.
#include <nlohmann/json.hpp>

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

// What a command wrote: the JSON file at `path` (throws if it does not parse),
// and the number of lines of an output (one-line errors are one).
nlohmann::json readJson(const std::string& path);
int lines(const std::string& output);

}  // namespace ml::test
