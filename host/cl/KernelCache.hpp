#pragma once
// On-disk cache of OpenCL program binaries that a damaged disk, a full disk or
// a parallel run cannot poison. One file per key: <dir>/<16 hex digits>.v1.bin.
//
// Format: a 40-byte header in host byte order (magic "MLKCACHE", format version,
// header size, the 64-bit key, the binary's size, fnv1a64 of the binary), then
// the binary. An entry from another byte order fails the magic check.
//
// Writes are atomic: a temp file with a unique name in the same folder (pid, a
// per-process seed from std::random_device, a counter) is written, fsynced and
// renamed over the entry, then the folder is fsynced. A reader sees no entry or
// a whole one; racing writers each rename a whole entry, the last one stays.
//
// load() checks everything the header claims before the driver sees a byte:
// an empty, short, unreadable, foreign (magic, version), swapped (key) or
// damaged (size, checksum) entry is deleted with one warning line on stderr
// naming the file, and the caller recompiles. discard() does the same for an
// entry whose binary the driver refuses. A folder that cannot be created or
// written, and any write failure (short write, ENOSPC, fsync, rename), print
// one warning line and turn the cache off for that folder for the rest of the
// process, so a run never fails or slows down because of its cache.
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace ml {

class KernelCache {
 public:
  // The folder $MANYLIGHTS_CACHE_DIR/kernels, else $XDG_CACHE_HOME/manylights/kernels,
  // else ~/.cache/manylights/kernels; `off` or nothing to go by: disabled.
  static KernelCache fromEnvironment();
  // Start-up check: resolves the folder from the environment and prints the
  // warning for an unusable one now, before any other output of the run.
  static void checkEnvironment();

  // `origin` names where `dir` came from in warnings (e.g. "MANYLIGHTS_CACHE_DIR=/x").
  // Empty `dir`: disabled. Creates the folder; an unusable one disables the cache.
  explicit KernelCache(std::string dir, std::string origin = {});

  bool enabled() const;
  const std::string& dir() const { return dir_; }
  std::string entryPath(std::uint64_t key) const;

  // The binary stored for `key`, or nothing (no entry, cache off, or a bad entry
  // that was just deleted with a warning).
  std::optional<std::vector<unsigned char>> load(std::uint64_t key) const;
  // Stores atomically; a failure warns once and disables the cache.
  void store(std::uint64_t key, const std::vector<unsigned char>& binary) const;
  // Deletes the entry of `key` with one warning line giving `why`.
  void discard(std::uint64_t key, const std::string& why) const;

  static constexpr std::uint32_t kFormatVersion = 1;
  static constexpr std::size_t kHeaderSize = 40;

 private:
  void disable(const std::string& why) const;
  std::string dir_;
  std::string origin_;
};

// Serialises one entry (header + binary); exposed for tests that forge entries.
std::vector<unsigned char> encodeKernelCacheEntry(std::uint64_t key, const std::vector<unsigned char>& binary);

}  // namespace ml
