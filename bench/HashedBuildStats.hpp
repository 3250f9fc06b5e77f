// Hashed shading's build as manylights-hashed-bench reports it: the
// median-total build of a case (its stages, tables, memory, hash attempts),
// as a table row and as JSON.
#pragma once

#include <nlohmann/json.hpp>

#include <string>
#include <vector>

#include "host/hashed/HashedStructure.hpp"

namespace ml {

struct BuildRecord {
  hashed::BuildStats stats;  // the median-total run
  std::vector<hashed::LayerStats> layers;
  std::size_t table_bytes = 0, list_entries = 0, gpu_bytes = 0;
  unsigned depth = 0, layer_count = 0;
  double cell = 0;
  std::uint64_t failed_attempts = 0, rejected = 0;
  double cpu_ms = 0;  // process CPU time of the build, all threads
  // Resident memory the build added at its peak (Linux: VmHWM after resetting
  // it, less VmRSS before; 0 where /proc cannot say), and the estimate that
  // the memory limit is checked against.
  std::size_t peak_bytes = 0, estimated_bytes = 0;
};

// Resets the process's peak resident size and returns the current one
// (bytes; 0 where /proc/self cannot do it); peakRssBytes() reads the peak since.
std::size_t resetPeakRss();
std::size_t peakRssBytes();

inline double mib(double bytes) { return bytes / (1024.0 * 1024.0); }

// `reps` builds of `lights` (`scene`: for the geometry mask, or null); the one
// with the median total time (the upper one for an even count).
BuildRecord timedBuild(const std::vector<gpu::PointLight>& lights, const hashed::HashedConfig& cfg, const Scene* scene,
                       int reps);
nlohmann::ordered_json buildJson(const BuildRecord& r);
void printBuildHeader();
void printBuild(const std::string& lights, const std::string& node, const BuildRecord& r);

}  // namespace ml
