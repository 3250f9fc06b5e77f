#pragma once
// `manylights bench`: every chosen technique over the same scene, camera path
// and light sets, swept over resolutions and technique parameters; per-frame
// light evaluations, exact lower bound, pass times and structure memory, with
// per-run summaries (mean, median, p95, max), written as JSON/CSV and plotted
// by scripts/plot_bench.py. See docs/testbed.md.
#include <CLI/CLI.hpp>

#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "host/run/SceneInputs.hpp"

namespace ml {

struct BenchArgs {
  SceneInputArgs scene;    // scene.lights: a comma list of light sets (see BenchInputs.hpp)
  std::string techniques;  // comma list; empty: every registered technique
  std::string size = "320x320";
  std::string sizes;       // comma list; overrides size
  std::string frames;      // FIRST:LAST:STEP; empty: the whole path
  std::vector<std::string> params;  // "key=v1,v2"
  std::map<std::string, std::string> shorthands;  // --KEY LIST for every registry parameter, by key
  std::string json, csv, plot, images;
  std::string device;
  std::string progress = "auto";
  unsigned repeat = 1;
  unsigned warmup = 1;
  double animate = 0.0;        // fraction of lights moved before every render of a frame
  double animate_speed = 0.25;
  bool no_counts = false;
  bool no_timing = false;
  bool no_shading = false;     // depth + assignment passes only (FrameOptions::shade)
  float fovy = 0, near_plane = 0, far_plane = 0;  // 0: keep the path's
  std::string gi = "none";     // none | vct: a GI pass in every frame; --param sweeps its settings too
  bool gi_reference = false;   // --gi vct: gi_rel_rmse against the ray-traced reference
  unsigned gi_samples = 64;    // the reference's hemisphere samples per pixel (as render's --gi-samples)
  std::uint64_t gi_seed = kThesisSeed;
  std::string command_line;  // for the JSON's meta
};

CLI::App* addBenchCommand(CLI::App& app, BenchArgs& args);
int runBench(const BenchArgs& args);

// Finds a Python 3 that imports matplotlib: $MANYLIGHTS_PYTHON if set (and
// only it), else python3 on the PATH, else /usr/bin/python3; empty if none.
std::string findPlotPython();
// scripts/plot_bench.py of the source tree (or next to the binary); UserError if absent.
std::string plotScriptPath();
// Runs plot_bench.py on a bench JSON into `out_dir`; UserError naming
// python3-matplotlib when it cannot run.
void runPlotScript(const std::string& json_path, const std::string& out_dir);

}  // namespace ml
