#pragma once
// The join half of `compare-reference`: our counted frames of each thesis
// series (SeriesRun, filled by the command's render loop through the run
// layer) joined with the published counts, and the reports written from the
// join: per-series ratios ours/thesis, the technique ratios (tiled/naive,
// clustered/tiled, clustered/naive) ours vs theirs, as a printed table,
// Markdown, CSV and JSON. Frames whose covered pixels match the thesis's
// (implied by its naive count) within a tolerance are also reported apart:
// a missing mesh or a different lens does not distort those.
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "host/suite/ThesisReference.hpp"

namespace ml {

struct SeriesRun {
  const ReferenceSeries* ref = nullptr;
  std::string technique;
  std::string label;  // "tiled-deferred[tile=8,tile_depth=none]"
  std::vector<std::pair<std::string, std::string>> param_labels;
  std::string skipped;  // why it did not run
  std::uint32_t light_count = 0;
  // Per compared frame (reference frame numbers):
  std::vector<std::size_t> frames;
  std::vector<double> ours, thesis, thesis_raw, bound, covered;
};

struct ComparisonSettings {
  double naive_scale = 10.0;          // applied to the thesis's naive counts
  double coverage_tolerance = 0.005;  // "matched" frames
  int frame_offset = 0;
  float fovy = 0;  // 0: the reference config's
  std::string suite;
  std::vector<std::string> missing_meshes;
};

struct ComparisonOutputs {
  std::string json, csv, markdown;  // empty: not written
};

// Prints both tables on stdout and writes the requested files.
void reportComparison(const ThesisReference& ref, const std::vector<SeriesRun>& runs, const ComparisonSettings& s,
                      const ComparisonOutputs& out);

}  // namespace ml
