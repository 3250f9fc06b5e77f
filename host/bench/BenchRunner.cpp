#include "host/bench/BenchRunner.hpp"

#include <algorithm>
#include <cctype>
#include <memory>

#include "gl/FrameRenderer.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/hashed/HashedAssigner.hpp"
#include "host/scene/LightAnimator.hpp"
#include "host/bench/OutputFiles.hpp"

namespace ml {
namespace {

double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

std::string fileSafe(const std::string& s) {
  std::string out;
  for (char c : s) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-' || c == '.' || c == '=') ? c : '_';
  return out;
}

}  // namespace

std::size_t planSteps(const BenchPlan& plan) {
  return plan.sizes.size() * plan.light_sets.size() * plan.variants.size() * plan.frames.size();
}

std::vector<FrameRecord> runBench(ClRuntime& cl, const BenchScene& scene, const BenchPlan& plan, Progress* progress,
                                  const std::function<void(const FrameRecord&)>& on_record) {
  std::vector<FrameRecord> records;
  std::size_t done = 0;
  for (const auto& [width, height] : plan.sizes) {
    FrameRenderer renderer(cl, scene.scene, width, height);
    const std::string size_label = std::to_string(width) + "x" + std::to_string(height);
    for (const LightSetInput& ls : plan.light_sets) {
      for (const TechniqueVariant& v : plan.variants) {
        renderer.setLights(ls.lights);
        LightAnimator animator(ls.lights, plan.animate, 23, plan.animate_speed);
        auto animate = [&] {
          if (animator.movesPerStep() > 0) renderer.setLights(animator.step());
        };
        const std::string run = v.label + " " + ls.label + " " + size_label;
        auto assigner = makeAssigner(v.technique, cl, v.params);
        attachSceneGeometry(*assigner, scene.scene);  // hashed geometry_mask=on needs the triangles
        FrameOptions timed_opts;
        timed_opts.pipeline = v.pipeline;
        FrameOptions count_opts = timed_opts;
        count_opts.count_lights = true;
        if (progress) progress->update(done, run + " (warm-up)");
        if (!plan.frames.empty())
          for (unsigned w = 0; w < plan.warmup; ++w)
            renderer.render(scene.cameras.frames[plan.frames.front()], *assigner, timed_opts);

        for (std::size_t frame : plan.frames) {
          if (progress) progress->update(done, run + " frame " + std::to_string(frame));
          const Camera& cam = scene.cameras.frames[frame];
          FrameRecord r;
          r.run = run;
          r.technique = v.technique;
          r.pipeline = v.pipeline == Pipeline::Forward ? "forward" : "deferred";
          r.params = v.labels;
          r.lights = ls.label;
          r.light_file = ls.file;
          r.light_count = static_cast<std::uint32_t>(ls.lights.size());
          r.width = width;
          r.height = height;
          r.frame = frame;
          if (plan.counts) {
            animate();
            const FrameResult c = renderer.render(cam, *assigner, count_opts);
            r.counted = true;
            r.light_evaluations = c.light_evaluations;
            r.lower_bound = c.lower_bound;
            r.covered_pixels = c.covered_pixels;
            r.fragment_evaluations = c.fragment_evaluations;
            r.memory_bytes = c.memory_bytes;
          }
          if (plan.timing) {
            std::vector<FrameResult> reps;
            for (unsigned i = 0; i < std::max(plan.repeat, 1u); ++i) {
              animate();
              reps.push_back(renderer.render(cam, *assigner, timed_opts));
            }
            for (const auto& [name, ms] : reps.front().passes.entries()) {
              (void)ms;
              std::vector<double> vals;
              for (const auto& f : reps) vals.push_back(f.passes.get(name));
              r.passes.add(name, median(vals));
            }
            std::vector<double> host;
            for (const auto& f : reps) host.push_back(f.host_ms);
            r.host_ms = median(host);
            r.passes_total_ms = r.passes.total();
            r.memory_bytes = std::max(r.memory_bytes, reps.back().memory_bytes);
            r.timed = true;
          }
          if (!plan.image_dir.empty())  // the folder was checked before the first frame (requireOutputDir)
            writeImageAtomically("--images", plan.image_dir + "/" + fileSafe(run) + "_f" + std::to_string(frame) + ".png",
                                 width, height, 4, renderer.targets().readColor());
          r.technique_stats = assigner->stats();
          ++done;
          if (on_record) on_record(r);
          records.push_back(std::move(r));
        }
      }
    }
  }
  if (progress) progress->update(done, "done");
  return records;
}

}  // namespace ml
