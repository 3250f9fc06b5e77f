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

ClusterUniquer::ClusterUniquer(ClRuntime& rt, UniqueMethod method, unsigned page_bits, KernelShape shape,
                               std::size_t max_group)
    : rt_(rt),
      method_(method),
      shape_(resolveKernelShape(rt.info(), shape)),
      page_bits_(page_bits),
      scan_(rt, compute::Options{shape_, max_group}),
      compact_(rt, compute::Options{shape_, max_group}),
      radix_(rt, compute::Options{shape_, max_group}),
      segsort_(rt, compute::Options{shape_, max_group}) {
  if (page_bits < 1 || page_bits > 16) throw std::invalid_argument("ClusterUniquer: page_bits must be 1..16");
  // Every kernel of cluster_keys.cl is one work-item per pixel, page, slot or
  // sorted element, reading and writing consecutive elements: that suits a GPU
  // as it is and PoCL vectorizes it across work-items, so one shape serves both;
  // the shape reaches the primitives (scan, compaction, sorts).
  program_ = rt.programs().build("clustered/cluster_keys.cl");
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
  local_ = 1024;
  for (const cl::Kernel* k : {&keys_k_, &mark_, &store_, &inverse_, &page_unique_, &page_map_, &sort_init_, &gather_,
                              &heads_, &scatter_})
    local_ = std::min(local_, elementLocalSize(*k, rt.device(), rt.info(), max_group));
}

void ClusterUniquer::ensurePixels(std::size_t n) {
  if (n <= pixel_capacity_) return;
  pixel_capacity_ = n;
  const std::size_t bytes = std::max<std::size_t>(16, n * 4);
  for (cl::Buffer* b : {&keys_, &unique_keys_, &cluster_of_, &sort_keys_, &sort_vals_, &flags_, &rank_})
    *b = checkedBuffer(rt_, CL_MEM_READ_WRITE, bytes, "clustered shading per-pixel buffers");
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
    bounds_ = checkedBuffer(rt_, CL_MEM_READ_ONLY, bounds_capacity_ * 4, "clustered shading unique clusters");
  }
  q.enqueueWriteBuffer(bounds_, CL_FALSE, 0, g.slice_bounds.size() * 4, g.slice_bounds.data());
  setArgs(keys_k_, depth, cam, bounds_, cl_uint(g.slices), cl_uint(g.tile_size), cl_uint(g.x_bits), cl_uint(g.k_bits),
          keys_);
  launch1d(q, keys_k_, n, local_, timer ? timer->next("cluster-keys") : nullptr);
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
    marks_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, n_pages * 4, "clustered shading unique clusters");
    page_table_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, n_pages * 4, "clustered shading unique clusters");
    phys_to_virt_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, n_pages * 4, "clustered shading unique clusters");
  }
  q.enqueueFillBuffer(marks_, cl_uint(0), 0, n_pages * 4);
  setArgs(mark_, keys_, cl_uint(n), cl_uint(pb), marks_);
  launch1d(q, mark_, n, local_, ev("cluster-page-mark"));
  const std::uint32_t used_pages = scan_.exclusiveTotal(q, marks_, page_table_, n_pages, timer);
  if (used_pages == 0) {
    q.enqueueFillBuffer(map, kClusterInvalid, 0, n * 4);
    return 0;
  }
  // Physical memory is only the used pages: that is the point of the table.
  const std::size_t n_slots = std::size_t(used_pages) << pb;
  if (n_slots > slot_capacity_) {
    slot_capacity_ = n_slots;
    slots_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, n_slots * 4, "clustered shading unique clusters");
    used_slots_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, n_slots * 4, "clustered shading unique clusters");
  }
  q.enqueueFillBuffer(slots_, cl_uint(0), 0, n_slots * 4);
  setArgs(store_, keys_, cl_uint(n), cl_uint(pb), page_table_, slots_);
  launch1d(q, store_, n, local_, ev("cluster-page-store"));
  setArgs(inverse_, marks_, page_table_, cl_uint(n_pages), phys_to_virt_);
  launch1d(q, inverse_, n_pages, local_, ev("cluster-page-inverse"));
  const auto count = std::uint32_t(compact_.compactIndices(q, slots_, used_slots_, n_slots, timer));
  if (count > 0) {
    setArgs(page_unique_, used_slots_, cl_uint(count), cl_uint(pb), phys_to_virt_, unique_keys_, slots_);
    launch1d(q, page_unique_, count, local_, ev("cluster-page-unique"));
  }
  setArgs(page_map_, keys_, cl_uint(n), cl_uint(pb), page_table_, slots_, map);
  launch1d(q, page_map_, n, local_, ev("cluster-page-map"));
  return count;
}

std::uint32_t ClusterUniquer::uniqueSorted(cl::CommandQueue& q, const ClusterGrid& g, std::size_t n, bool per_tile,
                                           ClPassTimer* timer, cl::Buffer& map) {
  auto ev = [&](const char* name) { return timer ? timer->next(name) : nullptr; };
  if (per_tile) {
    const std::size_t n_tiles = std::size_t(g.tiles_x) * g.tiles_y;
    if (n_tiles + 1 > tile_offsets_capacity_) {
      tile_offsets_capacity_ = n_tiles + 1;
      tile_offsets_ =
          checkedBuffer(rt_, CL_MEM_READ_ONLY, tile_offsets_capacity_ * 4, "clustered shading tile offsets");
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
    launch1d(q, gather_, n, local_, ev("cluster-tile-gather"));
    // A tile holds at most tile_size^2 pixels: the GPU sort runs only the stages that takes.
    segsort_.sort(q, sort_keys_, &sort_vals_, n, tile_offsets_, n_tiles, timer,
                  std::size_t(g.tile_size) * g.tile_size);
  } else {
    setArgs(sort_init_, keys_, cl_uint(n), sort_keys_, sort_vals_);
    launch1d(q, sort_init_, n, local_, ev("cluster-sort-init"));
    // One bit above the key so that sky (all ones) sorts after every cluster.
    radix_.sort(q, sort_keys_, &sort_vals_, n, std::min(32u, g.keyBits() + 1), timer);
  }
  setArgs(heads_, sort_keys_, cl_uint(n), flags_);
  launch1d(q, heads_, n, local_, ev("cluster-heads"));
  const std::uint32_t count = scan_.exclusiveTotal(q, flags_, rank_, n, timer);
  setArgs(scatter_, sort_keys_, sort_vals_, cl_uint(n), flags_, rank_, unique_keys_, map);
  launch1d(q, scatter_, n, local_, ev("cluster-scatter"));
  return count;
}

}  // namespace ml
