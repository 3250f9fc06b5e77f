#include "host/clustered/ClusterLightAssigner.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

#include "host/cl/KernelArgs.hpp"
#include "host/cl/ProgramBuilder.hpp"
#include "host/util/Error.hpp"

namespace ml {

ClusterAssignMethod parseClusterAssign(const std::string& s) {
  if (s == "bvh") return ClusterAssignMethod::Bvh;
  if (s == "brute") return ClusterAssignMethod::Brute;
  throw UserError("--cluster-assign: expected bvh or brute, got '" + s + "'");
}

const char* clusterAssignName(ClusterAssignMethod m) { return m == ClusterAssignMethod::Bvh ? "bvh" : "brute"; }

ClusterBounds parseClusterBounds(const std::string& s) {
  if (s == "pixels") return ClusterBounds::Pixels;
  if (s == "frustum") return ClusterBounds::Frustum;
  throw UserError("--cluster-bounds: expected pixels or frustum, got '" + s + "'");
}

const char* clusterBoundsName(ClusterBounds b) { return b == ClusterBounds::Pixels ? "pixels" : "frustum"; }

namespace {
constexpr std::uint32_t kBranch = 32;  // BVH_BRANCH in the kernel (inner nodes)
constexpr unsigned kMaxLevels = 7;     // BVH_STACK (256) >= 32 * levels + 32
// Hit-leaf records of all clusters together (8 bytes each): clusters with more
// hit leaves than their share are walked again by the fill pass.
constexpr std::size_t kDefaultRecordBudget = std::size_t(1) << 22;
constexpr float kInf = std::numeric_limits<float>::infinity();
constexpr std::uint32_t kMortonChunk = 1024;  // MORTON_CHUNK in the kernel
constexpr std::size_t kNodeFloats = 10;       // NODE_FLOATS in the kernel
// Morton quantization per axis: 3 x 8 bits sort in 3 radix passes (8-bit
// digits on CPUs) where 3 x 10 take 4; see light_morton.
constexpr unsigned kMortonAxisBits = 8;
constexpr std::size_t kGroupMax = 256;  // PIX_WG and RED_WG in the kernel
// The GPU shape's pixel boxes are ordered ints until cluster_boxes_finish.
constexpr cl_int kOrderedInf = 0x7f800000, kOrderedNegInf = cl_int(0x807fffffu);
}  // namespace

static unsigned checkedLeafSize(unsigned requested) {
  if (requested != 8 && requested != 16 && requested != 32)
    throw UserError("cluster BVH leaf size: expected 8, 16 or 32 lights, got " + std::to_string(requested));
  return requested;
}

static std::size_t checkedMaxGroup(std::size_t max_group) {
  if (max_group && max_group < kBranch)
    throw UserError("cluster assignment: groups of at least " + std::to_string(kBranch) + " work-items needed, " +
                    std::to_string(max_group) + " given");
  return max_group;
}

ClusterLightAssigner::ClusterLightAssigner(ClRuntime& rt, ClusterAssignMethod method, unsigned leaf_size,
                                           KernelShape shape, std::size_t max_group)
    : rt_(rt),
      method_(method),
      leaf_size_(checkedLeafSize(leaf_size)),
      shape_(resolveKernelShape(rt.info(), shape)),
      gpu_(shape_ == KernelShape::GpuWorkGroup),
      max_group_(checkedMaxGroup(max_group)),
      record_budget_(kDefaultRecordBudget),
      scan_(rt, compute::Options{shape_, max_group}),
      radix_(rt, compute::Options{shape_, max_group}),
      compact_(rt, compute::Options{shape_, max_group}) {
  const std::string leaf = std::to_string(leaf_size_) + "u";
  bounds_program_ = rt.programs().build("clustered/cluster_bounds.cl");
  bvh_program_ = rt.programs().build("clustered/light_bvh.cl",
                                     {{"LEAF_SIZE", leaf}, {"MORTON_AXIS_BITS", std::to_string(kMortonAxisBits) + "u"}});
  lists_program_ = rt.programs().build("clustered/cluster_assign.cl", {{"LEAF_SIZE", leaf}});
  // Kernels that serve both shapes (a work-item per light or cluster);
  // write_grid (common/light_grid.cl) turns (offsets, counts) into LightRanges.
  view_ = cl::Kernel(bounds_program_, "light_view");
  boxes_ = cl::Kernel(bounds_program_, "cluster_boxes");
  finish_ = cl::Kernel(bounds_program_, "cluster_boxes_finish");
  morton_ = cl::Kernel(bvh_program_, "light_morton");
  union_part_ = cl::Kernel(bvh_program_, "cluster_union_partial");
  union_final_ = cl::Kernel(bvh_program_, "cluster_union_final");
  reaches_k_ = cl::Kernel(bvh_program_, "light_reaches_union");
  gather_k_ = cl::Kernel(bvh_program_, "gather_spheres");
  remap_k_ = cl::Kernel(bvh_program_, "remap_leaf_ids");
  order_k_ = cl::Kernel(lists_program_, "cluster_order");
  ranges_ = cl::Kernel(lists_program_, "write_grid");
  // One kernel of each pass per shape.
  auto shaped = [&](const cl::Program& p, const std::string& name) {
    return cl::Kernel(p, (gpu_ ? name + "_wg" : name).c_str());
  };
  pixel_boxes_ = shaped(bounds_program_, "cluster_pixel_boxes");
  pack_ = shaped(bvh_program_, "pack_leaves");
  level_ = shaped(bvh_program_, "bvh_level");
  blocks_ = shaped(bvh_program_, "node_blocks");
  bounds_part_ = shaped(bvh_program_, "light_bounds_partial");
  bounds_final_ = shaped(bvh_program_, "light_bounds_final");
  count_k_ = shaped(lists_program_, "assign_count");
  fill_k_ = shaped(lists_program_, "assign_fill");
  fitLocalSizes();
  block_start_ = checkedBuffer(rt, CL_MEM_READ_ONLY, kMaxLevels * 4, "cluster BVH");
  frame_ = checkedBuffer(rt, CL_MEM_READ_WRITE, 16, "cluster BVH");
  box_union_ = checkedBuffer(rt, CL_MEM_READ_WRITE, 32, "cluster BVH");
  for (cl::Buffer* b :
       {&spheres_, &codes_, &ids_, &soa_, &leaf_ids_, &node_lo_, &node_hi_, &node_sph_, &node_soa_, &rec_leaf_,
        &rec_mask_, &order_codes_, &order_ids_, &reaching_, &reaching_spheres_})
    *b = checkedBuffer(rt, CL_MEM_READ_WRITE, 16, "cluster BVH");
}

void ClusterLightAssigner::fitLocalSizes() {
  const cl::Device& dev = rt_.device();
  const DeviceInfo& info = rt_.info();
  local_ = 1024;
  for (const cl::Kernel* k : {&view_, &boxes_, &morton_, &order_k_, &finish_, &ranges_, &blocks_, &union_part_,
                              &reaches_k_, &gather_k_, &remap_k_})
    local_ = std::min(local_, elementLocalSize(*k, dev, info, max_group_));
  if (!gpu_) {
    // CPU shape: every pass is a work-item per element (tile, chunk, leaf, node, cluster).
    for (const cl::Kernel* k : {&pixel_boxes_, &pack_, &level_, &bounds_part_, &bounds_final_, &count_k_, &fill_k_})
      local_ = std::min(local_, elementLocalSize(*k, dev, info, max_group_));
    pixel_local_ = red_local_ = leaf_local_ = node_local_ = walk_local_ = local_;
    return;
  }
  // Group sizes the GPU kernels are written for (their __local arrays):
  // up to PIX_WG and RED_WG, exactly LEAF_SIZE and BVH_BRANCH items.
  const std::size_t most = max_group_ ? std::min(kGroupMax, max_group_) : kGroupMax;
  pixel_local_ = fitLocalSize(pixel_boxes_, dev, most, 1, 0, "cluster_pixel_boxes_wg");
  red_local_ = std::min(fitLocalSize(bounds_part_, dev, most, 1, 0, "light_bounds_partial_wg"),
                        fitLocalSize(bounds_final_, dev, most, 1, 0, "light_bounds_final_wg"));
  leaf_local_ = fitLocalSize(pack_, dev, leaf_size_, leaf_size_, 0, "pack_leaves_wg");
  node_local_ = fitLocalSize(level_, dev, kBranch, kBranch, 0, "bvh_level_wg");
  walk_local_ = std::min(fitLocalSize(count_k_, dev, kBranch, kBranch, 0, "assign_count_wg"),
                         fitLocalSize(fill_k_, dev, kBranch, kBranch, 0, "assign_fill_wg"));
}

std::size_t ClusterLightAssigner::scratchBytes() const {
  return light_capacity_ * (16 + 4 + 4 + 16 + 4) + leaf_capacity_ * leaf_size_ * (16 + 4) + node_capacity_ * 48 +
         block_capacity_ * kBranch * kNodeFloats * 4 +
         cluster_capacity_ * (32 + 12) + bounds_capacity_ * 4 + record_capacity_ * 8;
}

// The arguments assign_count and assign_fill share (the tree, the boxes), then `rest`.
template <typename... Rest>
void ClusterLightAssigner::setAssignArgs(cl::Kernel& k, const Rest&... rest) {
  setArgs(k, soa_, n_leaves_, node_soa_, block_start_, cl_uint(levels_), cl_uint(bvh_ && levels_ > 0), box_lo_, box_hi_,
          clusters_, rest...);
}

std::uint32_t ClusterLightAssigner::count(cl::CommandQueue& q, const cl::Buffer& lights, std::uint32_t n,
                                          const gpu::CameraParams& cam, const ClusterGrid& g,
                                          const cl::Buffer& unique_keys, std::uint32_t clusters,
                                          ClPassTimer* timer, const ClusterPixels* pixels) {
  boxes(q, cam, g, unique_keys, clusters, timer, pixels);
  return assign(q, lights, n, cam, timer);
}

void ClusterLightAssigner::boxes(cl::CommandQueue& q, const gpu::CameraParams& cam, const ClusterGrid& g,
                                 const cl::Buffer& unique_keys, std::uint32_t clusters, ClPassTimer* timer,
                                 const ClusterPixels* pixels) {
  auto ev = [&](const char* name) { return timer ? timer->next(name) : nullptr; };
  clusters_ = clusters;
  if (clusters + 1 > cluster_capacity_) {
    cluster_capacity_ = std::size_t(clusters) + clusters / 2 + 1;
    for (cl::Buffer* b : {&box_lo_, &box_hi_})
      *b = checkedBuffer(rt_, CL_MEM_READ_WRITE, cluster_capacity_ * 16, "cluster boxes");
    for (cl::Buffer* b : {&counts_, &offsets_, &hit_leaves_})
      *b = checkedBuffer(rt_, CL_MEM_READ_WRITE, cluster_capacity_ * 4, "cluster light counts");
  }
  if (g.slice_bounds.size() > bounds_capacity_) {
    bounds_capacity_ = g.slice_bounds.size();
    bounds_ = checkedBuffer(rt_, CL_MEM_READ_ONLY, bounds_capacity_ * 4, "cluster slice bounds");
  }
  q.enqueueWriteBuffer(bounds_, CL_FALSE, 0, g.slice_bounds.size() * 4, g.slice_bounds.data());
  if (clusters == 0) return;
  order_keys_ = unique_keys;
  order_grid_ = g;
  if (pixels) {
    const cl_uint n_tiles = g.tiles_x * g.tiles_y;
    const std::size_t bytes = std::size_t(clusters) * 16;
    if (gpu_) {
      // A work-group per tile reduces ordered ints; the finish pass widens them into floats.
      q.enqueueFillBuffer(box_lo_, cl_int4{{kOrderedInf, kOrderedInf, kOrderedInf, 0}}, 0, bytes);
      q.enqueueFillBuffer(box_hi_, cl_int4{{kOrderedNegInf, kOrderedNegInf, kOrderedNegInf, 0}}, 0, bytes);
      setArgs(pixel_boxes_, pixels->depth, pixels->cluster_of, cam, cl_uint(g.tile_size), cl_uint(g.tiles_x), box_lo_,
              box_hi_);
      launch1d(q, pixel_boxes_, std::size_t(n_tiles) * pixel_local_, pixel_local_, ev("cluster-boxes"));
      setArgs(finish_, box_lo_, box_hi_, clusters, cam);
      launch1d(q, finish_, clusters, local_, ev("cluster-boxes"));
    } else {
      q.enqueueFillBuffer(box_lo_, cl_float4{{kInf, kInf, kInf, kInf}}, 0, bytes);
      q.enqueueFillBuffer(box_hi_, cl_float4{{-kInf, -kInf, -kInf, -kInf}}, 0, bytes);
      setArgs(pixel_boxes_, pixels->depth, pixels->cluster_of, cam, cl_uint(g.tile_size), cl_uint(g.tiles_x), n_tiles,
              box_lo_, box_hi_);
      launch1d(q, pixel_boxes_, n_tiles, pixel_local_, ev("cluster-boxes"));
    }
  } else {
    setArgs(boxes_, unique_keys, cl_uint(clusters), cam, bounds_, cl_uint(g.tile_size), cl_uint(g.x_bits),
            cl_uint(g.k_bits), box_lo_, box_hi_);
    launch1d(q, boxes_, clusters, local_, ev("cluster-boxes"));
  }
}

std::uint32_t ClusterLightAssigner::assign(cl::CommandQueue& q, const cl::Buffer& lights, std::uint32_t n,
                                           const gpu::CameraParams& cam, ClPassTimer* timer) {
  auto ev = [&](const char* name) { return timer ? timer->next(name) : nullptr; };
  const std::uint32_t clusters = clusters_;
  n_ = n;
  tree_lights_ = n;
  bvh_ = method_ == ClusterAssignMethod::Bvh;
  n_leaves_ = 0;
  levels_ = 0;
  if (clusters == 0) return 0;
  if (n > light_capacity_) {
    light_capacity_ = std::size_t(n) + n / 2;
    spheres_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, light_capacity_ * 16, "clustered light assignment");
    codes_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, light_capacity_ * 4, "clustered light assignment");
    ids_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, light_capacity_ * 4, "clustered light assignment");
    reaching_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, light_capacity_ * 4, "clustered light assignment");
    reaching_spheres_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, light_capacity_ * 16, "clustered light assignment");
  }
  n_leaves_ = (n + leaf_size_ - 1) / leaf_size_;
  if (n > 0) {
    setArgs(view_, lights, n, cam, spheres_);
    launch1d(q, view_, n, local_, ev("cluster-light-view"));
    if (bvh_) buildBvh(q, keepReachingLights(q, n, timer), timer);
    else packLeaves(q, spheres_, n, false, timer);
  }
  orderClusters(q, clusters, timer);
  // Record slots per cluster: an equal share of the budget, at most every leaf.
  slots_ = std::uint32_t(std::min<std::size_t>(n_leaves_, std::max<std::size_t>(1, record_budget_ / clusters)));
  if (std::size_t(clusters) * slots_ > record_capacity_) {
    record_capacity_ = std::size_t(clusters) * slots_;
    rec_leaf_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, record_capacity_ * 4, "clustered light assignment");
    rec_mask_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, record_capacity_ * 4, "clustered light assignment");
  }
  setAssignArgs(count_k_, rec_leaf_, rec_mask_, slots_, hit_leaves_, counts_, order_ids_, cl_uint(use_order_));
  launchShaped(q, count_k_, clusters, walk_local_, ev("cluster-assign-count"));
  const std::uint32_t records = scan_.exclusiveTotal(q, hit_leaves_, offsets_, clusters, timer);
  // The scan wraps mod 2^32; where clusters x leaves could pass that, the
  // records are summed again in 64 bits, and too many are an error, not a wrap.
  if (std::uint64_t(clusters) * n_leaves_ > 0xffffffffull) {
    const std::uint64_t total = sumOver(q, hit_leaves_);
    if (total > 0xffffffffull)
      throw UserError("clustered shading: the cluster light lists need " + std::to_string(total) +
                      " records, more than 32-bit offsets reach (fewer --lights or a smaller --size)");
  }
  return records;
}

