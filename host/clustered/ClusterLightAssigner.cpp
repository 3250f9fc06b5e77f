#include "host/clustered/ClusterLightAssigner.hpp"

#include <algorithm>
#include <stdexcept>

#include "host/cl/ProgramBuilder.hpp"
#include "host/util/Error.hpp"

namespace ml {

ClusterAssignMethod parseClusterAssign(const std::string& s) {
  if (s == "bvh") return ClusterAssignMethod::Bvh;
  if (s == "brute") return ClusterAssignMethod::Brute;
  throw UserError("--cluster-assign: expected bvh or brute, got '" + s + "'");
}

const char* clusterAssignName(ClusterAssignMethod m) { return m == ClusterAssignMethod::Bvh ? "bvh" : "brute"; }

namespace {
constexpr std::uint32_t kBranch = 32;  // BVH_BRANCH in the kernel
constexpr unsigned kMaxLevels = 7;     // BVH_STACK (256) >= 32 * levels + 32
}  // namespace

ClusterLightAssigner::ClusterLightAssigner(ClRuntime& rt, ClusterAssignMethod method)
    : rt_(rt), method_(method), scan_(rt), radix_(rt) {
  program_ = rt.programs().build("cluster_assign.cl");
  view_ = cl::Kernel(program_, "light_view");
  boxes_ = cl::Kernel(program_, "cluster_boxes");
  brute_ = cl::Kernel(program_, "brute_assign");
  morton_ = cl::Kernel(program_, "light_morton");
  leaves_ = cl::Kernel(program_, "bvh_leaves");
  level_ = cl::Kernel(program_, "bvh_level");
  bvh_ = cl::Kernel(program_, "bvh_assign");
  // The tiled kernel's write_grid turns (offsets, counts) into LightRanges.
  keys_program_ = rt.programs().build("tiled_light_culling.cl", {{"TILE_SIZE", "16"}, {"DEPTH_MODE", "0"}});
  ranges_ = cl::Kernel(keys_program_, "write_grid");
  const auto& ctx = rt.context();
  level_start_ = cl::Buffer(ctx, CL_MEM_READ_ONLY, kMaxLevels * 4);
  level_count_ = cl::Buffer(ctx, CL_MEM_READ_ONLY, kMaxLevels * 4);
  for (cl::Buffer* b : {&spheres_, &codes_, &ids_, &sorted_, &sorted_ids_, &node_lo_, &node_hi_})
    *b = cl::Buffer(ctx, CL_MEM_READ_WRITE, 16);
}

std::size_t ClusterLightAssigner::scratchBytes() const {
  return light_capacity_ * (16 + 4 + 4 + 16 + 4) + node_capacity_ * 32 + cluster_capacity_ * (32 + 8) +
         bounds_capacity_ * 4;
}

std::uint32_t ClusterLightAssigner::count(cl::CommandQueue& q, const cl::Buffer& lights, std::uint32_t n,
                                          const gpu::CameraParams& cam, const ClusterGrid& g,
                                          const cl::Buffer& unique_keys, std::uint32_t clusters,
                                          ClPassTimer* timer) {
  auto ev = [&](const char* name) { return timer ? timer->next(name) : nullptr; };
  const auto& ctx = rt_.context();
  n_ = n;
  clusters_ = clusters;
  if (n > light_capacity_) {
    light_capacity_ = std::size_t(n) + n / 2;
    spheres_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, light_capacity_ * 16);
    codes_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, light_capacity_ * 4);
    ids_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, light_capacity_ * 4);
    sorted_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, light_capacity_ * 16);
    sorted_ids_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, light_capacity_ * 4);
  }
  if (clusters + 1 > cluster_capacity_) {
    cluster_capacity_ = std::size_t(clusters) + clusters / 2 + 1;
    box_lo_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, cluster_capacity_ * 16);
    box_hi_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, cluster_capacity_ * 16);
    counts_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, cluster_capacity_ * 4);
    offsets_ = cl::Buffer(ctx, CL_MEM_READ_WRITE, cluster_capacity_ * 4);
  }
  if (g.slice_bounds.size() > bounds_capacity_) {
    bounds_capacity_ = g.slice_bounds.size();
    bounds_ = cl::Buffer(ctx, CL_MEM_READ_ONLY, bounds_capacity_ * 4);
  }
  q.enqueueWriteBuffer(bounds_, CL_FALSE, 0, g.slice_bounds.size() * 4, g.slice_bounds.data());
  if (clusters == 0) return 0;
  boxes_.setArg(0, unique_keys);
  boxes_.setArg(1, cl_uint(clusters));
  boxes_.setArg(2, cam);
  boxes_.setArg(3, bounds_);
  boxes_.setArg(4, cl_uint(g.tile_size));
  boxes_.setArg(5, cl_uint(g.x_bits));
  boxes_.setArg(6, cl_uint(g.k_bits));
  boxes_.setArg(7, box_lo_);
  boxes_.setArg(8, box_hi_);
  q.enqueueNDRangeKernel(boxes_, cl::NullRange, cl::NDRange(clusters), cl::NullRange, nullptr, ev("cluster-boxes"));
  if (n > 0) {
    view_.setArg(0, lights);
    view_.setArg(1, n);
    view_.setArg(2, cam);
    view_.setArg(3, spheres_);
    q.enqueueNDRangeKernel(view_, cl::NullRange, cl::NDRange(n), cl::NullRange, nullptr, ev("cluster-light-view"));
    if (method_ == ClusterAssignMethod::Bvh) {
      // Morton cube: the view frustum's box.
      const float half_y = cam.far_plane * cam.tan_half_fovy, half_x = half_y * cam.aspect;
      const float extent = std::max({2.0f * half_x, 2.0f * half_y, cam.far_plane});
      morton_.setArg(0, spheres_);
      morton_.setArg(1, n);
      morton_.setArg(2, cl_float4{{-half_x, -half_y, -cam.far_plane, 0.0f}});
      morton_.setArg(3, 1.0f / extent);
      morton_.setArg(4, codes_);
      morton_.setArg(5, ids_);
      q.enqueueNDRangeKernel(morton_, cl::NullRange, cl::NDRange(n), cl::NullRange, nullptr, ev("cluster-morton"));
      radix_.sort(q, codes_, &ids_, n, 30, timer);
      buildBvh(q, n, timer);
    }
  }
  runAssign(q, false, nullptr, timer);
  return scan_.exclusiveTotal(q, counts_, offsets_, clusters, timer);
}

