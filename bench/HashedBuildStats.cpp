#include "HashedBuildStats.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <string>

#include "BenchCommon.hpp"

namespace ml {
namespace {

// "VmRSS:   1234 kB" -> bytes.
std::size_t statusBytes(const char* field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const std::string key = std::string(field) + ":";
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) return std::size_t(std::stoull(line.substr(key.size()))) * 1024;
  return 0;
}

}  // namespace

std::size_t resetPeakRss() {
  std::ofstream("/proc/self/clear_refs") << "5";  // Linux: resets VmHWM to VmRSS
  return statusBytes("VmRSS");
}

std::size_t peakRssBytes() { return statusBytes("VmHWM"); }

BuildRecord timedBuild(const std::vector<gpu::PointLight>& lights, const hashed::HashedConfig& cfg, const Scene* scene,
                       int reps) {
  std::vector<std::pair<double, BuildRecord>> runs;
  for (int i = 0; i < reps; ++i) {
    hashed::HashedStructure hs(cfg, scene);
    const std::size_t rss0 = resetPeakRss();
    const double c0 = benchutil::cpuSeconds();
    hs.build(lights);
    BuildRecord r;
    r.cpu_ms = (benchutil::cpuSeconds() - c0) * 1e3;
    const std::size_t peak = peakRssBytes();
    r.peak_bytes = peak > rss0 ? peak - rss0 : 0;
    r.stats = hs.lastBuild();
    // The larger of the build's two checks (with the mask: before and after the light octrees).
    r.estimated_bytes = hashed::estimateBuildBytes(lights, hs.bounds(), cfg.geometry_mask);
    if (cfg.geometry_mask)
      r.estimated_bytes = std::max(r.estimated_bytes, hashed::estimateLitBytes(lights.size(), r.stats.filled_cells));
    r.layers = hs.linkless().layerStats();
    r.table_bytes = hs.linkless().tableBytes();
    r.list_entries = hs.linkless().pool().list().size();
    r.gpu_bytes = hs.linkless().gpuBytes();
    r.depth = hs.bounds().depth;
    r.layer_count = hs.linkless().layerCount();
    r.cell = hs.bounds().cell_size;
    for (const auto& l : r.layers) {
      r.failed_attempts += (l.desc_attempts - 1) + (l.data_attempts - 1);
      r.rejected += l.rejected_candidates;
    }
    runs.emplace_back(r.stats.total_ms, r);
  }
  std::sort(runs.begin(), runs.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return runs[runs.size() / 2].second;
}

nlohmann::ordered_json buildJson(const BuildRecord& r) {
  nlohmann::ordered_json layers = nlohmann::ordered_json::array();
  for (const auto& l : r.layers)
    layers.push_back({{"depth", l.depth}, {"branches", l.desc_keys}, {"filled_leaves", l.data_keys},
                      {"desc_slots", l.desc_slots}, {"data_slots", l.data_slots}, {"desc_offsets", l.desc_offsets},
                      {"data_offsets", l.data_offsets}, {"bytes", l.bytes}, {"desc_attempts", l.desc_attempts},
                      {"data_attempts", l.data_attempts}, {"rejected_candidates", l.rejected_candidates},
                      {"hash_ms", l.hash_ms}});
  const auto& s = r.stats;
  return {{"cell_size", r.cell},
          {"depth", r.depth},
          {"layers", r.layer_count},
          {"cpu_ms", r.cpu_ms},
          {"peak_bytes", r.peak_bytes},
          {"estimated_bytes", r.estimated_bytes},
          {"ms", {{"total", s.total_ms}, {"bounds", s.bounds_ms}, {"geometry_mask", s.mask_ms},
                  {"light_octrees", s.light_octrees_ms}, {"merge", s.merge_ms}, {"normalize", s.normalize_ms},
                  {"hashes", s.hash_ms}}},
          {"filled_cells", s.filled_cells},
          {"scene_nodes", s.scene_nodes},
          {"table_bytes", r.table_bytes},
          {"index_list_entries", r.list_entries},
          {"unshared_index_entries", s.leaf_index_entries},
          {"gpu_bytes", r.gpu_bytes},
          {"failed_attempts", r.failed_attempts},
          {"rejected_candidates", r.rejected},
          {"per_layer", layers}};
}

void printBuildHeader() {
  std::printf("%-8s %-6s %6s %3s %8s %8s %8s %8s %8s %8s %8s %9s %9s %9s %6s\n", "lights", "node", "cell", "L",
              "total ms", "cpu ms", "octrees", "merge", "normal.", "hashes", "nodes", "tables MiB", "list MiB",
              "GPU MiB",
              "fails");
}

void printBuild(const std::string& lights, const std::string& node, const BuildRecord& r) {
  const auto& s = r.stats;
  std::printf("%-8s %-6s %6.3f %3u %8.2f %8.2f %8.2f %8.2f %8.2f %8.2f %8zu %9.3f %9.3f %9.3f %6llu\n",
              lights.c_str(), node.c_str(), r.cell, r.depth, s.total_ms, r.cpu_ms, s.light_octrees_ms, s.merge_ms,
              s.normalize_ms, s.hash_ms, s.scene_nodes, mib(double(r.table_bytes)), mib(double(r.list_entries) * 4),
              mib(double(r.gpu_bytes)), static_cast<unsigned long long>(r.failed_attempts));
}

}  // namespace ml