// Bvh: the lights that reach the box around the cluster boxes, compacted
// (reaching_: their indices, reaching_spheres_: their spheres); returns their count.
std::uint32_t ClusterLightAssigner::keepReachingLights(cl::CommandQueue& q, std::uint32_t n, ClPassTimer* timer) {
  auto ev = [&](const char* name) { return timer ? timer->next(name) : nullptr; };
  const std::uint32_t parts = (std::max(n, clusters_) + kMortonChunk - 1) / kMortonChunk;
  if (parts > part_capacity_) {
    part_capacity_ = std::size_t(parts) + parts / 2;
    part_lo_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, part_capacity_ * 16, "clustered light assignment");
    part_hi_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, part_capacity_ * 16, "clustered light assignment");
  }
  const std::uint32_t cluster_parts = (clusters_ + kMortonChunk - 1) / kMortonChunk;
  setArgs(union_part_, box_lo_, box_hi_, clusters_, part_lo_, part_hi_);
  launch1d(q, union_part_, cluster_parts, local_, ev("cluster-union"));
  setArgs(union_final_, part_lo_, part_hi_, cluster_parts, box_union_);
  launch1d(q, union_final_, 1, 1, ev("cluster-union"));
  setArgs(reaches_k_, spheres_, n, box_union_, codes_);  // codes_ as the flags, before the Morton pass
  launch1d(q, reaches_k_, n, local_, ev("cluster-light-reach"));
  const auto m = std::uint32_t(compact_.compactIndices(q, codes_, reaching_, n, timer));
  if (m > 0) {
    setArgs(gather_k_, spheres_, reaching_, m, reaching_spheres_);
    launch1d(q, gather_k_, m, local_, ev("cluster-light-reach"));
  }
  return m;
}

