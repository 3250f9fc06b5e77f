#include "ml_test_paths.h"  // MANYLIGHTS_TEST_DATA_DIR, MANYLIGHTS_BINARY (generated)
#include "support/RunCommand.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace ml::test {

nlohmann::json readJson(const std::string& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

int lines(const std::string& output) {
  int n = 0;
  for (char c : output) n += c == '\n';
  return n;
}

std::string tempDir() {
  static const std::string dir = [] {
    auto d = std::filesystem::temp_directory_path() / ("manylights-test-" + std::to_string(::getpid()));
    std::filesystem::create_directories(d);
    return d.string();
  }();
  return dir;
}

CommandResult runShell(const std::string& command) {
  static int counter = 0;
  const std::string base = tempDir() + "/cmd" + std::to_string(counter++);
  const std::string cmd = command + " >" + base + ".out 2>" + base + ".err </dev/null";
  const int status = std::system(cmd.c_str());
  CommandResult r;
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  auto slurp = [](const std::string& p) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  };
  r.out = slurp(base + ".out");
  r.err = slurp(base + ".err");
  return r;
}

CommandResult runManylights(const std::string& args, const std::string& env) {
  return runShell((env.empty() ? "" : "env " + env + " ") + std::string(MANYLIGHTS_BINARY) + " " + args);
}

}  // namespace ml::test
