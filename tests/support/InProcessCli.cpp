#include "support/InProcessCli.hpp"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include "host/cli/Cli.hpp"

namespace ml::test {
namespace {

// Points `fd` at a fresh temporary file for its lifetime, then restores it
// and keeps what was written.
class Redirect {
 public:
  explicit Redirect(int fd) : fd_(fd) {
    char name[] = "/tmp/manylights-cli-XXXXXX";
    file_ = mkstemp(name);
    if (file_ < 0) throw std::runtime_error("mkstemp failed");
    path_ = name;
    saved_ = dup(fd_);
    dup2(file_, fd_);
  }
  std::string finish() {
    dup2(saved_, fd_);
    close(saved_);
    close(file_);
    std::ifstream in(path_);
    std::stringstream s;
    s << in.rdbuf();
    std::remove(path_.c_str());
    return s.str();
  }

 private:
  int fd_, file_ = -1, saved_ = -1;
  std::string path_;
};

}  // namespace

InProcessResult runCliInProcess(const std::vector<std::string>& args) {
  std::vector<std::string> store = {"manylights"};
  store.insert(store.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (auto& a : store) argv.push_back(a.data());
  std::cout.flush();
  std::fflush(nullptr);
  Redirect out(1), err(2);
  InProcessResult r;
  r.exit_code = runCli(static_cast<int>(argv.size()), argv.data());
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  r.err = err.finish();
  r.out = out.finish();
  return r;
}

}  // namespace ml::test