// Bvh over the m reaching lights: Morton frame (their bounding cube, on the
// device), codes, sort, leaves and levels; leaf slots then name light indices.
void ClusterLightAssigner::buildBvh(cl::CommandQueue& q, std::uint32_t m, ClPassTimer* timer) {
  auto ev = [&](const char* name) { return timer ? timer->next(name) : nullptr; };
  tree_lights_ = m;
  n_leaves_ = (m + leaf_size_ - 1) / leaf_size_;
  if (m == 0) return;
  const std::uint32_t parts = (m + kMortonChunk - 1) / kMortonChunk;
  setArgs(bounds_part_, reaching_spheres_, m, part_lo_, part_hi_);
  launchShaped(q, bounds_part_, parts, red_local_, ev("cluster-light-bounds"));
  setArgs(bounds_final_, part_lo_, part_hi_, parts, frame_);
  launchShaped(q, bounds_final_, 1, red_local_, ev("cluster-light-bounds"));
  setArgs(morton_, reaching_spheres_, m, frame_, codes_, ids_);
  launch1d(q, morton_, m, local_, ev("cluster-morton"));
  radix_.sort(q, codes_, &ids_, m, 3 * kMortonAxisBits, timer);
  packLeaves(q, reaching_spheres_, m, true, timer);
  const auto slots = cl_uint(leafLightSlots());
  setArgs(remap_k_, leaf_ids_, slots, reaching_);
  launch1d(q, remap_k_, slots, local_, ev("cluster-bvh-leaves"));
}

