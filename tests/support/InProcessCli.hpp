#pragma once
// Runs `manylights ARGS...` inside the test binary (ml::runCli), capturing
// stdout and stderr through temporary files, so that what the test binary
// registered (extra techniques) is part of the command line.
#include <string>
#include <vector>

namespace ml::test {

struct InProcessResult {
  int exit_code = 0;
  std::string out, err;
};
InProcessResult runCliInProcess(const std::vector<std::string>& args);

}  // namespace ml::test
