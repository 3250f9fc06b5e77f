#include "host/bench/BenchRunner.hpp"

#include <algorithm>
#include <cctype>
#include <map>
#include <memory>

#include "gl/FrameRenderer.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/run/RunLayer.hpp"
#include "host/scene/LightAnimator.hpp"
#include "host/run/OutputFiles.hpp"
#include "host/reference/IndirectReference.hpp"
#include "host/reference/ReferenceCache.hpp"

namespace ml {
namespace {

std::string fileSafe(const std::string& s) {
  std::string out;
  for (char c : s) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.' || c == '=') ? c : '_';
  return out;
}

// The references of one size and light set, by frame: traced once, reused by every variant.
using GiReferences = std::map<std::size_t, IndirectImage>;

// One (size, light set, variant, GI variant) run over the plan's frames.
struct Run {
  const RunScene& scene;
  const BenchPlan& plan;
  FrameRenderer& renderer;
  const LightSetInput& lights;
  const TechniqueVariant& variant;
  const GiVariant& gi;
  GiReferences& references;
  std::string label;  // "<variant>[ gi=<mode>[...]] <lights> <WxH>"
};

// The pass's last indirect image against the frame's reference (traced once
// per run and frame, or read from the reference cache), with its noise.
IndirectComparison giError(const Run& run, const GiPass& pass, std::size_t frame) {
  auto it = run.references.find(frame);
  if (it == run.references.end()) {
    const IndirectOptions o{run.plan.gi_reference_samples, run.plan.gi_reference_seed, false};
    it = run.references
             .emplace(frame, cachedIndirectReference(run.scene.scene, run.lights.lights, run.scene.cameras.frames[frame],
                                                     run.renderer.width(), run.renderer.height(), o)
                                 .image)
             .first;
  }
  return compareWithReference(pass.indirectRgba(), it->second);
}

// `gi`: the run's GI pass (its voxel memory), null without one.
FrameRecord recordOf(const Run& run, std::size_t frame, const GiPass* gi) {
  FrameRecord r;
  r.run = run.label;
  r.technique = run.variant.technique;
  r.pipeline = pipelineName(run.variant.pipeline);
  r.params = run.variant.labels;
  r.lights = run.lights.label;
  r.light_file = run.lights.file;
  r.light_count = static_cast<std::uint32_t>(run.lights.lights.size());
  r.width = run.renderer.width();
  r.height = run.renderer.height();
  r.frame = frame;
  r.gi = run.gi.mode;
  r.gi_settings = run.gi.settings;
  if (gi) r.voxel_bytes = gi->stats().data_bytes;
  return r;
}

void runFrames(ClRuntime& cl, const Run& run, Progress* progress, std::size_t& done,
               const std::function<void(FrameRecord)>& emit) {
  const BenchPlan& plan = run.plan;
  FrameRenderer& renderer = run.renderer;
  renderer.setLights(run.lights.lights);
  LightAnimator animator(run.lights.lights, plan.animate, kThesisSeed, plan.animate_speed);
  auto animate = [&] {
    if (animator.movesPerStep() > 0) renderer.setLights(animator.step());
  };
  auto assigner = makeAssigner(*run.variant.info, cl, run.variant.params, &run.scene.scene);
  const std::unique_ptr<GiPass> gi = run.gi.make ? run.gi.make(cl, run.scene.scene) : nullptr;
  FrameOptions options{run.variant.pipeline, false, plan.shade};
  options.gi = gi.get();
  if (progress) progress->update(done, run.label + " (warm-up)");
  if (!plan.frames.empty())
    for (unsigned w = 0; w < plan.warmup; ++w)
      renderer.render(run.scene.cameras.frames[plan.frames.front()], *assigner, options);
  for (std::size_t frame : plan.frames) {
    if (progress) progress->update(done, run.label + " frame " + std::to_string(frame));
    const Camera& cam = run.scene.cameras.frames[frame];
    FrameRecord r = recordOf(run, frame, gi.get());
    if (plan.counts) {
      animate();
      setCounts(r, countedRender(renderer, *assigner, options, cam));
    }
    if (plan.timing) {
      const GiUpdateCounts before = gi ? gi->updateCounts() : GiUpdateCounts{};
      setTimes(r, timedRenders(renderer, *assigner, options, cam, plan.repeat, animate));
      if (gi) {
        const GiUpdateCounts after = gi->updateCounts();
        r.gi_updates = GiUpdateCounts{after.ran - before.ran, after.reused - before.reused};
      }
    }
    if (gi && plan.timing && plan.gi_reference_samples > 0) {
      const IndirectComparison e = giError(run, *gi, frame);
      r.gi_rel_rmse = e.error.rel_rmse;
      r.gi_ref_noise = e.ref_noise;
      r.gi_rel_rmse_corrected = e.corrected;
    }
    if (!plan.image_dir.empty())  // the folder was checked before the first frame (requireOutputDir)
      writeImageAtomically("--images", plan.image_dir + "/" + fileSafe(run.label) + "_f" + std::to_string(frame) + ".png",
                           renderer.width(), renderer.height(), 4, renderer.targets().readColor());
    r.technique_stats = assigner->stats();
    ++done;
    emit(std::move(r));
  }
}

}  // namespace

std::size_t planSteps(const BenchPlan& plan) {
  return plan.sizes.size() * plan.light_sets.size() * plan.variants.size() * plan.gi.size() * plan.frames.size();
}

std::vector<FrameRecord> runBench(ClRuntime& cl, const RunScene& scene, const BenchPlan& plan, Progress* progress,
                                  const std::function<void(const FrameRecord&)>& on_record) {
  std::vector<FrameRecord> records;
  std::size_t done = 0;
  auto emit = [&](FrameRecord r) {
    if (on_record) on_record(r);
    records.push_back(std::move(r));
  };
  for (const auto& [width, height] : plan.sizes) {
    FrameRenderer renderer(cl, scene.scene, width, height);
    const std::string size_label = std::to_string(width) + "x" + std::to_string(height);
    for (const LightSetInput& ls : plan.light_sets) {
      GiReferences references;
      for (const TechniqueVariant& v : plan.variants)
        for (const GiVariant& g : plan.gi)
          runFrames(cl,
                    Run{scene, plan, renderer, ls, v, g, references,
                        v.label + giRunLabel(g) + " " + ls.label + " " + size_label},
                    progress, done, emit);
    }
  }
  if (progress) progress->update(done, "done");
  return records;
}

}  // namespace ml
