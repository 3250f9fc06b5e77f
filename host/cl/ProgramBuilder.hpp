#pragma once
// Builds OpenCL programs from the embedded kernels/<feature>/*.cl with host-chosen defines.
//
// `#include "x.h"` / `#include "feature/x.cl"` lines are expanded from the embedded
// host/shared/ headers and kernels/ (a .cl path is relative to kernels/, e.g.
// "common/view_frustum.cl") before compiling, so the text that is hashed
// is the text that is compiled. Built binaries are cached on disk under
// $MANYLIGHTS_CACHE_DIR/kernels (default $XDG_CACHE_HOME/manylights/kernels or
// ~/.cache/manylights/kernels; `off` disables), keyed by a hash of source,
// options, device, driver and platform: the second run of anything skips the
// LLVM compile. The cache (KernelCache.hpp) checks each entry's header, key and
// checksum before the driver sees it; a bad entry, or one whose binary the
// driver refuses, is deleted with one warning line and recompiled, and a cache
// that cannot be written is turned off with one warning line: the cache never
// makes a run fail. On a driver that ends the process when it refuses a binary
// (Mesa rusticl; KernelCacheProbe.hpp) binaries are neither loaded nor stored:
// every program is built from source there. Programs are also memoised per
// process. A failed build from source throws UserError with the build log.
#include <CL/opencl.hpp>

#include <cstdint>
#include <map>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "host/cl/KernelCache.hpp"

namespace ml {

struct DeviceInfo;

// Ordered list of -D NAME=VALUE pairs (order is part of the cache key).
using Defines = std::vector<std::pair<std::string, std::string>>;

class ProgramBuilder {
 public:
  struct Stats {
    int memory_hits = 0;
    int disk_hits = 0;
    int compiles = 0;
  };

  // Caches in KernelCache::fromEnvironment().
  ProgramBuilder(cl::Context context, cl::Device device, const DeviceInfo& info);
  ProgramBuilder(cl::Context context, cl::Device device, const DeviceInfo& info, KernelCache cache);

  // Builds kernels/<file> (e.g. "compute/scan.cl").
  cl::Program build(std::string_view file, const Defines& defines = {});
  // Builds arbitrary source text; `name` labels errors and the cache entry.
  cl::Program buildSource(std::string_view name, const std::string& source, const Defines& defines = {});

  const Stats& stats() const { return stats_; }
  // Where binaries go; empty when the cache is disabled (MANYLIGHTS_CACHE_DIR=off,
  // an unusable folder, or a write failed earlier in this run).
  std::string cacheDir() const { return cache_.enabled() ? cache_.dir() : std::string(); }
  const KernelCache& cache() const { return cache_; }
  // Whether binaries go to and come from the cache: it is enabled and the
  // driver refuses a bad binary safely (probed once per driver, in a child process).
  bool cachesBinaries();
  // The cache key of a build (source after includes, options, device, driver, platform).
  std::uint64_t cacheKey(std::string_view name, const std::string& source, const Defines& defines = {}) const;

  // Expands #include "..." lines from embedded files (exposed for tests).
  static std::string expandIncludes(std::string_view name, const std::string& source);

 private:
  cl::Program compile(std::string_view name, const std::string& source, const std::string& options,
                      std::uint64_t key);
  std::string options(const Defines& defines) const;
  std::optional<cl::Program> fromCache(const std::string& options, std::uint64_t key);
  void storeInCache(const cl::Program& program, std::uint64_t key);
  cl::Context context_;
  cl::Device device_;
  std::string device_id_;  // device + driver + platform, part of the key
  KernelCache cache_;
  std::optional<bool> driver_refuses_safely_;
  std::map<std::uint64_t, cl::Program> memo_;
  std::mutex mutex_;
  Stats stats_;
};

// 64-bit FNV-1a. Hand-written because the cache key must be stable across
// builds and library versions, which std::hash does not promise.
std::uint64_t fnv1a64(std::string_view data, std::uint64_t seed = 0xcbf29ce484222325ull);

}  // namespace ml