// GPU shape: a work-group of `group` items per element; CPU: a work-item per element.
void ClusterLightAssigner::launchShaped(cl::CommandQueue& q, const cl::Kernel& k, std::size_t elements,
                                        std::size_t group, cl::Event* event) const {
  if (gpu_) launch1d(q, k, elements * group, group, event);
  else launch1d(q, k, elements, local_, event);
}

void ClusterLightAssigner::packLeaves(cl::CommandQueue& q, const cl::Buffer& spheres, std::uint32_t n, bool bvh,
                                      ClPassTimer* timer) {
  auto ev = [&](const char* name) { return timer ? timer->next(name) : nullptr; };
  const std::uint32_t n_leaves = (n + leaf_size_ - 1) / leaf_size_;
  if (n_leaves > leaf_capacity_) {
    leaf_capacity_ = std::size_t(n_leaves) + n_leaves / 2;
    soa_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, leaf_capacity_ * leaf_size_ * 16, "cluster BVH leaves");
    leaf_ids_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, leaf_capacity_ * leaf_size_ * 4, "cluster BVH leaves");
  }
  std::vector<cl_uint> start, count, block_start;
  std::uint32_t total = 0, blocks = 0;
  if (bvh) {
    std::uint32_t c = n_leaves;
    for (;;) {
      start.push_back(total);
      count.push_back(c);
      block_start.push_back(blocks);
      total += c;
      blocks += (c + kBranch - 1) / kBranch;
      if (c <= kBranch) break;
      c = (c + kBranch - 1) / kBranch;
    }
    levels_ = unsigned(start.size());
    if (levels_ > kMaxLevels) throw UserError("clustered: too many lights for the BVH stack");
    if (total > node_capacity_) {
      node_capacity_ = std::size_t(total) + total / 2;
      node_lo_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, node_capacity_ * 16, "clustered light assignment");
      node_hi_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, node_capacity_ * 16, "clustered light assignment");
      node_sph_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, node_capacity_ * 16, "clustered light assignment");
    }
    if (blocks > block_capacity_) {
      block_capacity_ = std::size_t(blocks) + blocks / 2;
      node_soa_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, block_capacity_ * kBranch * kNodeFloats * 4, "cluster BVH");
    }
    q.enqueueWriteBuffer(block_start_, CL_TRUE, 0, levels_ * 4, block_start.data());
  }
  setArgs(pack_, spheres, ids_, cl_uint(bvh), n, soa_, leaf_ids_, node_lo_, node_hi_, node_sph_, cl_uint(bvh));
  launchShaped(q, pack_, n_leaves, leaf_local_, ev(bvh ? "cluster-bvh-leaves" : "cluster-pack-leaves"));
  for (unsigned l = 1; l < levels_; ++l) {
    setArgs(level_, node_lo_, node_hi_, node_sph_, start[l - 1], count[l - 1], start[l]);
    launchShaped(q, level_, count[l], node_local_, ev("cluster-bvh-level"));
  }
  for (unsigned l = 0; l < levels_; ++l) {
    const std::uint32_t n_blocks = (count[l] + kBranch - 1) / kBranch;
    setArgs(blocks_, node_lo_, node_hi_, node_sph_, start[l], count[l], block_start[l], node_soa_);
    launch1d(q, blocks_, gpu_ ? std::size_t(n_blocks) * kBranch : n_blocks, local_, ev("cluster-bvh-blocks"));
  }
}

