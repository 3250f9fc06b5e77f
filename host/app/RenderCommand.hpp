#pragma once
// `manylights render`: renders one camera frame of a scene with one technique,
// prints per-pass times (median over --frames timed frames) and light counts,
// writes the image and optionally a stats JSON. The technique flags (--tile,
// --node-size, ...) and debug views (--cluster-view) come from the technique
// registry; every value is checked against its parameter's spec before any
// input loads or GL/CL opens.
#include <CLI/CLI.hpp>

#include <map>
#include <string>

#include "host/app/GiOptions.hpp"
#include "host/run/SceneInputs.hpp"
#include "host/techniques/Registry.hpp"

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
  std::string ratio_map;   // lights evaluated / lights in range per pixel (host/util/Heatmap.hpp)
  double ratio_max = 4.0;
  bool counts = false;
  bool no_shading = false;  // depth + assignment passes only (FrameOptions::shade)
  unsigned frame = 0;     // index into the camera path
  unsigned frames = 3;    // timed frames
  unsigned warmup = 1;
  // --animate F: before every timed frame a fraction F of the lights
  // (distinct, chosen at random, seed 23) takes a random step (LightAnimator).
  double animate = 0.0;
  double animate_speed = 0.25;
  GiArgs gi;                                  // --gi reference: the ray-traced indirect image
  std::map<std::string, std::string> params;  // technique flags given, by parameter key ("tile" -> "32")
  std::map<std::string, std::string> views;   // debug views asked for, by view name ("cluster" -> "c.png")
};

// The registry's parameters as flags (--KEY VALUE; switches --KEY / --no-KEY)
// and debug views (--NAME-view FILE), recorded in `params` / `views` only when given.
void addTechniqueFlags(CLI::App& cmd, std::map<std::string, std::string>& params,
                       std::map<std::string, std::string>* views);
CLI::App* addRenderCommand(CLI::App& app, RenderArgs& args);
int runRender(const RenderArgs& args);

}  // namespace ml
