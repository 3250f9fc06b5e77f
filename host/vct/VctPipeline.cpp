#include "host/vct/VctPipeline.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <stdexcept>

#include "gl/GlPassTimer.hpp"

namespace ml::vct {
namespace {

bool sameParams(const gpu::VoxelGridParams& a, const gpu::VoxelGridParams& b) {
  return std::memcmp(&a, &b, sizeof(a)) == 0;
}

// Before the first update the cascade is placed around the scene's centre.
glm::vec3 centre(const Aabb& b) { return b.empty() ? glm::vec3(0.0f) : 0.5f * (b.min + b.max); }

// The lattice cells of `coarse` that its window box `b` (foldBox) holds.
LatticeBox latticeCells(const VoxelBox& b, const gpu::VoxelGridParams& coarse) {
  const LatticeCorner k = latticeCorner(coarse);
  const long long c[3] = {k.x, k.y, k.z};
  LatticeBox cells;
  for (int a = 0; a < 3; ++a) {
    cells.lo[a] = c[a] + b.lo[a];
    cells.hi[a] = c[a] + b.hi[a];
  }
  return cells;
}

// The window box of `g` that holds the cells of a and b (the smallest box
// around both, clipped to the window; empty when it misses).
VoxelBox windowBoxAround(const LatticeBox& a, const LatticeBox& b, const gpu::VoxelGridParams& g) {
  const LatticeCorner k = latticeCorner(g);
  const long long c[3] = {k.x, k.y, k.z};
  VoxelBox w;
  for (int i = 0; i < 3; ++i) {
    const long long lo = std::max(std::min(a.lo[i], b.lo[i]) - c[i], 0LL);
    const long long hi = std::min(std::max(a.hi[i], b.hi[i]) - c[i], static_cast<long long>(g.edge));
    if (hi <= lo) return VoxelBox{};
    w.lo[i] = static_cast<unsigned>(lo);
    w.hi[i] = static_cast<unsigned>(hi);
  }
  return w;
}

}  // namespace

bool LatticeBox::operator==(const LatticeBox& o) const {
  return std::equal(lo, lo + 3, o.lo) && std::equal(hi, hi + 3, o.hi);
}

VctPipeline::VctPipeline(ClRuntime& rt, const VctPipelineOptions& options, const Aabb& scene_bounds)
    : rt_(rt),
      options_(options),
      bounds_(scene_bounds),
      env_(rt),
      injector_(env_, options.compute, options.shadows),
      occupancy_(env_, options.compute),
      mips_(env_, options.compute),
      fold_(env_, options.compute),
      lists_(env_),
      hashed_(hashed::HashedConfig{}) {
  checkCascades(options.cascades);
  if (options.cascades > 1 && options.shadows)  // users get checkVctGiSettings' line first
    throw std::invalid_argument("VctPipeline: shadows need one level (the march reads one unscrolled grid)");
  const auto placed = placeCascade(bounds_, options.grid, options.cascades, centre(bounds_), options.fold);
  for (unsigned c = 0; c < options.cascades; ++c)
    levels_.push_back(
        std::make_unique<CascadeLevel>(rt, cascadeLevelSettings(options.grid, options.cascades, c), placed[c]));
}

std::size_t VctPipeline::bytes() const { return cascadeBytes(options_.grid, cascades()); }

bool VctPipeline::moves(const glm::vec3& eye) const {
  const auto placed = placeCascade(bounds_, options_.grid, cascades(), eye, options_.fold);
  for (unsigned c = 0; c < cascades(); ++c)
    if (!levels_[c]->placed || !sameParams(levels_[c]->volume.params(), placed[c])) return true;
  return false;
}

void VctPipeline::voxelize(const SceneGpu& scene, const glm::vec3& eye, PassTimings& timings,
                           std::vector<bool>& touched, std::vector<VoxelRegion>& regions) {
  const auto placed = placeCascade(bounds_, options_.grid, cascades(), eye, options_.fold);
  GlPassTimer gl_timer;
  for (unsigned c = 0; c < cascades(); ++c) {
    CascadeLevel& l = *levels_[c];
    const bool fresh = !l.placed || options_.revoxelize;
    if (!fresh && sameParams(l.volume.params(), placed[c])) continue;
    ScrollUpdate u = fresh ? ScrollUpdate{} : scrollRegion(&l.volume.params(), placed[c]);
    l.volume.setParams(placed[c]);
    voxelize_.run(scene, placed[c], l.volume.accum(), &gl_timer, u.full ? VoxelRegion{} : u.region);
    touched[c] = true;
    regions[c] = u.full ? VoxelRegion{} : u.region;
    l.placed = true;
    if (u.full) {
      ++report_.full_levels;
      ++voxelizations_;
    } else {
      ++report_.scrolled_levels;
      report_.scrolled_voxels += regionVoxels(u.region, placed[c].edge);
    }
  }
  gl_timer.collect(timings);
}

void VctPipeline::update(const SceneGpu& scene, const std::vector<gpu::PointLight>& lights, PassTimings& timings,
                         const VctUpdateInputs& in) {
  report_ = {};
  std::vector<bool> touched(cascades(), false);
  std::vector<VoxelRegion> regions(cascades());
  voxelize(scene, in.eye, timings, touched, regions);
  if (touched.back() && cascades() == 1) occupancy_stale_ = true;
  const bool relight = in.lights_changed || !lists_valid_;
  cl::CommandQueue& q = rt_.queue();
  if (relight) uploadLights(q, lights, timings);
  ClPassTimer timer;
  std::vector<bool> changed(cascades(), false);
  for (unsigned c = 0; c < cascades(); ++c) {
    const LevelWork w = levelWork(c, relight, touched[c], regions[c], c > 0 && changed[c - 1]);
    if (!w.run) continue;
    CascadeLevel& l = *levels_[c];
    VoxelVolume& v = l.volume;
    v.accum().acquireForCl(q, ClAccess::Read);
    v.radiance().acquireForCl(q, ClAccess::ReadWrite);
    if (v.anisotropic()) v.anisotropic()->acquireForCl(q, ClAccess::Write);
    if (options_.shadows && occupancy_stale_) {
      occupancy_.build(q, v.params().edge, v.accum().cl(), &timer);
      occupancy_stale_ = false;
    }
    if (w.inject) lightLevel(q, l, lights.size(), w.region, timer);
    if (c > 0 && options_.fold) fold(q, c, timer);
    mips(q, v, timer);
    if (v.anisotropic()) v.anisotropic()->releaseToGl(q);
    v.radiance().releaseToGl(q);
    v.accum().releaseToGl(q);
    unpackTextures(l, timings);
    changed[c] = true;
  }
  timer.collect(timings);
  ++updates_;
}

void VctPipeline::refilter(PassTimings& timings) {
  if (cascades() != 1) throw std::logic_error("VctPipeline::refilter: one level only");
  cl::CommandQueue& q = rt_.queue();
  ClPassTimer timer;
  VoxelVolume& v = volume();
  v.radiance().acquireForCl(q, ClAccess::ReadWrite);
  if (v.anisotropic()) v.anisotropic()->acquireForCl(q, ClAccess::Write);
  mips(q, v, timer);
  timer.collect(timings);
  if (v.anisotropic()) v.anisotropic()->releaseToGl(q);
  v.radiance().releaseToGl(q);
  unpackTextures(*levels_.back(), timings);
}

// A light change or a full voxelization injects the whole level; a scroll
// its slabs. With the fold, a coarser level that runs injects again the
// cells the finer window covered and covers (one box around both): the fold
// reads the level's own injection there, and cells the window left need it
// back; and it runs whenever the finer level changed.
VctPipeline::LevelWork VctPipeline::levelWork(unsigned c, bool relight, bool touched, const VoxelRegion& scrolled,
                                              bool finer_changed) {
  LevelWork w;
  if (relight || (touched && scrolled.empty())) {
    w.run = w.inject = true;
    return w;
  }
  if (touched) w.region = scrolled;
  w.run = touched || (options_.fold && finer_changed);
  if (c > 0 && w.run && options_.fold) {
    const CascadeLevel& l = *levels_[c];
    const gpu::VoxelGridParams& g = l.volume.params();
    const LatticeBox now = latticeCells(foldBox(levels_[c - 1]->volume.params(), g), g);
    const VoxelBox box = windowBoxAround(l.folded.empty() ? now : l.folded, now, g);
    if (box.voxels() > 0) {
      w.region.push_back(box);
      report_.refolded_voxels += box.voxels();
    }
  }
  w.inject = !w.region.empty();
  return w;
}

// Level c's level 0 takes the opacity of level c - 1's mip 1 where that window lies.
void VctPipeline::fold(cl::CommandQueue& q, unsigned c, ClPassTimer& timer) {
  CascadeLevel& fine = *levels_[c - 1];
  CascadeLevel& l = *levels_[c];
  fine.volume.radiance().acquireForCl(q, ClAccess::Read);
  fold_.run(q, fine.volume.params(), fine.volume.radiance().cl(), l.volume.params(), l.volume.radiance().cl(), &timer);
  fine.volume.radiance().releaseToGl(q);
  const VoxelBox box = foldBox(fine.volume.params(), l.volume.params());
  l.folded = latticeCells(box, l.volume.params());
  report_.folded_voxels += box.voxels();
}

void VctPipeline::mips(cl::CommandQueue& q, VoxelVolume& v, ClPassTimer& timer) {
  mips_.isotropic(q, v.params(), v.radiance().cl(), &timer);
  if (v.anisotropic()) mips_.anisotropic(q, v.params(), v.radiance().cl(), v.anisotropic()->cl(), &timer);
}

void VctPipeline::unpackTextures(CascadeLevel& l, PassTimings& timings) {
  GlPassTimer gl_timer;
  VoxelVolume& v = l.volume;
  l.textures.unpack(v.params(), v.radiance().gl(), v.anisotropic() ? v.anisotropic()->gl() : 0, &gl_timer);
  gl_timer.collect(timings);
}

// Lights go to a grown device buffer (never empty: an OpenCL buffer needs a
// size). The first update builds the hashed lists; later ones update them
// incrementally (HashedStructure::update, which rebuilds by itself when that
// is cheaper or the lights left the octree) and upload only what changed.
void VctPipeline::uploadLights(cl::CommandQueue& q, const std::vector<gpu::PointLight>& lights,
                               PassTimings& timings) {
  const std::size_t bytes = std::max<std::size_t>(lights.size(), 1) * sizeof(gpu::PointLight);
  if (bytes > lights_capacity_) {
    lights_ = cl::Buffer(env_.context(), CL_MEM_READ_ONLY, bytes);  // the runtime's CL calls throw on error
    lights_capacity_ = bytes;
  }
  if (!lights.empty())
    q.enqueueWriteBuffer(lights_, CL_TRUE, 0, lights.size() * sizeof(gpu::PointLight), lights.data());
  lists_valid_ = true;
  if (options_.brute_force || lights.empty()) return;
  const auto start = std::chrono::steady_clock::now();
  const hashed::UpdateStats& st = hashed_.update(lights);
  lists_.upload(q, hashed_.linkless(), st.full_rebuild);
  ++(st.full_rebuild ? list_builds_ : list_updates_);
  if (!st.full_rebuild) list_update_bytes_ += lists_.lastUploadBytes();
  timings.add("vct-lists", std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
}

// Without lights the hashed structure has nothing to bound, and brute force
// over zero lights writes the unlit volume.
void VctPipeline::lightLevel(cl::CommandQueue& q, CascadeLevel& l, std::size_t light_count,
                             const VoxelRegion& region, ClPassTimer& timer) {
  VoxelVolume& v = l.volume;
  const gpu::VoxelGridParams& g = v.params();
  if (options_.brute_force || light_count == 0) {
    injector_.brute(q, g, v.accum().cl(), lights_, light_count, v.radiance().cl(), &timer, occupancy(), region);
    return;
  }
  injector_.hashed(q, g, v.accum().cl(), lights_, light_count, lists_, v.radiance().cl(), &timer, occupancy(),
                   region);
}

}  // namespace ml::vct
