#pragma once
// Data model of a benchmark run: frame selections, technique variants (a
// technique plus the parameter values of one sweep point), per-frame records,
// per-run summaries, and their JSON/CSV forms.
//
// JSON schema "manylights-bench/1": {"schema", "meta": {...}, "records": [
//   {"run", "technique", "pipeline", "params": {k: v}, "lights", "light_file",
//    "light_count", "width", "height", "frame", "light_evaluations",
//    "lower_bound", "covered_pixels", "fragment_evaluations", "passes": {name: ms},
//    "passes_total_ms", "host_ms", "memory_bytes", "technique_stats": {k: v}}],
//  "summaries": [{"run", ..., "frames", "light_evaluations": {mean, median, p95,
//    max, min}, "lower_bound": {...}, "passes_total_ms": {...}, "host_ms": {...},
//    "memory_bytes": {...}, "passes": {name: {...}}}]}
// Counts are null in records of runs without counting (--no-counts), times are
// null without timing (--no-timing). CSV: one row per record, the same scalar
// fields, params as "k=v;k=v", then one "pass:<name>_ms" column per pass name.
#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "gl/FrameRenderer.hpp"
#include "host/assign/Techniques.hpp"
#include "host/util/PassTimings.hpp"

namespace ml {

// "FIRST:LAST:STEP" with LAST inclusive; any part may be empty ("::8" = every
// 8th frame of the path, "100:" = from 100 on, "7" = frame 7 only).
struct FrameRange {
  std::size_t first = 0;
  std::optional<std::size_t> last;  // empty: the path's last frame
  std::size_t step = 1;
};
FrameRange parseFrameRange(const std::string& text, const std::string& flag);
// The selected frame indices of a path with `path_frames` frames; LAST past
// the end is clamped. Throws UserError (naming `flag`) when FIRST is past the end.
std::vector<std::size_t> selectFrames(const FrameRange& range, std::size_t path_frames, const std::string& flag);

struct Summary {
  std::size_t n = 0;
  double mean = 0, median = 0, p95 = 0, max = 0, min = 0;
};
// p95 and median interpolate linearly between order statistics (numpy's default).
Summary summarize(std::vector<double> values);
// The q-quantile (0..1) of ascending values, interpolated the same way; 0 when empty.
double percentile(const std::vector<double>& sorted, double q);
nlohmann::ordered_json toJson(const Summary& s);

// Technique parameters a sweep may vary, by key. Keys: tile, tile_depth,
// cluster_tile, unique, cluster_assign, node_size, start_depth, geometry_mask, octant_masks.
const std::vector<std::string>& techniqueParamKeys();
// The keys a technique reads, judged by its registered name ("tiled" ->
// tile, tile_depth; "clustered" -> cluster_tile, unique, cluster_assign;
// "hashed" -> node_size, start_depth, geometry_mask, octant_masks). Sweeping a key a
// technique does not read would only repeat identical runs, so it is not swept
// for that technique.
std::vector<std::string> paramKeysUsedBy(const std::string& technique);
// Sets `key` in `params` from text; UserError naming `flag` on bad key/value.
void setTechniqueParam(TechniqueParams& params, const std::string& key, const std::string& value,
                       const std::string& flag);

struct TechniqueVariant {
  std::string technique;
  Pipeline pipeline = Pipeline::Deferred;
  TechniqueParams params;
  std::vector<std::pair<std::string, std::string>> labels;  // the given keys this technique reads
  std::string label;  // "tiled-deferred[tile=16,tile_depth=none]"
};
// Cartesian product of `sweep` (key -> values) over the keys each technique
// reads. Unknown technique names throw UserError naming `flag`.
std::vector<TechniqueVariant> expandVariants(const std::vector<std::string>& techniques,
                                             const std::vector<std::pair<std::string, std::vector<std::string>>>& sweep,
                                             const TechniqueParams& base, const std::string& flag);

struct FrameRecord {
  std::string run;  // variant label + " " + lights + " " + WxH
  std::string technique;
  std::string pipeline;  // "forward" | "deferred"
  std::vector<std::pair<std::string, std::string>> params;
  std::string lights;      // light-set label
  std::string light_file;  // empty for generated sets
  std::uint32_t light_count = 0;
  unsigned width = 0, height = 0;
  std::size_t frame = 0;
  bool counted = false;
  std::uint64_t light_evaluations = 0, lower_bound = 0, covered_pixels = 0, fragment_evaluations = 0;
  bool timed = false;
  PassTimings passes;  // median over the timed repeats, per pass
  double passes_total_ms = 0;
  double host_ms = 0;
  std::size_t memory_bytes = 0;
  std::vector<std::pair<std::string, double>> technique_stats;
};

struct RunSummary {
  std::string run, technique, pipeline, lights, light_file;
  std::vector<std::pair<std::string, std::string>> params;
  std::uint32_t light_count = 0;
  unsigned width = 0, height = 0;
  std::size_t frames = 0;
  bool counted = false, timed = false;
  Summary light_evaluations, lower_bound, covered_pixels, passes_total_ms, host_ms, memory_bytes;
  std::vector<std::pair<std::string, Summary>> passes;
};
// One summary per distinct `run`, in first-appearance order.
std::vector<RunSummary> summarizeRuns(const std::vector<FrameRecord>& records);

nlohmann::ordered_json recordJson(const FrameRecord& r);
nlohmann::ordered_json summaryJson(const RunSummary& s);
nlohmann::ordered_json benchJson(const nlohmann::ordered_json& meta, const std::vector<FrameRecord>& records,
                                 const std::vector<RunSummary>& summaries);
std::string benchCsv(const std::vector<FrameRecord>& records);
std::string paramsText(const std::vector<std::pair<std::string, std::string>>& params);  // "k=v;k=v"

}  // namespace ml
