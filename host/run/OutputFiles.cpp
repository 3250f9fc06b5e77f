#include "host/run/OutputFiles.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
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

// A target that is not a place for a file: a device (/dev/null), a pipe or a
// socket, or the process's own stdout/stderr by any name (/dev/stdout, also
// when it is redirected to a regular file). A rename there would replace the
// name (as root, /dev/stdout became a plain file and nothing was printed), so
// such targets are written in place, and the process's own streams through
// their descriptors, after what was printed before.
enum class StreamKind { None, Stdout, Stderr, Other };

StreamKind streamKind(const std::string& path) {
  struct stat target {};
  if (path.empty() || ::stat(path.c_str(), &target) != 0) return StreamKind::None;
  for (const int fd : {1, 2}) {
    struct stat own {};
    if (::fstat(fd, &own) == 0 && own.st_dev == target.st_dev && own.st_ino == target.st_ino)
      return fd == 1 ? StreamKind::Stdout : StreamKind::Stderr;
  }
  return S_ISREG(target.st_mode) || S_ISDIR(target.st_mode) ? StreamKind::None : StreamKind::Other;
}

bool writeAll(int fd, const std::string& bytes) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    done += static_cast<std::size_t>(n);
  }
  return true;
}

void writeToStream(const std::string& flag, const std::string& path, StreamKind kind, const std::string& bytes) {
  std::cout.flush();
  std::cerr.flush();
  std::fflush(nullptr);
  const int fd = kind == StreamKind::Stdout ? 1 : kind == StreamKind::Stderr ? 2 : ::open(path.c_str(), O_WRONLY);
  const bool ok = fd >= 0 && writeAll(fd, bytes);
  const int saved = errno;
  if (kind == StreamKind::Other && fd >= 0) ::close(fd);
  if (!ok) throw UserError(flag + ": writing '" + path + "' failed (" + std::strerror(saved ? saved : EIO) + ")");
}

// An existing link to a regular file is written through: the file it names is
// replaced, the link stays.
fs::path fileBehind(const std::string& path) {
  std::error_code ec;
  if (!fs::is_symlink(path, ec)) return path;
  const fs::path target = fs::canonical(path, ec);
  return ec ? fs::path(path) : target;
}

std::string readWholeFile(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
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
  if (streamKind(path) != StreamKind::None) {
    if (::access(path.c_str(), W_OK) != 0)
      throw UserError(flag + ": cannot write '" + path + "' (" + std::strerror(errno) + ")");
    return;
  }
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
  if (const StreamKind kind = streamKind(path); kind != StreamKind::None)
    return writeToStream(flag, path, kind, bytes);
  const fs::path file = fileBehind(path);
  const fs::path tmp = tempNameFor(file);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL, 0644);
  if (fd < 0) throw UserError(flag + ": cannot write '" + path + "' (" + std::strerror(errno) + ")");
  bool ok = writeAll(fd, bytes);
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
  replaceWith(flag, tmp, file.string());
}

// Image writers take a file name (the format follows its extension), so a
// stream target gets the image made in the temporary folder, then its bytes.
void writeImageAtomically(const std::string& flag, const std::string& path, unsigned width, unsigned height,
                          unsigned channels, const std::vector<float>& pixels) {
  const StreamKind kind = streamKind(path);
  const fs::path file = fileBehind(path);
  const fs::path tmp = tempNameFor(kind == StreamKind::None ? file : fs::temp_directory_path() / file.filename());
  std::error_code ec;
  try {
    writeImage(tmp.string(), width, height, channels, pixels);
  } catch (const UserError& e) {
    fs::remove(tmp, ec);
    throw UserError(flag + ": cannot write '" + path + "': " + e.what());
  }
  if (kind == StreamKind::None) return replaceWith(flag, tmp, file.string());
  const std::string bytes = readWholeFile(tmp);
  fs::remove(tmp, ec);
  writeToStream(flag, path, kind, bytes);
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
