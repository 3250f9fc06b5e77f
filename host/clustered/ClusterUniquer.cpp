#include "host/clustered/ClusterUniquer.hpp"

#include <algorithm>
#include <stdexcept>

#include "host/cl/KernelArgs.hpp"
#include "host/cl/ProgramBuilder.hpp"
#include "host/util/Error.hpp"

namespace ml {

UniqueMethod parseUniqueMethod(const std::string& s) {
  if (s == "pagetable") return UniqueMethod::PageTable;
  if (s == "sort") return UniqueMethod::Sort;
  if (s == "tile-sort") return UniqueMethod::TileSort;
  throw UserError("--unique: expected pagetable, sort or tile-sort, got '" + s + "'");
}

const char* uniqueMethodName(UniqueMethod m) {
  switch (m) {
    case UniqueMethod::PageTable: return "pagetable";
    case UniqueMethod::Sort: return "sort";
    case UniqueMethod::TileSort: return "tile-sort";
  }
  return "?";
}

ClusterUniquer::ClusterUniquer(ClRuntime& rt, UniqueMethod method, unsigned page_bits)
    : rt_(rt), method_(method), page_bits_(page_bits), scan_(rt), compact_(rt), radix_(rt), segsort_(rt) {
  if (page_bits < 1 || page_bits > 16) throw std::invalid_argument("ClusterUniquer: page_bits must be 1..16");
  program_ = rt.programs().build("cluster_keys.cl");
  keys_k_ = cl::Kernel(program_, "cluster_keys");
  mark_ = cl::Kernel(program_, "page_mark");
  store_ = cl::Kernel(program_, "page_store");
  inverse_ = cl::Kernel(program_, "page_inverse");
  page_unique_ = cl::Kernel(program_, "page_unique");
  page_map_ = cl::Kernel(program_, "page_map");
  sort_init_ = cl::Kernel(program_, "sort_init");
  gather_ = cl::Kernel(program_, "tile_gather");
  heads_ = cl::Kernel(program_, "head_flags");
  scatter_ = cl::Kernel(program_, "run_scatter");
}

void ClusterUniquer::ensurePixels(std::size_t n) {
  if (n <= pixel_capacity_) return;
  pixel_capacity_ = n;
  const auto& ctx = rt_.context();
  const std::size_t bytes = std::max<std::size_t>(16, n * 4);
  for (cl::Buffer* b : {&keys_, &unique_keys_, &cluster_of_, &sort_keys_, &sort_vals_, &flags_, &rank_})
    *b = cl::Buffer(ctx, CL_MEM_READ_WRITE, bytes);
}

std::size_t ClusterUniquer::scratchBytes() const {
  return pixel_capacity_ * 4 * 7 + page_capacity_ * 4 * 3 + slot_capacity_ * 4 * 2 + bounds_capacity_ * 4 +
         tile_offsets_capacity_ * 4;
}

void ClusterUniquer::keys(cl::CommandQueue& q, const cl::Buffer& depth, const gpu::CameraParams& cam,
                          const ClusterGrid& g, ClPassTimer* timer) {
  const std::size_t n = std::size_t(cam.width) * cam.height;
  if (g.width != cam.width || g.height != cam.height) throw std::logic_error("ClusterUniquer: grid/camera mismatch");
  ensurePixels(n);
  if (g.slice_bounds.size() > bounds_capacity_) {
    bounds_capacity_ = g.slice_bounds.size();
    bounds_ = cl::Buffer(rt_.context(), CL_MEM_READ_ONLY, bounds_capacity_ * 4);
  }
  q.enqueueWriteBuffer(bounds_, CL_FALSE, 0, g.slice_bounds.size() * 4, g.slice_bounds.data());
  setArgs(keys_k_, depth, cam, bounds_, cl_uint(g.slices), cl_uint(g.tile_size), cl_uint(g.x_bits), cl_uint(g.k_bits),
          keys_);
  q.enqueueNDRangeKernel(keys_k_, cl::NullRange, cl::NDRange(n), cl::NullRange, nullptr,
                         timer ? timer->next("cluster-keys") : nullptr);
}

void ClusterUniquer::setKeys(cl::CommandQueue& q, const std::vector<std::uint32_t>& keys, const ClusterGrid& g) {
  const std::size_t n = std::size_t(g.width) * g.height;
  if (keys.size() != n) throw std::logic_error("ClusterUniquer::setKeys: size mismatch");
  ensurePixels(n);
  q.enqueueWriteBuffer(keys_, CL_TRUE, 0, n * 4, keys.data());
}

std::uint32_t ClusterUniquer::unique(cl::CommandQueue& q, const ClusterGrid& g, ClPassTimer* timer,
                                     cl::Buffer* map_out) {
  const std::size_t n = std::size_t(g.width) * g.height;
  cl::Buffer& map = map_out ? *map_out : cluster_of_;
  switch (method_) {
    case UniqueMethod::PageTable: return uniquePageTable(q, g, n, timer, map);
    case UniqueMethod::Sort: return uniqueSorted(q, g, n, false, timer, map);
    case UniqueMethod::TileSort: return uniqueSorted(q, g, n, true, timer, map);
  }
  return 0;
}

std::uint32_t ClusterUniquer::uniquePageTable(cl::CommandQueue& q, const ClusterGrid& g, std::size_t n,
                                              ClPassTimer* timer, cl::Buffer& map) {
  auto ev = [&](const char* name) { return timer ? timer->next(name) : nullptr; };
  // Pages grow with the key so the page table stays at most 2^20 entries.
  const unsigned pb = std::max(std::min(page_bits_, std::max(1u, g.keyBits())), g.keyBits() > 20 ? g.keyBits() - 20 : 0u);
  const std::size_t key_space = std::size_t(1) << std::max(g.keyBits(), pb);
  const std::size_t n_pages = key_space >> pb;
  if (n_pages > page_capacity_) {
    page_capacity_ = n_pages;
    const auto& ctx = rt_.context();
    marks_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, n_pages * 4);
    page_table_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, n_pages * 4);
    phys_to_virt_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, n_pages * 4);
  }
  q.enqueueFillBuffer(marks_, cl_uint(0), 0, n_pages * 4);
  setArgs(mark_, keys_, cl_uint(n), cl_uint(pb), marks_);
  q.enqueueNDRangeKernel(mark_, cl::NullRange, cl::NDRange(n), cl::NullRange, nullptr, ev("cluster-page-mark"));
  const std::uint32_t used_pages = scan_.exclusiveTotal(q, marks_, page_table_, n_pages, timer);
  if (used_pages == 0) {
    q.enqueueFillBuffer(map, kClusterInvalid, 0, n * 4);
    return 0;
  }
  // Physical memory is only the used pages: that is the point of the table.
  const std::size_t n_slots = std::size_t(used_pages) << pb;
  if (n_slots > slot_capacity_) {
    slot_capacity_ = n_slots;
    slots_ = cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, n_slots * 4);
    used_slots_ = cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, n_slots * 4);
  }
  q.enqueueFillBuffer(slots_, cl_uint(0), 0, n_slots * 4);
  setArgs(store_, keys_, cl_uint(n), cl_uint(pb), page_table_, slots_);
  q.enqueueNDRangeKernel(store_, cl::NullRange, cl::NDRange(n), cl::NullRange, nullptr, ev("cluster-page-store"));
  setArgs(inverse_, marks_, page_table_, cl_uint(n_pages), phys_to_virt_);
  q.enqueueNDRangeKernel(inverse_, cl::NullRange, cl::NDRange(n_pages), cl::NullRange, nullptr,
                         ev("cluster-page-inverse"));
  const auto count = std::uint32_t(compact_.compactIndices(q, slots_, used_slots_, n_slots, timer));
  if (count > 0) {
    setArgs(page_unique_, used_slots_, cl_uint(count), cl_uint(pb), phys_to_virt_, unique_keys_, slots_);
    q.enqueueNDRangeKernel(page_unique_, cl::NullRange, cl::NDRange(count), cl::NullRange, nullptr,
                           ev("cluster-page-unique"));
  }
  setArgs(page_map_, keys_, cl_uint(n), cl_uint(pb), page_table_, slots_, map);
  q.enqueueNDRangeKernel(page_map_, cl::NullRange, cl::NDRange(n), cl::NullRange, nullptr, ev("cluster-page-map"));
  return count;
}

