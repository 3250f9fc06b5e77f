#include "host/hashed/SceneOctreeBuild.hpp"

#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_pipeline.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>

#include "host/hashed/KeySort.hpp"
#include "host/util/Stopwatch.hpp"

namespace ml::hashed {
namespace {

// Lights per chunk: small enough that the last chunks leave little of the
// merge to wait for, large enough that handing chunks between threads
// costs nothing measurable.
constexpr std::size_t kChunk = 4096;
constexpr unsigned kMortonBits = 10;
constexpr std::size_t kLightPrefetch = 8;

std::uint64_t spread3(std::uint64_t v) {  // 10 bits -> every third of 30
  v &= 0x3FF;
  v = (v | (v << 16)) & 0x30000FF;
  v = (v | (v << 8)) & 0x300F00F;
  v = (v | (v << 4)) & 0x30C30C3;
  v = (v | (v << 2)) & 0x9249249;
  return v;
}

struct Chunk {
  std::size_t begin = 0, end = 0;    // a range of the Morton order
  std::vector<LightOctree> octrees;  // its lights' octrees, in that order
};

}  // namespace

std::vector<std::uint32_t> mortonOrder(const std::vector<gpu::PointLight>& lights, const OctreeBounds& b) {
  const unsigned shift = b.depth > kMortonBits ? b.depth - kMortonBits : 0;
  const double top = double(b.cellsPerAxis() - 1);
  std::vector<std::uint64_t> keys(lights.size()), scratch;
  for (std::size_t i = 0; i < lights.size(); ++i) {
    const auto& p = lights[i].position_radius;
    const glm::dvec3 f = glm::floor(b.toCells({p.x, p.y, p.z}));
    glm::u64vec3 q;
    for (int a = 0; a < 3; ++a) q[a] = std::uint64_t(f[a] >= 0.0 ? std::min(f[a], top) : 0.0) >> shift;  // NaN: 0
    keys[i] = ((spread3(q.x) | spread3(q.y) << 1 | spread3(q.z) << 2) << 32) | i;
  }
  if (keys.size() < kRadixSortMinItems)
    std::sort(keys.begin(), keys.end());
  else
    radixSortBy(keys, scratch, [](std::uint64_t k) { return k; });
  std::vector<std::uint32_t> order(lights.size());
  for (std::size_t i = 0; i < keys.size(); ++i) order[i] = std::uint32_t(keys[i]);
  return order;
}

SceneOctreeBuild buildSceneOctree(const std::vector<gpu::PointLight>& lights, const OctreeBounds& b,
                                  const GeometryMask* mask, bool keep_octrees,
                                  const std::function<void(std::size_t)>& check_lit,
                                  const std::vector<std::uint32_t>* given_order) {
  SceneOctreeBuild out;
  out.tree = std::make_unique<SceneOctree>(b, mask);
  if (keep_octrees) out.octrees.resize(lights.size());
  // Neighbouring lights test the same geometry cells and edit the same tree
  // nodes: in this order they find them in cache (in the lights' own random
  // order at 1M lights nearly every mask cell read was a cache miss).
  std::vector<std::uint32_t> own_order;
  if (!given_order) own_order = mortonOrder(lights, b);
  const std::vector<std::uint32_t>& order = given_order ? *given_order : own_order;
  tbb::enumerable_thread_specific<LightGridScratch> scratch;
  std::size_t next = 0;
  auto take = [&](tbb::flow_control& fc) {
    Chunk c;
    if (next >= order.size()) fc.stop();
    c.begin = next;
    c.end = next = std::min(next + kChunk, order.size());
    return c;
  };
  auto build = [&](Chunk c) {
    LightGridScratch& s = scratch.local();
    c.octrees.reserve(c.end - c.begin);
    for (std::size_t i = c.begin; i < c.end; ++i) {
      // Morton order reads the light array at random: the next lights are
      // asked for ahead so that their misses overlap this one's work.
      if (i + kLightPrefetch < c.end) __builtin_prefetch(&lights[order[i + kLightPrefetch]]);
      c.octrees.push_back(buildLightOctree(lights[order[i]], order[i], b, s, mask));
    }
    return c;
  };
  auto merge = [&](Chunk c) {
    const auto t = SteadyClock::now();
    for (const auto& o : c.octrees) out.filled_cells += o.filled_cells;
    check_lit(out.filled_cells);
    for (const auto& o : c.octrees) out.tree->insert(o);
    out.merge_ms += msSince(t);
    return c;
  };
  // Into their lights' slots after the merge, in parallel: the slots lie
  // anywhere in the array, and those writes missed the cache on the
  // merge's serial path.
  auto keep = [&](Chunk c) {
    if (keep_octrees)
      for (auto& o : c.octrees) out.octrees[o.light] = std::move(o);
  };
  const std::size_t tokens = 4 * std::size_t(tbb::this_task_arena::max_concurrency());
  tbb::parallel_pipeline(tokens, tbb::make_filter<void, Chunk>(tbb::filter_mode::serial_in_order, take) &
                                     tbb::make_filter<Chunk, Chunk>(tbb::filter_mode::parallel, build) &
                                     tbb::make_filter<Chunk, Chunk>(tbb::filter_mode::serial_in_order, merge) &
                                     tbb::make_filter<Chunk, void>(tbb::filter_mode::parallel, keep));
  return out;
}

}  // namespace ml::hashed
