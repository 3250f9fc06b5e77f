#include "host/bench/RunLayer.hpp"

#include <algorithm>
#include <cstdio>

#include "host/shared/depth_convention.h"
#include "host/util/Heatmap.hpp"

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
  for (const auto& [name, ms] : frames.front().passes.entries()) {
    (void)ms;
    std::vector<double> v;
    for (const auto& f : frames) v.push_back(f.passes.get(name));
    t.passes.add(name, summarize(v).median);
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

std::vector<float> frameHeatmap(const FrameRenderer& renderer, Pipeline pipeline, unsigned channel,
                                std::uint32_t max_value, std::uint32_t& scale_max) {
  const auto depth = renderer.targets().readDepth(pipeline == Pipeline::Deferred);
  std::vector<bool> covered(depth.size());
  for (std::size_t i = 0; i < depth.size(); ++i) covered[i] = !gpu::is_sky_depth(depth[i]);
  const auto counts = renderer.targets().readCounts();
  scale_max = max_value ? max_value : heatmapScaleMax(counts, 2, channel, covered);
  return heatmapRgba(counts, 2, channel, covered, scale_max);
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
