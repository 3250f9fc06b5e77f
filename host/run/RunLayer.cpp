#include "host/run/RunLayer.hpp"

#include <algorithm>
#include <cstdio>

#include "host/assign/ExactLowerBound.hpp"
#include "host/shared/depth_convention.h"

namespace ml {

RunContext RunContext::open(const DeviceChoice& device) { return open(device, createHeadlessContext()); }

RunContext RunContext::open(const DeviceChoice& device, std::unique_ptr<GlContext> gl) {
  RunContext ctx;
  ctx.gl = std::move(gl);
  const GlShareHandles share = ctx.gl->shareHandles();
  ctx.cl = ClRuntime::create(device, &share);
  return ctx;
}

void RunContext::printDevices() const {
  std::printf("%s\n%s\n", cl->describe().c_str(), gl->describe().c_str());
}

TimedFrame medianOf(const std::vector<FrameResult>& frames) {
  TimedFrame t;
  if (frames.empty()) return t;
  // Every pass that ran on any frame, in the order they first appear; a frame
  // that did not run it counts 0 ms (it did not spend them), one whose time
  // is missing does not count (all missing: the median is missing too).
  PassTimings names;
  for (const auto& f : frames) names.merge(f.passes);
  for (std::size_t i = 0; i < names.entries().size(); ++i) {
    const std::string& name = names.entries()[i].first;
    std::vector<double> v;
    for (const auto& f : frames)
      if (!PassTimings::isMissing(f.passes.get(name))) v.push_back(f.passes.get(name));
    t.passes.add(name, v.empty() ? PassTimings::kMissing : summarize(v).median, names.clockAt(i));
  }
  std::vector<double> host;
  for (const auto& f : frames) host.push_back(f.host_ms);
  t.host_ms = summarize(host).median;
  t.passes_total_ms = t.passes.total();
  t.memory_bytes = frames.back().memory_bytes;
  t.shaded = frames.back().shaded;
  return t;
}

TimedFrame timedRenders(FrameRenderer& renderer, LightAssigner& assigner, FrameOptions options, const Camera& camera,
                        unsigned repeat, const std::function<void()>& before) {
  options.count_lights = false;
  std::vector<FrameResult> frames;
  for (unsigned i = 0; i < std::max(repeat, 1u); ++i) {
    if (before) before();
    frames.push_back(renderer.render(camera, assigner, options));
  }
  return medianOf(frames);
}

FrameResult countedRender(FrameRenderer& renderer, LightAssigner& assigner, FrameOptions options,
                          const Camera& camera) {
  options.count_lights = true;
  options.gi = nullptr;
  return renderer.render(camera, assigner, options);
}

namespace {

std::vector<bool> coveredPixels(const std::vector<float>& depth) {
  std::vector<bool> covered(depth.size());
  for (std::size_t i = 0; i < depth.size(); ++i) covered[i] = !gpu::is_sky_depth(depth[i]);
  return covered;
}

}  // namespace

FrameHeatmap frameHeatmap(const FrameRenderer& renderer, Pipeline pipeline, HeatmapScale scale) {
  const std::vector<bool> covered = coveredPixels(renderer.targets().readDepth(pipeline == Pipeline::Deferred));
  const auto counts = renderer.targets().readCounts();
  if (scale.top == 0) scale.top = heatmapScaleMax(counts, scale.kind, covered);
  return {heatmapRgba(counts, covered, scale), scale};
}

std::vector<float> frameDebugView(const FrameRenderer& renderer, Pipeline pipeline, const Camera& camera,
                                  LightAssigner& assigner, const std::string& view) {
  DebugViewInputs frame;
  frame.width = renderer.width();
  frame.height = renderer.height();
  frame.depth = renderer.targets().readDepth(pipeline == Pipeline::Deferred);
  // The matrices FrameRenderer::render used for this frame.
  const float aspect = float(frame.width) / float(frame.height);
  frame.unproject = boundParams(camera.view(), camera.projection(aspect), frame.width, frame.height);
  return assigner.debugViewRgba(view, frame);
}

void setCounts(FrameRecord& r, const FrameResult& c) {
  r.counted = true;
  r.shaded = c.shaded;
  r.light_evaluations = c.light_evaluations;
  r.lower_bound = c.lower_bound;
  r.covered_pixels = c.covered_pixels;
  r.fragment_evaluations = c.fragment_evaluations;
  r.memory_bytes = c.memory_bytes;
}

void setTimes(FrameRecord& r, const TimedFrame& t) {
  r.timed = true;
  r.shaded = t.shaded;
  r.passes = t.passes;
  r.passes_total_ms = t.passes_total_ms;
  r.host_ms = t.host_ms;
  r.memory_bytes = std::max(r.memory_bytes, t.memory_bytes);
}

}  // namespace ml
