#include "host/hashed/DynamicLightUpdater.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <tbb/task_group.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <thread>

#include "host/hashed/LightOctreeBuilder.hpp"
#include "host/hashed/OctantMask.hpp"

namespace ml::hashed {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

bool sameVolume(const gpu::PointLight& a, const gpu::PointLight& b) {
  return a.position_radius.x == b.position_radius.x && a.position_radius.y == b.position_radius.y &&
         a.position_radius.z == b.position_radius.z && a.position_radius.w == b.position_radius.w;
}

using Indexed = std::vector<std::pair<std::uint32_t, gpu::PointLight>>;

// The new versions' octrees, and for moved lights (the first `replaced` of
// them) both versions' subtree ends, which replace() walks by. Built in
// chunks that the tree edits consume in order while later chunks are still
// being built (the edits are sequential; building runs on the other threads
// and on this one whenever it would otherwise wait).
class Batch {
 public:
  static constexpr std::size_t kChunk = 16;
  static constexpr std::size_t kHelpersMinLights = 64;
  Batch(const Indexed& lights, const std::vector<LightOctree>& replaced, const OctreeBounds& b,
        const GeometryMask* geometry)
      : lights_(lights), replaced_(replaced), b_(b), geometry_(geometry), octrees(lights.size()),
        old_ends(replaced.size()), new_ends(replaced.size()), chunks_((lights.size() + kChunk - 1) / kChunk),
        ready_(chunks_) {
    for (auto& r : ready_) r.store(0, std::memory_order_relaxed);
    // A few lights: waking the worker threads costs more than it saves
    // (and on a busy machine a late worker stalls the whole frame).
    if (lights.size() >= kHelpersMinLights) {
      helpers_ = true;
      group_.run([this] {
        tbb::parallel_for(0, int(tbb::this_task_arena::max_concurrency()) - 1, [this](int) { work(); });
      });
    }
  }
  ~Batch() { finish(); }
  // Blocks until octree k is built (building others meanwhile).
  void waitFor(std::size_t k) {
    const std::size_t c = k / kChunk;
    while (!ready_[c].load(std::memory_order_acquire)) {
      if (!claimOne()) std::this_thread::yield();
    }
  }
  void finish() {
    if (helpers_) {
      work();
      group_.wait();
      helpers_ = false;
    }
    while (claimOne()) {
    }
  }

 private:
  const Indexed& lights_;
  const std::vector<LightOctree>& replaced_;
  const OctreeBounds& b_;
  const GeometryMask* geometry_;

 public:
  std::vector<LightOctree> octrees;
  std::vector<std::vector<std::uint32_t>> old_ends, new_ends;

 private:
  std::size_t chunks_;
  std::vector<std::atomic<std::uint8_t>> ready_;
  std::atomic<std::size_t> next_{0};
  tbb::enumerable_thread_specific<LightGridScratch> scratch_;
  tbb::task_group group_;
  bool helpers_ = false;

  void work() {
    while (claimOne()) {
    }
  }
  bool claimOne() {
    const std::size_t c = next_.fetch_add(1, std::memory_order_relaxed);
    if (c >= chunks_) return false;
    auto& s = scratch_.local();
    const std::size_t end = std::min(lights_.size(), (c + 1) * kChunk);
    for (std::size_t i = c * kChunk; i < end; ++i) {
      octrees[i] = buildLightOctree(lights_[i].second, lights_[i].first, b_, s, geometry_);
      if (i < replaced_.size()) {
        SceneOctree::subtreeEnds(replaced_[i], old_ends[i]);
        SceneOctree::subtreeEnds(octrees[i], new_ends[i]);
      }
    }
    ready_[c].store(1, std::memory_order_release);
    return true;
  }
};

}  // namespace

void DynamicLightUpdater::apply(HashedStructure& s, const std::vector<gpu::PointLight>& lights, UpdateStats& st) {
  const auto t0 = Clock::now();
  auto rebuild = [&](const char* why) {
    st.full_rebuild = true;
    st.reason = why;
    s.build(lights);
    st.total_ms = msSince(t0);
  };
  if (!s.built()) return rebuild("first build");
  if (!lightsInside(lights, s.bounds_)) return rebuild("a light left the octree bounds");
  const std::vector<std::uint32_t> moved = diff(s.lights_, lights, st);
  const std::size_t edits = st.moved + st.added + st.removed;
  if (edits == 0) {
    s.lights_ = lights;  // colours only
    st.total_ms = msSince(t0);
    return;
  }
  if (double(edits) > s.cfg_.max_incremental_fraction * double(std::max(s.lights_.size(), lights.size())))
    return rebuild("most lights changed");

  // While this thread edits the tree, another one repacks the previous
  // update's garbage in the light index list, then finds the moved lights'
  // octant masks that change in place: their whole surface, not only where
  // their sets change. Neither reads the tree.
  tbb::task_group background;
  bool compacted = false;
  std::vector<OctantRewrite> rewrites;
  background.run([&] {
    compacted = s.linkless_->compactIfWanted();
    rewrites = findRewrites(s, lights, moved);
  });
  const std::vector<std::uint64_t> touched = editTree(s, lights, moved, st);

  const auto t = Clock::now();
  background.wait();
  st.sync.compacted = compacted;
  s.linkless_->applyOctantRewrites(rewrites, st.sync);
  s.linkless_->applyTouched(*s.tree_, lights, touched, st.sync);
  st.sync_ms = msSince(t);
  s.lights_ = lights;
  st.total_ms = msSince(t0);
}

