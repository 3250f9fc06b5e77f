#pragma once
// Runs a benchmark plan: for every resolution (one FrameRenderer each), light
// set, technique variant and selected camera frame, one counting render (light
// evaluations, exact lower bound, covered pixels) and, separately, `repeat`
// timed renders without counting (counting costs shading time), reporting the
// per-pass median. Each (resolution, light set, variant) run starts with
// `warmup` untimed renders of its first frame, so shader compilation and
// one-off structure builds do not land in the first frame's times.
// Needs a current GL context and a CL runtime that shares with it.
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "host/run/SceneInputs.hpp"
#include "host/run/RunRecords.hpp"
#include "host/bench/GiSweep.hpp"
#include "host/run/Progress.hpp"

namespace ml {

class ClRuntime;

struct BenchPlan {
  std::vector<TechniqueVariant> variants;
  // The GI sweep (GiSweep.hpp): {none} without --gi; each point is a run of
  // its own, with a fresh pass, whose passes land in the timed frames.
  std::vector<GiVariant> gi = {GiVariant{}};
  // > 0: the ray-traced indirect reference (host/reference/IndirectReference)
  // with this many samples per pixel, traced once per size, light set and
  // frame and reused by every GI variant: records get gi_rel_rmse.
  unsigned gi_reference_samples = 0;
  std::uint64_t gi_reference_seed = 0;
  std::vector<LightSetInput> light_sets;
  std::vector<std::pair<unsigned, unsigned>> sizes;
  std::vector<std::size_t> frames;  // indices into the scene's camera path
  bool counts = true;
  bool timing = true;
  bool shade = true;  // false: no shading pass (FrameOptions::shade), records say so
  unsigned repeat = 1;
  unsigned warmup = 1;
  // > 0: before every counted and timed render, this fraction of the lights
  // moves (LightAnimator, seed 23, `animate_speed` radii per step). Every run
  // starts from the light set as loaded, so runs see the same motion.
  double animate = 0.0;
  double animate_speed = 0.25;
  // Non-empty: the shaded image of every record goes here as
  // <run>_f<frame>.png (spaces and brackets replaced), for eyeballing.
  std::string image_dir;
};

std::size_t planSteps(const BenchPlan& plan);  // renders of frames the progress counts (one per record)

// Records in loop order (size, light set, variant, GI variant, frame). `on_record` sees
// each record as soon as it exists (e.g. to stream it).
std::vector<FrameRecord> runBench(ClRuntime& cl, const RunScene& scene, const BenchPlan& plan, Progress* progress,
                                  const std::function<void(const FrameRecord&)>& on_record = {});

}  // namespace ml
