#include "host/run/Progress.hpp"

#include <sys/ioctl.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>

#include "host/util/Error.hpp"

namespace ml {

Progress::Mode Progress::parseMode(const std::string& text, const std::string& flag) {
  if (text == "auto") return Mode::Auto;
  if (text == "bar") return Mode::Bar;
  if (text == "lines") return Mode::Lines;
  if (text == "none") return Mode::None;
  throw UserError(flag + ": expected auto|bar|lines|none, got '" + text + "'");
}

Progress::Progress(std::size_t total, Mode mode, std::FILE* out)
    : total_(std::max<std::size_t>(total, 1)), mode_(mode), out_(out), start_(std::chrono::steady_clock::now()) {
  if (mode_ == Mode::Auto) mode_ = ::isatty(::fileno(out_)) ? Mode::Bar : Mode::Lines;
}

double Progress::elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
}

std::string Progress::formatDuration(double s) {
  if (!std::isfinite(s) || s < 0) return "--";
  const long t = std::lround(s);
  char buf[32];
  if (t < 60) std::snprintf(buf, sizeof buf, "%lds", t);
  else if (t < 3600) std::snprintf(buf, sizeof buf, "%ldm%02lds", t / 60, t % 60);
  else std::snprintf(buf, sizeof buf, "%ldh%02ldm", t / 3600, (t % 3600) / 60);
  return buf;
}

std::string Progress::eta(std::size_t done) const {
  if (done == 0) return "--";
  return formatDuration(elapsed() / static_cast<double>(done) * static_cast<double>(total_ - std::min(done, total_)));
}

void Progress::update(std::size_t done, const std::string& what) {
  if (mode_ == Mode::None || finished_) return;
  done = std::min(done, total_);
  const int pct = static_cast<int>(100.0 * static_cast<double>(done) / static_cast<double>(total_));
  if (mode_ == Mode::Bar) {
    int cols = 100;
    winsize ws{};
    if (::ioctl(::fileno(out_), TIOCGWINSZ, &ws) == 0 && ws.ws_col > 20) cols = ws.ws_col;
    constexpr int kBar = 24;
    const int filled = static_cast<int>(kBar * static_cast<double>(done) / static_cast<double>(total_));
    char head[160];
    std::snprintf(head, sizeof head, "[%s%s] %zu/%zu %3d%% ETA %s  ", std::string(filled, '#').c_str(),
                  std::string(kBar - filled, '.').c_str(), done, total_, pct, eta(done).c_str());
    std::string line = head + what;
    if (static_cast<int>(line.size()) > cols - 1) line.resize(static_cast<std::size_t>(cols - 1));
    std::fprintf(out_, "\r%s\033[K", line.c_str());
    std::fflush(out_);
    drawn_ = true;
    return;
  }
  const double now = elapsed();
  const bool step_due = done == 0 || (done - last_line_done_) * 10 >= total_;
  if (!step_due && now - last_line_s_ < 15.0) return;
  std::fprintf(out_, "progress: %zu/%zu (%d%%), %s elapsed, ETA %s: %s\n", done, total_, pct,
               formatDuration(now).c_str(), eta(done).c_str(), what.c_str());
  std::fflush(out_);
  last_line_s_ = now;
  last_line_done_ = done;
}

void Progress::finish() {
  if (mode_ == Mode::None || finished_) return;
  finished_ = true;
  if (mode_ == Mode::Bar && drawn_) std::fprintf(out_, "\r\033[K");
  std::fprintf(out_, "progress: %zu/%zu done in %s\n", total_, total_, formatDuration(elapsed()).c_str());
  std::fflush(out_);
}

}  // namespace ml
