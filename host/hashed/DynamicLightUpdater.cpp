#include "host/hashed/DynamicLightUpdater.hpp"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>

#include "host/hashed/LightOctreeBuilder.hpp"

namespace ml::hashed {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

bool sameVolume(const gpu::PointLight& a, const gpu::PointLight& b) {
  return a.position_radius.x == b.position_radius.x && a.position_radius.y == b.position_radius.y &&
         a.position_radius.z == b.position_radius.z && a.position_radius.w == b.position_radius.w;
}

using Indexed = std::vector<std::pair<std::uint32_t, gpu::PointLight>>;

std::vector<LightOctree> octreesOf(const Indexed& lights, const OctreeBounds& b, const GeometryMask* geometry) {
  std::vector<LightOctree> out(lights.size());
  if (lights.size() < 64) {
    // A few lights: waking the worker threads costs more than it saves
    // (and on a busy machine a late worker stalls the whole frame).
    LightGridScratch s;
    for (std::size_t i = 0; i < lights.size(); ++i) out[i] = buildLightOctree(lights[i].second, lights[i].first, b, s, geometry);
    return out;
  }
  tbb::enumerable_thread_specific<LightGridScratch> scratch;
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, lights.size(), 16), [&](const auto& r) {
    auto& s = scratch.local();
    for (std::size_t i = r.begin(); i != r.end(); ++i)
      out[i] = buildLightOctree(lights[i].second, lights[i].first, b, s, geometry);
  });
  return out;
}

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

  const auto& old = s.lights_;
  const std::size_t n_old = old.size(), n_new = lights.size(), common = std::min(n_old, n_new);
  std::vector<std::uint32_t> moved;
  for (std::size_t i = 0; i < common; ++i)
    if (!sameVolume(old[i], lights[i])) moved.push_back(std::uint32_t(i));
  st.moved = moved.size();
  st.added = n_new > n_old ? n_new - n_old : 0;
  st.removed = n_old > n_new ? n_old - n_new : 0;
  const std::size_t edits = st.moved + st.added + st.removed;
  if (edits == 0) {
    s.lights_ = lights;  // colours only
    st.stale_lights = s.stale_.size();
    st.total_ms = msSince(t0);
    return;
  }
  if (double(edits) > s.cfg_.max_incremental_fraction * double(std::max(n_old, n_new)))
    return rebuild("most lights changed");

  // Old versions come from the octree cache; only new versions are built.
  std::vector<LightOctree> to_remove;
  std::vector<LightOctree> replaced;  // old versions of moved lights (exact mode)
  Indexed to_insert;
  std::vector<std::uint32_t> reinsert;  // current versions re-added after a lazy flush
  auto& cache = s.octrees_;
  for (const auto i : moved) {
    if (s.cfg_.lazy_removal) s.stale_[i].push_back(std::move(cache[i]));
    else replaced.push_back(std::move(cache[i]));
    to_insert.emplace_back(i, lights[i]);
  }
  for (std::size_t i = n_new; i < n_old; ++i) {
    // A removed index must vanish exactly: the shader would read past the lights.
    to_remove.push_back(std::move(cache[i]));
    if (auto it = s.stale_.find(std::uint32_t(i)); it != s.stale_.end()) {
      for (auto& o : it->second) to_remove.push_back(std::move(o));
      s.stale_.erase(it);
    }
  }
  cache.resize(n_new);
  for (std::size_t i = n_old; i < n_new; ++i) to_insert.emplace_back(std::uint32_t(i), lights[i]);
  if (s.cfg_.lazy_removal && double(s.stale_.size()) > s.cfg_.lazy_flush_fraction * double(n_new)) {
    // Exact clean-up: drop every stale version, then re-add the current one
    // (a stale version may share cells with it).
    for (auto& [i, versions] : s.stale_) {
      for (auto& o : versions) to_remove.push_back(std::move(o));
      if (!std::binary_search(moved.begin(), moved.end(), i)) reinsert.push_back(i);
    }
    s.stale_.clear();
    st.flushed = true;
  }

  auto t = Clock::now();
  auto new_octrees = octreesOf(to_insert, s.bounds_, s.lightGeometry());
  st.light_octrees_ms = msSince(t);

  t = Clock::now();
  SceneOctree& tree = *s.tree_;
  tree.setRecording(true);
  for (const auto& o : to_remove) tree.remove(o);
  for (const auto i : reinsert) tree.remove(cache[i]);
  // Moved lights come first in to_insert: replace their old versions in one
  // walk; the rest (added lights, lazy mode) are plain inserts.
  for (std::size_t k = 0; k < new_octrees.size(); ++k) {
    if (k < replaced.size()) tree.replace(replaced[k], new_octrees[k]);
    else tree.insert(new_octrees[k]);
  }
  for (const auto i : reinsert) tree.insert(cache[i]);
  tree.normalize();
  const std::vector<std::uint64_t> touched = tree.takeTouched();
  tree.setRecording(false);
  st.tree_ms = msSince(t);
  for (std::size_t k = 0; k < to_insert.size(); ++k) cache[to_insert[k].first] = std::move(new_octrees[k]);

  t = Clock::now();
  s.linkless_->applyTouched(tree, touched, st.sync);
  st.sync_ms = msSince(t);

  s.lights_ = lights;
  st.stale_lights = s.stale_.size();
  st.total_ms = msSince(t0);
}

}  // namespace ml::hashed