std::uint32_t ClusterUniquer::uniqueSorted(cl::CommandQueue& q, const ClusterGrid& g, std::size_t n, bool per_tile,
                                           ClPassTimer* timer, cl::Buffer& map) {
  auto ev = [&](const char* name) { return timer ? timer->next(name) : nullptr; };
  if (per_tile) {
    const std::size_t n_tiles = std::size_t(g.tiles_x) * g.tiles_y;
    if (n_tiles + 1 > tile_offsets_capacity_) {
      tile_offsets_capacity_ = n_tiles + 1;
      tile_offsets_ = cl::Buffer(rt_.context(), CL_MEM_READ_ONLY, tile_offsets_capacity_ * 4);
      offsets_for_w_ = 0;
    }
    if (offsets_for_w_ != g.width || offsets_for_h_ != g.height || offsets_for_tile_ != g.tile_size) {
      const auto off = g.tileOffsets();
      q.enqueueWriteBuffer(tile_offsets_, CL_TRUE, 0, off.size() * 4, off.data());
      offsets_for_w_ = g.width;
      offsets_for_h_ = g.height;
      offsets_for_tile_ = g.tile_size;
    }
    setArgs(gather_, keys_, cl_uint(g.width), cl_uint(g.height), cl_uint(g.tile_size), cl_uint(g.tiles_x),
            tile_offsets_, sort_keys_, sort_vals_);
    q.enqueueNDRangeKernel(gather_, cl::NullRange, cl::NDRange(n), cl::NullRange, nullptr, ev("cluster-tile-gather"));
    // A tile holds at most tile_size^2 pixels: the GPU sort runs only the stages that takes.
    segsort_.sort(q, sort_keys_, &sort_vals_, n, tile_offsets_, n_tiles, timer,
                  std::size_t(g.tile_size) * g.tile_size);
  } else {
    setArgs(sort_init_, keys_, cl_uint(n), sort_keys_, sort_vals_);
    q.enqueueNDRangeKernel(sort_init_, cl::NullRange, cl::NDRange(n), cl::NullRange, nullptr, ev("cluster-sort-init"));
    // One bit above the key so that sky (all ones) sorts after every cluster.
    radix_.sort(q, sort_keys_, &sort_vals_, n, std::min(32u, g.keyBits() + 1), timer);
  }
  setArgs(heads_, sort_keys_, cl_uint(n), flags_);
  q.enqueueNDRangeKernel(heads_, cl::NullRange, cl::NDRange(n), cl::NullRange, nullptr, ev("cluster-heads"));
  const std::uint32_t count = scan_.exclusiveTotal(q, flags_, rank_, n, timer);
  setArgs(scatter_, sort_keys_, sort_vals_, cl_uint(n), flags_, rank_, unique_keys_, map);
  q.enqueueNDRangeKernel(scatter_, cl::NullRange, cl::NDRange(n), cl::NullRange, nullptr, ev("cluster-scatter"));
  return count;
}

}  // namespace ml
