#pragma once
// `manylights render`: renders one camera frame of a scene with one technique,
// prints per-pass times (median over --frames timed frames) and light counts,
// writes the image and optionally a stats JSON.
#include <CLI/CLI.hpp>

#include <string>

#include "host/app/SceneInputs.hpp"
#include "host/assign/Techniques.hpp"

namespace ml {

struct RenderArgs {
  SceneInputArgs inputs;
  std::string technique = "deferred";
  std::string size = "640x360";
  std::string device;
  std::string out;
  std::string stats_json;
  std::string heatmap;     // lights evaluated per pixel, cubehelix
  unsigned heatmap_max = 0;
  bool counts = false;
  unsigned frame = 0;     // index into the camera path
  unsigned frames = 3;    // timed frames
  unsigned warmup = 1;
  TechniqueParams params;
};

void addSceneInputFlags(CLI::App& cmd, SceneInputArgs& a);
CLI::App* addRenderCommand(CLI::App& app, RenderArgs& args);
int runRender(const RenderArgs& args);

// "1280x720" -> (1280, 720); UserError naming `flag` otherwise.
void parseSize(const std::string& text, const std::string& flag, unsigned& w, unsigned& h);

}  // namespace ml
