#include "host/bench/OutputFiles.hpp"

#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <optional>

#include "host/util/DataPaths.hpp"
#include "host/util/Error.hpp"
#include "host/util/ImageIO.hpp"

namespace ml {
namespace fs = std::filesystem;
namespace {

// A name next to `target` that no other process or call picks: the process id
// and a per-process counter; the target's extension is kept (image writers
// choose the format by it).
fs::path tempNameFor(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  const fs::path dir = target.has_parent_path() ? target.parent_path() : fs::path(".");
  // Appended piece by piece: a `"." + std::string` chain trips GCC 12's
  // -Wstringop-overflow false positive under -O3 (as in BenchTypes.cpp).
  std::string name = ".";
  name += target.stem().string();
  name += ".tmp";
  name += std::to_string(::getpid());
  name += '-';
  name += std::to_string(counter++);
  name += target.extension().string();
  return dir / name;
}

fs::path folderOf(const fs::path& p) { return p.has_parent_path() ? p.parent_path() : fs::path("."); }

// /proc and /sys hold kernel interfaces, not folders for results, and as root
// the probe below can succeed there (/proc/self/root/... is any folder, and a
// folder made under /sys/fs/cgroup is a new control group), so paths there are
// refused as written and as resolved through links, before anything is made.
void refuseKernelFolders(const std::string& flag, const std::string& path) {
  std::error_code ec;
  const fs::path as_written = fs::absolute(path, ec).lexically_normal();
  const fs::path resolved = fs::weakly_canonical(as_written, ec);
  for (const fs::path& p : {as_written, resolved}) {
    auto part = p.begin();
    if (part == p.end() || ++part == p.end()) continue;  // the root, then its first folder
    if (*part == "proc" || *part == "sys")
      throw UserError(flag + ": '" + path + "' is under /" + part->string() +
                      " (kernel interfaces, not a place for output files)");
  }
}

// Creates `dir` if missing and proves it takes a new file.
void probeFolder(const std::string& flag, const std::string& shown, const fs::path& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (!fs::is_directory(dir, ec))
    throw UserError(flag + ": cannot create the folder '" + dir.string() + "'" +
                    (shown == dir.string() ? std::string() : " for '" + shown + "'"));
  const fs::path probe = tempNameFor(dir / "probe");
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
  if (fd < 0)
    throw UserError(flag + ": cannot write in the folder '" + dir.string() + "' (" + std::strerror(errno) + ")");
  ::close(fd);
  fs::remove(probe, ec);
}

void replaceWith(const std::string& flag, const fs::path& tmp, const std::string& path) {
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp, ec);
    throw UserError(flag + ": cannot write '" + path + "' (" + ec.message() + ")");
  }
}

}  // namespace

void requireOutputFile(const std::string& flag, const std::string& path) {
  if (path.empty()) return;
  std::error_code ec;
  if (fs::is_directory(path, ec)) throw UserError(flag + ": '" + path + "' is a folder, expected a file name");
  refuseKernelFolders(flag, path);
  probeFolder(flag, path, folderOf(path));
}

void requireOutputDir(const std::string& flag, const std::string& dir) {
  if (dir.empty()) return;
  std::error_code ec;
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
    throw UserError(flag + ": '" + dir + "' is a file, expected a folder");
  refuseKernelFolders(flag, dir);
  probeFolder(flag, dir, dir);
}

void requireImageFile(const std::string& flag, const std::string& path) {
  if (path.empty()) return;
  const std::string ext = fs::path(path).extension().string();
  if (ext != ".png" && ext != ".exr")
    throw UserError(flag + ": '" + path + "' must end in .png (8-bit) or .exr (float)");
  requireOutputFile(flag, path);
}

void writeFileAtomically(const std::string& flag, const std::string& path, const std::string& bytes) {
  const fs::path tmp = tempNameFor(path);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
  if (fd < 0) throw UserError(flag + ": cannot write '" + path + "' (" + std::strerror(errno) + ")");
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) break;
    done += static_cast<std::size_t>(n);
  }
  bool ok = done == bytes.size();
  int saved = ok ? 0 : errno;
  if (ok && ::fsync(fd) != 0) {  // a full disk shows here on some file systems
    ok = false;
    saved = errno;
  }
  ::close(fd);
  if (!ok) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw UserError(flag + ": writing '" + path + "' failed (" + std::strerror(saved ? saved : EIO) + ")");
  }
  replaceWith(flag, tmp, path);
}

void writeImageAtomically(const std::string& flag, const std::string& path, unsigned width, unsigned height,
                          unsigned channels, const std::vector<float>& pixels) {
  const fs::path tmp = tempNameFor(path);
  try {
    writeImage(tmp.string(), width, height, channels, pixels);
  } catch (const UserError& e) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw UserError(flag + ": cannot write '" + path + "': " + e.what());
  }
  replaceWith(flag, tmp, path);
}

std::string reportPath(const std::string& path) {
  std::error_code ec;
  const fs::path p = fs::weakly_canonical(path, ec);
  if (ec || path.empty()) return path;
  auto below = [&](const fs::path& base) -> std::optional<fs::path> {
    std::error_code e;
    const fs::path b = fs::weakly_canonical(base, e);
    if (e) return std::nullopt;
    const fs::path rel = p.lexically_relative(b);
    if (rel.empty() || *rel.begin() == "..") return std::nullopt;
    return rel;
  };
  if (const auto rel = below(dataDir())) return (fs::path("data") / *rel).string();
  if (fs::path(path).is_relative()) return path;
  if (const auto rel = below(fs::current_path(ec))) return rel->string();
  return path;
}

}  // namespace ml
