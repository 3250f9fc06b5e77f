#include "host/cl/KernelCache.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <random>
#include <set>
#include <string_view>
#include <system_error>

#include "host/cl/ProgramBuilder.hpp"  // fnv1a64

namespace ml {
namespace fs = std::filesystem;

namespace {

constexpr char kMagic[8] = {'M', 'L', 'K', 'C', 'A', 'C', 'H', 'E'};

struct EntryHeader {
  char magic[8];
  std::uint32_t version;
  std::uint32_t header_size;
  std::uint64_t key;
  std::uint64_t binary_size;
  std::uint64_t checksum;  // fnv1a64 of the binary
};
static_assert(sizeof(EntryHeader) == KernelCache::kHeaderSize);

// Folders whose cache is off for the rest of the process (unusable, or a write
// failed): shared by every KernelCache so a run warns once per folder.
std::mutex g_off_mutex;
std::set<std::string> g_off_dirs;

bool isOff(const std::string& dir) {
  std::lock_guard lock(g_off_mutex);
  return g_off_dirs.count(dir) != 0;
}

void warn(const std::string& line) { std::fprintf(stderr, "manylights: warning: %s\n", line.c_str()); }

std::string errnoText(int err) { return std::error_code(err, std::generic_category()).message(); }

std::string hex(std::uint64_t v) {
  char buf[17];
  std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
  return buf;
}

std::uint64_t checksum(const unsigned char* data, std::size_t size) {
  return fnv1a64(std::string_view(reinterpret_cast<const char*>(data), size));
}

// Why `bytes` is not a valid entry for `key`; empty when it is.
std::string validate(const std::vector<unsigned char>& bytes, std::uint64_t key) {
  if (bytes.empty()) return "is empty";
  if (bytes.size() < sizeof(EntryHeader))
    return "is truncated (" + std::to_string(bytes.size()) + " bytes, shorter than its header)";
  EntryHeader h;
  std::memcpy(&h, bytes.data(), sizeof h);
  if (std::memcmp(h.magic, kMagic, sizeof kMagic) != 0) return "is not a manylights kernel cache entry (bad magic)";
  if (h.version != KernelCache::kFormatVersion || h.header_size != sizeof h)
    return "has format version " + std::to_string(h.version) + " (expected " +
           std::to_string(KernelCache::kFormatVersion) + ")";
  if (h.key != key) return "holds the entry of key " + hex(h.key) + " (swapped or renamed)";
  const std::size_t have = bytes.size() - sizeof h;
  if (h.binary_size != have)
    return "is truncated or padded (header says " + std::to_string(h.binary_size) + " bytes of binary, file has " +
           std::to_string(have) + ")";
  if (have == 0) return "holds an empty binary";
  if (h.checksum != checksum(bytes.data() + sizeof h, have)) return "is damaged (checksum mismatch)";
  return {};
}

enum class ReadStatus { Missing, Ok, Failed };

// Reads the whole regular file at `path`; on Failed, `why` says what went wrong.
ReadStatus readFile(const std::string& path, std::vector<unsigned char>& out, struct stat& st, std::string& why) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    if (errno == ENOENT) return ReadStatus::Missing;
    why = "cannot be opened (" + errnoText(errno) + ")";
    return ReadStatus::Failed;
  }
  ReadStatus status = ReadStatus::Ok;
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    why = "is not a readable regular file";
    status = ReadStatus::Failed;
  }
  unsigned char buf[1 << 16];
  while (status == ReadStatus::Ok) {
    const ssize_t n = ::read(fd, buf, sizeof buf);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) {
      why = "cannot be read (" + errnoText(errno) + ")";
      status = ReadStatus::Failed;
    }
    if (n <= 0) break;
    out.insert(out.end(), buf, buf + n);
  }
  ::close(fd);
  return status;
}

// Writes all of `bytes`; empty on success, else why not.
std::string writeAll(int fd, const std::vector<unsigned char>& bytes, const std::string& path) {
  std::size_t done = 0;
  while (done < bytes.size()) {
    const ssize_t n = ::write(fd, bytes.data() + done, bytes.size() - done);
    if (n < 0 && errno == EINTR) continue;
    if (n < 0) return "writing " + path + " failed (" + errnoText(errno) + ")";
    if (n == 0) return "short write to " + path;
    done += static_cast<std::size_t>(n);
  }
  return {};
}

// Unique in the folder across processes (pid), across containers or hosts that
// share the folder and may reuse a pid (a per-process random seed) and within
// the process (a counter).
std::string tempPath(const std::string& dir, std::uint64_t key) {
  static const std::uint64_t seed = [] {
    std::random_device rd;
    return (static_cast<std::uint64_t>(rd()) << 32) ^ rd();
  }();
  static std::atomic<std::uint64_t> counter{0};
  return dir + "/." + hex(key) + "." + std::to_string(::getpid()) + "." + hex(seed) + "." +
         std::to_string(counter++) + ".tmp";
}

