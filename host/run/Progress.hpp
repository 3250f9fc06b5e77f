#pragma once
// Progress of a long run on stderr: a redrawn bar with ETA when stderr is a
// terminal, plain lines (every 10 % or 15 s, whichever comes first) otherwise,
// so logs of batch runs stay readable.
#include <chrono>
#include <cstddef>
#include <cstdio>
#include <string>

namespace ml {

class Progress {
 public:
  enum class Mode { Auto, Bar, Lines, None };
  static Mode parseMode(const std::string& text, const std::string& flag);  // auto|bar|lines|none

  Progress(std::size_t total, Mode mode, std::FILE* out = stderr);
  // `done` steps finished; `what` names the step now running.
  void update(std::size_t done, const std::string& what);
  void finish();  // final line (and newline after a bar)

  static std::string formatDuration(double seconds);  // "42s", "3m05s", "1h02m"

 private:
  double elapsed() const;
  std::string eta(std::size_t done) const;

  std::size_t total_;
  Mode mode_;
  std::FILE* out_;
  std::chrono::steady_clock::time_point start_;
  double last_line_s_ = -1e9;
  std::size_t last_line_done_ = 0;
  bool drawn_ = false;
  bool finished_ = false;
};

}  // namespace ml
