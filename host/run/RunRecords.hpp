#pragma once
// Data model of a benchmark run: frame selections, technique variants (a
// technique plus the parameter values of one sweep point), per-frame records,
// per-run summaries, and their JSON/CSV forms.
//
// JSON schema "manylights-bench/1": {"schema", "meta": {...}, "records": [
//   {"run", "technique", "pipeline", "params": {k: v}, "lights", "light_file",
//    "light_count", "width", "height", "frame", "light_evaluations",
//    "lower_bound", "covered_pixels", "fragment_evaluations", "passes": {name: ms},
//    "pass_clocks": {name: "device"|"host"}, "passes_total_ms", "host_ms", "memory_bytes", "technique_stats": {k: v},
//    "gi", "gi_settings": {k: v}, "voxel_bytes", "gi_rel_rmse", "gi_updates",
//    "gi_reused" (the GI pass's updates and reuses over the timed renders; null
//    without a GI pass or timing)}],
//  "summaries": [{"run", ..., "frames", "light_evaluations": {mean, median, p95,
//    max, min}, "lower_bound": {...}, "passes_total_ms": {...}, "host_ms": {...},
//    "memory_bytes": {...}, "passes": {name: {...}}, "pass_clocks": {...}}]}
// Counts are null in records of runs without counting (--no-counts), times are
// null without timing (--no-timing). A pass time the device could not measure
// is null (its CSV cell empty), never 0, and so is a total with such a part;
// "pass_clocks" says which passes were timed on the host clock because the
// device's own clock is unusable (host/cl/ClPassTimer.hpp, gl/GlPassTimer.hpp). CSV: one row per record, the same scalar
// fields in the same order (one field table, BenchTypes.cpp; not "shaded"),
// params and gi_settings as "k=v;k=v", then one "pass:<name>_ms" column per pass name.
#include <nlohmann/json.hpp>

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "host/techniques/Registry.hpp"
#include "host/util/GiUpdateCounts.hpp"
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
  double mean = 0, median = 0, p5 = 0, p95 = 0, max = 0, min = 0;
};
// p5, p95 and median interpolate linearly between order statistics (numpy's default).
Summary summarize(std::vector<double> values);
// The q-quantile (0..1) of ascending values, interpolated the same way; 0 when empty.
double percentile(const std::vector<double>& sorted, double q);
nlohmann::ordered_json toJson(const Summary& s);

// A technique with the parameter values of one sweep point.
struct TechniqueVariant {
  const TechniqueInfo* info = nullptr;
  std::string technique;
  Pipeline pipeline = Pipeline::Deferred;
  ParamValues params;  // every parameter of the technique (defaults, then the sweep's)
  std::vector<std::pair<std::string, std::string>> labels;  // the given keys this technique reads
  std::string label;  // "tiled-deferred[tile=16,tile_depth=none]"
};
using ParamSweep = std::vector<std::pair<std::string, std::vector<std::string>>>;  // key -> values
// Cartesian product of `sweep` over the keys each technique reads (its
// descriptor's parameters: sweeping a key a technique does not read would
// only repeat identical runs). Every value is checked against its
// parameter's spec first, so a bad value fails before anything renders;
// unknown keys and values name `flag`, unknown techniques --techniques.
std::vector<TechniqueVariant> expandVariants(const std::vector<std::string>& techniques, const ParamSweep& sweep,
                                             const std::string& flag);
// Every point of the product over `axes` (key -> values), as (key, value)
// lists, the first axis varying fastest; one empty point without axes.
std::vector<std::vector<std::pair<std::string, std::string>>> sweepPoints(
    const std::vector<const ParamSweep::value_type*>& axes);
// "tiled-deferred[tile=16,tile_depth=none]" (the name alone without labels).
std::string variantLabel(const std::string& technique, const std::vector<std::pair<std::string, std::string>>& labels);

// What identifies a run: shared by its frame records and its summary.
struct RunIdentity {
  std::string run;  // variant label + " " + lights + " " + WxH
  std::string technique;
  std::string pipeline;  // "forward" | "deferred"
  std::vector<std::pair<std::string, std::string>> params;
  std::string lights;      // light-set label
  std::string light_file;  // empty for generated sets
  std::uint32_t light_count = 0;
  unsigned width = 0, height = 0;
};

struct FrameRecord : RunIdentity {
  std::size_t frame = 0;
  bool counted = false;
  std::uint64_t light_evaluations = 0, lower_bound = 0, covered_pixels = 0, fragment_evaluations = 0;
  bool timed = false;
  PassTimings passes;  // median over the timed repeats, per pass
  double passes_total_ms = 0;
  double host_ms = 0;
  std::size_t memory_bytes = 0;
  std::vector<std::pair<std::string, double>> technique_stats;
  // false: rendered without the shading pass (--no-shading): light and
  // fragment evaluations are not counted (null in JSON, empty in CSV).
  bool shaded = true;
  // The frame's GI pass (bench --gi): its mode ("none" without one), every
  // setting, its voxel memory, and with --gi-reference the relative RMSE of
  // its indirect image against the ray-traced reference (negative: none).
  std::string gi = "none";
  std::vector<std::pair<std::string, std::string>> gi_settings;
  std::size_t voxel_bytes = 0;
  double gi_rel_rmse = -1;
  // The reference's own noise (relative RMSE) and the error without it
  // (compareWithReference, host/reference/IndirectReference.hpp); negative: none.
  double gi_ref_noise = -1, gi_rel_rmse_corrected = -1;
  // The GI pass's scene updates over the record's timed frames: ran (e.g.
  // VCT's inject/mips/textures) and reused (the lights unchanged since the
  // last update, so those passes are absent: 0 ms in the medians).
  std::optional<GiUpdateCounts> gi_updates;
};

struct RunSummary : RunIdentity {
  std::size_t frames = 0;
  bool counted = false, timed = false, shaded = true;
  Summary light_evaluations, lower_bound, covered_pixels, passes_total_ms, host_ms, memory_bytes;
  std::vector<std::pair<std::string, Summary>> passes;  // n == 0: every frame's time missing (null)
  std::vector<std::string> host_clock_passes;            // timed on the host clock in some frame
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
