#pragma once
// The run layer that `render`, `bench`, `compare-reference` and the bench
// mains share, so that each is a front end over the same steps:
//   RunContext ctx = RunContext::open(device);   // headless GL + a CL runtime sharing with it
//   ctx.printDevices();                          // the two start-up lines
//   auto a = makeAssigner(info, *ctx.cl, params, &scene);
//   FrameResult c = countedRender(renderer, *a, {pipeline}, camera);        // counts + lower bound
//   TimedFrame t = timedRenders(renderer, *a, {pipeline}, camera, repeat);  // per-pass medians
// Statistics have one definition: the median (and every quantile) of
// summarize() in BenchTypes.hpp, interpolated between order statistics, so
// `render` and `bench` report the same median for the same frames.
#include <functional>
#include <memory>
#include <vector>

#include "gl/FrameRenderer.hpp"
#include "gl/GlContext.hpp"
#include "host/run/RunRecords.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/util/Heatmap.hpp"

namespace ml {

struct RunContext {
  std::unique_ptr<GlContext> gl;
  std::unique_ptr<ClRuntime> cl;
  static RunContext open(const DeviceChoice& device);
  // Over a given GL context (the viewer's window): CL shares with it the same way.
  static RunContext open(const DeviceChoice& device, std::unique_ptr<GlContext> gl);
  void printDevices() const;  // CL device and GL renderer, one line each, on stdout
};

// Median over `frames` per pass, of the pass sum and of the host wall time.
// A pass absent from a frame (it did not run: a reused VCT volume, the hashed
// technique's skipped update) is 0 ms there; one that ran on one frame of
// three or more has a median of 0 (of two: half its time, the interpolated
// median), and a pass that ran on no frame is not listed.
struct TimedFrame {
  PassTimings passes;
  double passes_total_ms = 0;
  double host_ms = 0;
  std::size_t memory_bytes = 0;  // of the last render
  bool shaded = true;            // false: rendered without the shading pass (--no-shading)
};
TimedFrame medianOf(const std::vector<FrameResult>& frames);

// `repeat` (at least 1) uncounted renders of `camera`; `before` runs before
// each (e.g. a light animation step). `options.count_lights` is ignored.
TimedFrame timedRenders(FrameRenderer& renderer, LightAssigner& assigner, FrameOptions options, const Camera& camera,
                        unsigned repeat, const std::function<void()>& before = {});
// One render that counts light evaluations and the exact lower bound (untimed);
// without shading (options.shade off) only the bound and covered pixels. No GI
// pass runs in it (options.gi is ignored): counts do not depend on it.
FrameResult countedRender(FrameRenderer& renderer, LightAssigner& assigner, FrameOptions options,
                          const Camera& camera);

// The heat map of the last counted frame (FrameRenderer's count target:
// per pixel lights evaluated and lights in range), sky black: the kind and
// top of `scale` pick what it shows and up to where (top 0: the frame's
// maximum); `rgba` is the map, `scale` the scale used, for withColourBar.
struct FrameHeatmap {
  std::vector<float> rgba;
  HeatmapScale scale;
};
FrameHeatmap frameHeatmap(const FrameRenderer& renderer, Pipeline pipeline, HeatmapScale scale);

// A technique's debug view of the last frame rendered with `camera`: the
// assigner gets that frame's depth and unprojection (DebugViewInputs).
std::vector<float> frameDebugView(const FrameRenderer& renderer, Pipeline pipeline, const Camera& camera,
                                  LightAssigner& assigner, const std::string& view);

// A record's counted and timed fields from those renders.
void setCounts(FrameRecord& record, const FrameResult& counted);
void setTimes(FrameRecord& record, const TimedFrame& timed);

}  // namespace ml
