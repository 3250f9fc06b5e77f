#pragma once
// `manylights compare-reference`: reads the thesis's per-frame light-calculation
// counts (host/suite/ThesisReference.hpp), renders the same frames, light set
// and resolution with the techniques that model each series (ns -> deferred,
// ts/<tile> -> tiled-deferred with that tile and no depth bounds, cs/<tile> ->
// clustered-deferred with that cluster tile), and prints per series our count
// vs theirs (ratio distribution: mean, median, p5, p95, correlation) and the
// technique ratios (tiled/naive, clustered/tiled, clustered/naive) ours vs
// theirs. Series whose technique is not registered in this build are skipped
// with a note, so new techniques are picked up by name when they land.
#include <CLI/CLI.hpp>

#include <string>

#include "host/run/SceneInputs.hpp"

namespace ml {

struct CompareReferenceArgs {
  std::string reference;   // thesis-suite root, reference/, .../light_calculations or frames/
  std::string suite;       // the scene-suite folder (scenes/spaceship-indoor)
  std::string scene_name;  // reference scene folder; empty: the suite folder's name
  std::string techniques;  // our technique names to include; empty: all mapped ones
  std::string tiles;       // tile sizes to include; empty: all
  std::string frames;      // FIRST:LAST:STEP over the reference's frame numbers
  std::string technique_map = "ns=deferred,ts=tiled-deferred,cs=clustered-deferred";
  std::string tile_depth = "none";  // the thesis's tiled shading has no depth bounds
  std::string json, csv, markdown;
  SceneInputArgs inputs;  // --geometry, --allow-missing-meshes (the scene is --suite)
  std::string device;
  std::string progress = "auto";
  double naive_scale = 10.0;
  int frame_offset = 0;  // our camera frame = reference frame + offset
  float fovy = 0;        // 0: the reference config's (45 degrees)
  // Frames whose covered pixels are within this fraction of the thesis's
  // (implied by its naive count) are reported separately as "matched".
  double coverage_tolerance = 0.005;
};

CLI::App* addCompareReferenceCommand(CLI::App& app, CompareReferenceArgs& args);
int runCompareReference(const CompareReferenceArgs& args);

}  // namespace ml