void ClusterLightAssigner::orderClusters(cl::CommandQueue& q, std::uint32_t clusters, ClPassTimer* timer) {
  const ClusterGrid& g = order_grid_;
  const unsigned tile_bits = 2 * std::max(g.x_bits, g.y_bits);
  use_order_ = bvh_ && cluster_order_ && tile_bits + g.k_bits <= 32;
  if (!use_order_) return;
  if (clusters > order_capacity_) {
    order_capacity_ = std::size_t(clusters) + clusters / 2;
    order_codes_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, order_capacity_ * 4, "clustered light assignment");
    order_ids_ = checkedBuffer(rt_, CL_MEM_READ_WRITE, order_capacity_ * 4, "clustered light assignment");
  }
  setArgs(order_k_, order_keys_, clusters, cl_uint(g.x_bits), cl_uint(g.k_bits), order_codes_, order_ids_);
  launch1d(q, order_k_, clusters, local_, timer ? timer->next("cluster-order") : nullptr);
  radix_.sort(q, order_codes_, &order_ids_, clusters, tile_bits + g.k_bits, timer);
}

std::uint64_t ClusterLightAssigner::sumOver(cl::CommandQueue& q, const cl::Buffer& per_cluster) const {
  if (clusters_ == 0) return 0;
  std::vector<std::uint32_t> h(clusters_);
  q.enqueueReadBuffer(per_cluster, CL_TRUE, 0, h.size() * 4, h.data());
  std::uint64_t s = 0;
  for (auto v : h) s += v;
  return s;
}

void ClusterLightAssigner::fill(cl::CommandQueue& q, cl::Buffer& ranges, cl::Buffer& records, cl::Buffer& leaf_lights,
                                ClPassTimer* timer) {
  if (clusters_ == 0) return;
  setAssignArgs(fill_k_, rec_leaf_, rec_mask_, slots_, hit_leaves_, offsets_, records, order_ids_,
                cl_uint(use_order_));
  launchShaped(q, fill_k_, clusters_, walk_local_, timer ? timer->next("cluster-assign-fill") : nullptr);
  setArgs(ranges_, offsets_, hit_leaves_, clusters_, ranges);
  launch1d(q, ranges_, clusters_, local_, timer ? timer->next("cluster-ranges") : nullptr);
  if (leafLightSlots() > 0)
    q.enqueueCopyBuffer(leaf_ids_, leaf_lights, 0, 0, leafLightSlots() * 4, nullptr,
                        timer ? timer->next("cluster-leaf-lights") : nullptr);
}

}  // namespace ml