// Durable rename: without the folder's fsync a crash may lose the new name.
// Best effort: some file systems refuse fsync on folders, and losing the name
// only costs a recompile.
void syncDir(const std::string& dir) {
  const int fd = ::open(dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (fd < 0) return;
  (void)::fsync(fd);
  ::close(fd);
}

// temp file -> write -> fsync -> close -> rename; empty on success, else why not.
std::string writeAtomically(const std::string& dir, const std::string& path, std::uint64_t key,
                            const std::vector<unsigned char>& bytes) {
  const std::string tmp = tempPath(dir, key);
  const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0644);
  if (fd < 0) return "cannot create " + tmp + " (" + errnoText(errno) + ")";
  std::string err = writeAll(fd, bytes, tmp);
  if (err.empty() && ::fsync(fd) != 0) err = "fsync of " + tmp + " failed (" + errnoText(errno) + ")";
  if (::close(fd) != 0 && err.empty()) err = "closing " + tmp + " failed (" + errnoText(errno) + ")";
  if (err.empty() && ::rename(tmp.c_str(), path.c_str()) != 0)
    err = "renaming " + tmp + " to " + path + " failed (" + errnoText(errno) + ")";
  if (!err.empty()) {
    ::unlink(tmp.c_str());
    return err;
  }
  syncDir(dir);
  return {};
}

// Why `dir` cannot hold the cache (after creating it); empty when it can.
std::string unusable(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) return "cannot create folder " + dir + " (" + ec.message() + ")";
  if (!fs::is_directory(dir, ec)) return dir + " is not a folder";
  if (::access(dir.c_str(), W_OK | X_OK) != 0) return "folder " + dir + " is not writable (" + errnoText(errno) + ")";
  return {};
}

}  // namespace

std::vector<unsigned char> encodeKernelCacheEntry(std::uint64_t key, const std::vector<unsigned char>& binary) {
  EntryHeader h{};
  std::memcpy(h.magic, kMagic, sizeof kMagic);
  h.version = KernelCache::kFormatVersion;
  h.header_size = sizeof h;
  h.key = key;
  h.binary_size = binary.size();
  h.checksum = checksum(binary.data(), binary.size());
  std::vector<unsigned char> out(sizeof h + binary.size());
  std::memcpy(out.data(), &h, sizeof h);
  if (!binary.empty()) std::memcpy(out.data() + sizeof h, binary.data(), binary.size());
  return out;
}

KernelCache KernelCache::fromEnvironment() {
  if (const char* dir = std::getenv("MANYLIGHTS_CACHE_DIR"); dir && *dir) {
    if (std::string_view(dir) == "off") return KernelCache({});
    return KernelCache(std::string(dir) + "/kernels", "MANYLIGHTS_CACHE_DIR=" + std::string(dir));
  }
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg)
    return KernelCache(std::string(xdg) + "/manylights/kernels", "XDG_CACHE_HOME=" + std::string(xdg));
  if (const char* home = std::getenv("HOME"); home && *home)
    return KernelCache(std::string(home) + "/.cache/manylights/kernels", "HOME=" + std::string(home));
  return KernelCache({});
}

void KernelCache::checkEnvironment() { (void)fromEnvironment(); }

KernelCache::KernelCache(std::string dir, std::string origin) : dir_(std::move(dir)), origin_(std::move(origin)) {
  if (dir_.empty() || isOff(dir_)) return;
  if (std::string why = unusable(dir_); !why.empty()) disable(why);
}

bool KernelCache::enabled() const { return !dir_.empty() && !isOff(dir_); }

std::string KernelCache::entryPath(std::uint64_t key) const {
  return dir_ + "/" + hex(key) + ".v" + std::to_string(kFormatVersion) + ".bin";
}

void KernelCache::disable(const std::string& why) const {
  {
    std::lock_guard lock(g_off_mutex);
    if (!g_off_dirs.insert(dir_).second) return;  // another builder already warned
  }
  warn("kernel cache " + (origin_.empty() ? dir_ : origin_) + ": " + why + "; kernel caching is off for this run");
}

std::optional<std::vector<unsigned char>> KernelCache::load(std::uint64_t key) const {
  if (!enabled()) return std::nullopt;
  const std::string path = entryPath(key);
  std::vector<unsigned char> bytes;
  struct stat st{};
  std::string why;
  const ReadStatus status = readFile(path, bytes, st, why);
  if (status == ReadStatus::Missing) return std::nullopt;
  if (status == ReadStatus::Ok) why = validate(bytes, key);
  if (why.empty()) return std::vector<unsigned char>(bytes.begin() + sizeof(EntryHeader), bytes.end());
  // Delete only the file that was judged: a racing run may have just renamed a
  // fresh entry into its place.
  struct stat now{};
  const bool same = status == ReadStatus::Failed ||
                    (::stat(path.c_str(), &now) == 0 && now.st_dev == st.st_dev && now.st_ino == st.st_ino);
  std::string outcome = "deleted";
  if (same && ::unlink(path.c_str()) != 0 && errno != ENOENT) outcome = "could not delete it (" + errnoText(errno) + ")";
  warn("kernel cache entry " + path + " " + why + "; " + outcome + ", recompiling");
  return std::nullopt;
}

void KernelCache::discard(std::uint64_t key, const std::string& why) const {
  const std::string path = entryPath(key);
  std::string outcome = "deleted";
  if (::unlink(path.c_str()) != 0 && errno != ENOENT) outcome = "could not delete it (" + errnoText(errno) + ")";
  warn("kernel cache entry " + path + " " + why + "; " + outcome + ", recompiling");
}

void KernelCache::store(std::uint64_t key, const std::vector<unsigned char>& binary) const {
  if (!enabled() || binary.empty()) return;
  if (std::string err = writeAtomically(dir_, entryPath(key), key, encodeKernelCacheEntry(key, binary)); !err.empty())
    disable(err);
}

}  // namespace ml