std::vector<std::uint32_t> DynamicLightUpdater::diff(const std::vector<gpu::PointLight>& old,
                                                     const std::vector<gpu::PointLight>& lights, UpdateStats& st) {
  const std::size_t n_old = old.size(), n_new = lights.size(), common = std::min(n_old, n_new);
  std::vector<std::uint32_t> moved;
  for (std::size_t i = 0; i < common; ++i)
    if (!sameVolume(old[i], lights[i])) moved.push_back(std::uint32_t(i));
  st.moved = moved.size();
  st.added = n_new > n_old ? n_new - n_old : 0;
  st.removed = n_old > n_new ? n_old - n_new : 0;
  return moved;
}

std::vector<OctantRewrite> DynamicLightUpdater::findRewrites(const HashedStructure& s,
                                                             const std::vector<gpu::PointLight>& lights,
                                                             const std::vector<std::uint32_t>& moved) {
  if (!s.linkless_->octantMasks()) return {};
  std::vector<OctantChange> changes;
  // Without the mask, lights are listed where the cell test says (with it,
  // geometry-tight sets list fewer cells): look there.
  const bool both = !s.mask();
  for (const auto i : moved) appendOctantChanges(&s.lights_[i], &lights[i], i, s.bounds_, both, s.mask(), changes);
  return s.linkless_->findOctantRewrites(changes);
}

std::vector<std::uint64_t> DynamicLightUpdater::editTree(HashedStructure& s, const std::vector<gpu::PointLight>& lights,
                                                         const std::vector<std::uint32_t>& moved, UpdateStats& st) {
  const auto t = Clock::now();
  SceneOctree& tree = *s.tree_;
  tree.setRecording(true);
  // Geometry-tight sets need the light octrees (their cells test the geometry).
  const double waited_ms = s.mask() ? editByOctrees(s, lights, moved) : (editByCells(s, lights, moved), 0.0);
  tree.normalize();
  std::vector<std::uint64_t> touched = tree.takeTouched();
  tree.setRecording(false);
  // Building the octrees overlaps the edits: what the edits waited for it
  // (or built it themselves) counts as octree time, the rest as tree time.
  st.light_octrees_ms = waited_ms;
  st.tree_ms = msSince(t) - waited_ms;
  return touched;
}

void DynamicLightUpdater::editByCells(HashedStructure& s, const std::vector<gpu::PointLight>& lights,
                                      const std::vector<std::uint32_t>& moved) {
  const auto& old = s.lights_;
  const std::size_t n_old = old.size(), n_new = lights.size();
  const OctreeBounds& b = s.bounds_;
  SceneOctree& tree = *s.tree_;
  // Both versions of every changed light (no version: added or removed,
  // a default LightCells), built in parallel, then replaced one by one.
  std::vector<std::uint32_t> changed(moved);
  for (std::size_t i = n_new; i < n_old; ++i) changed.push_back(std::uint32_t(i));
  for (std::size_t i = n_old; i < n_new; ++i) changed.push_back(std::uint32_t(i));
  std::vector<LightCells> versions(2 * changed.size());
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, changed.size(), 16), [&](const auto& r) {
    for (std::size_t k = r.begin(); k != r.end(); ++k) {
      const std::uint32_t i = changed[k];
      if (i < n_old) versions[2 * k] = LightCells(old[i], b);
      if (i < n_new) versions[2 * k + 1] = LightCells(lights[i], b);
    }
  });
  for (std::size_t k = 0; k < changed.size(); ++k) tree.replace(versions[2 * k], versions[2 * k + 1], changed[k]);
}

double DynamicLightUpdater::editByOctrees(HashedStructure& s, const std::vector<gpu::PointLight>& lights,
                                          const std::vector<std::uint32_t>& moved) {
  const std::size_t n_old = s.lights_.size(), n_new = lights.size();
  // Old versions come from the octree cache; only new versions are built.
  std::vector<LightOctree> replaced, removed;  // old versions of moved and of removed lights
  Indexed to_insert;
  auto& cache = s.octrees_;
  for (const auto i : moved) {
    replaced.push_back(std::move(cache[i]));
    to_insert.emplace_back(i, lights[i]);
  }
  for (std::size_t i = n_new; i < n_old; ++i) removed.push_back(std::move(cache[i]));
  cache.resize(n_new);
  for (std::size_t i = n_old; i < n_new; ++i) to_insert.emplace_back(std::uint32_t(i), lights[i]);

  Batch batch(to_insert, replaced, s.bounds_, s.mask());
  auto& new_octrees = batch.octrees;
  SceneOctree& tree = *s.tree_;
  // A removed index must vanish exactly: the shader would read past the lights.
  for (const auto& o : removed) tree.remove(o);
  // Moved lights come first in to_insert: their old versions are replaced
  // (one joint walk each); the rest (added lights) are inserts.
  double waited_ms = 0.0;
  for (std::size_t e = 0; e < new_octrees.size(); ++e) {
    const auto w = Clock::now();
    batch.waitFor(e);
    waited_ms += msSince(w);
    if (e < replaced.size()) tree.replace(replaced[e], new_octrees[e], &batch.old_ends[e], &batch.new_ends[e]);
    else tree.insert(new_octrees[e]);
  }
  batch.finish();
  for (std::size_t k = 0; k < to_insert.size(); ++k) cache[to_insert[k].first] = std::move(new_octrees[k]);
  return waited_ms;
}

}  // namespace ml::hashed
