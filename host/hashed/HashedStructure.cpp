#include "host/hashed/HashedStructure.hpp"

#include <tbb/parallel_invoke.h>

#include "host/hashed/DynamicLightUpdater.hpp"
#include "host/hashed/LightOctreeBuilder.hpp"
#include "host/hashed/OctantMask.hpp"
#include "host/hashed/SceneOctreeBuild.hpp"
#include "host/util/Error.hpp"
#include "host/util/Stopwatch.hpp"

namespace ml::hashed {

void HashedStructure::checkLightCount(std::size_t n) {
  if (n > kMaxHashedLights)
    throw UserError("--lights: hashed shading addresses at most " + std::to_string(kMaxHashedLights) +
                    " lights (24-bit light indices in its index list), got " + std::to_string(n));
}

HashedStructure::HashedStructure(const HashedConfig& config, const Scene* scene) : cfg_(config), scene_(scene) {
  parseNodeSize(cfg_.node_size);  // fail early on a bad flag
  if (cfg_.geometry_mask && !scene_)
    throw UserError("--geometry-mask: hashed shading was given no scene geometry to mask with "
                    "(--no-geometry-mask builds without it)");
}

HashedStructure::~HashedStructure() = default;

void HashedStructure::build(const std::vector<gpu::PointLight>& lights) {
  const auto t0 = SteadyClock::now();
  const OctreeBounds b = computeBounds(lights, cfg_);
  const double bounds_ms = msSince(t0);
  build(lights, b);
  build_stats_.bounds_ms = bounds_ms;
  build_stats_.total_ms += bounds_ms;
}

std::unique_ptr<GeometryMask> HashedStructure::buildMask(const OctreeBounds& bounds) const {
  try {
    return std::make_unique<GeometryMask>(*scene_, bounds, cfg_.geometry_margin_cells, cfg_.memory_limit);
  } catch (const GeometryMask::OverLimit& e) {
    throw UserError("--node-size " + cfg_.node_size + ": the geometry mask needs more than " +
                    std::to_string(e.bytes >> 20) + " MiB (limit " + std::to_string(cfg_.memory_limit >> 20) +
                    " MiB); use a larger node size or --no-geometry-mask");
  }
}

void HashedStructure::build(const std::vector<gpu::PointLight>& lights, const OctreeBounds& bounds) {
  checkLightCount(lights.size());
  checkMemory(lights, bounds, cfg_.memory_limit, cfg_.node_size, cfg_.geometry_mask);
  BuildStats st;
  const auto t0 = SteadyClock::now();
  std::unique_ptr<GeometryMask> new_mask;  // built first: a refused mask leaves the last build in place
  std::vector<std::uint32_t> order;         // the lights' Morton order, made beside the mask's serial steps
  if (cfg_.geometry_mask) {
    tbb::parallel_invoke([&] { new_mask = buildMask(bounds); }, [&] { order = mortonOrder(lights, bounds); });
    st.mask_ms = msSince(t0);
    st.mask_cells = new_mask->cellCount();
    st.mask_bytes = new_mask->peakBytes();
  }
  bounds_ = bounds;
  linkless_.reset();
  tree_.reset();
  mask_ = std::move(new_mask);

  auto t = SteadyClock::now();
  auto check_lit = [&](std::size_t lit) {
    if (mask_) checkLitMemory(lights.size(), lit, cfg_.memory_limit, cfg_.node_size);
  };
  SceneOctreeBuild sb = buildSceneOctree(lights, bounds_, mask(), mask() != nullptr, check_lit,
                                         order.empty() ? nullptr : &order);
  st.light_octrees_ms = msSince(t);
  st.merge_ms = sb.merge_ms;
  st.filled_cells = sb.filled_cells;
  tree_ = std::move(sb.tree);
  octrees_ = std::move(sb.octrees);  // with the mask, kept for updates

  t = SteadyClock::now();
  tree_->normalize();
  st.normalize_ms = msSince(t);

  t = SteadyClock::now();
  linkless_ = std::make_unique<LinklessOctree>(bounds_, cfg_, mask_.get());
  linkless_->buildFrom(*tree_, lights);
  st.hash_ms = msSince(t);

  st.scene_nodes = tree_->nodeCount();
  st.index_entries = linkless_->pool().list().size();
  st.leaf_index_entries = tree_->indexEntries();
  st.total_ms = msSince(t0);
  build_stats_ = st;
  lights_ = lights;
  ++builds_;
}

const UpdateStats& HashedStructure::update(const std::vector<gpu::PointLight>& lights) {
  checkLightCount(lights.size());
  UpdateStats st;
  DynamicLightUpdater::apply(*this, lights, st);
  update_stats_ = st;
  return update_stats_;
}

}  // namespace ml::hashed