void ClusterLightAssigner::buildBvh(cl::CommandQueue& q, std::uint32_t n, ClPassTimer* timer) {
  auto ev = [&](const char* name) { return timer ? timer->next(name) : nullptr; };
  std::vector<cl_uint> start, count;
  std::uint32_t c = (n + kBranch - 1) / kBranch, total = 0;
  for (;;) {
    start.push_back(total);
    count.push_back(c);
    total += c;
    if (c <= kBranch) break;
    c = (c + kBranch - 1) / kBranch;
  }
  levels_ = unsigned(start.size());
  if (levels_ > kMaxLevels) throw UserError("clustered: too many lights for the BVH stack");
  if (total > node_capacity_) {
    node_capacity_ = std::size_t(total) + total / 2;
    node_lo_ = cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, node_capacity_ * 16);
    node_hi_ = cl::Buffer(rt_.context(), CL_MEM_READ_WRITE, node_capacity_ * 16);
  }
  q.enqueueWriteBuffer(level_start_, CL_FALSE, 0, levels_ * 4, start.data());
  q.enqueueWriteBuffer(level_count_, CL_TRUE, 0, levels_ * 4, count.data());
  leaves_.setArg(0, spheres_);
  leaves_.setArg(1, ids_);
  leaves_.setArg(2, n);
  leaves_.setArg(3, sorted_);
  leaves_.setArg(4, sorted_ids_);
  leaves_.setArg(5, node_lo_);
  leaves_.setArg(6, node_hi_);
  q.enqueueNDRangeKernel(leaves_, cl::NullRange, cl::NDRange(count[0]), cl::NullRange, nullptr, ev("cluster-bvh-leaves"));
  for (unsigned l = 1; l < levels_; ++l) {
    level_.setArg(0, node_lo_);
    level_.setArg(1, node_hi_);
    level_.setArg(2, start[l - 1]);
    level_.setArg(3, count[l - 1]);
    level_.setArg(4, start[l]);
    q.enqueueNDRangeKernel(level_, cl::NullRange, cl::NDRange(count[l]), cl::NullRange, nullptr, ev("cluster-bvh-level"));
  }
}

void ClusterLightAssigner::runAssign(cl::CommandQueue& q, bool fill, cl::Buffer* indices, ClPassTimer* timer) {
  const char* name = fill ? "cluster-assign-fill" : "cluster-assign-count";
  cl::Event* e = timer ? timer->next(name) : nullptr;
  cl::Buffer& out = indices ? *indices : counts_;
  if (n_ == 0 || method_ == ClusterAssignMethod::Brute) {
    brute_.setArg(0, spheres_);
    brute_.setArg(1, n_);
    brute_.setArg(2, box_lo_);
    brute_.setArg(3, box_hi_);
    brute_.setArg(4, clusters_);
    brute_.setArg(5, counts_);
    brute_.setArg(6, offsets_);
    brute_.setArg(7, out);
    brute_.setArg(8, cl_uint(fill));
    q.enqueueNDRangeKernel(brute_, cl::NullRange, cl::NDRange(clusters_), cl::NullRange, nullptr, e);
    return;
  }
  bvh_.setArg(0, sorted_);
  bvh_.setArg(1, sorted_ids_);
  bvh_.setArg(2, n_);
  bvh_.setArg(3, node_lo_);
  bvh_.setArg(4, node_hi_);
  bvh_.setArg(5, level_start_);
  bvh_.setArg(6, level_count_);
  bvh_.setArg(7, cl_uint(levels_));
  bvh_.setArg(8, box_lo_);
  bvh_.setArg(9, box_hi_);
  bvh_.setArg(10, clusters_);
  bvh_.setArg(11, counts_);
  bvh_.setArg(12, offsets_);
  bvh_.setArg(13, out);
  bvh_.setArg(14, cl_uint(fill));
  q.enqueueNDRangeKernel(bvh_, cl::NullRange, cl::NDRange(clusters_), cl::NullRange, nullptr, e);
}

void ClusterLightAssigner::fill(cl::CommandQueue& q, cl::Buffer& ranges, cl::Buffer& indices, ClPassTimer* timer) {
  if (clusters_ == 0) return;
  runAssign(q, true, &indices, timer);
  ranges_.setArg(0, offsets_);
  ranges_.setArg(1, counts_);
  ranges_.setArg(2, clusters_);
  ranges_.setArg(3, ranges);
  q.enqueueNDRangeKernel(ranges_, cl::NullRange, cl::NDRange(clusters_), cl::NullRange, nullptr,
                         timer ? timer->next("cluster-ranges") : nullptr);
}

}  // namespace ml
