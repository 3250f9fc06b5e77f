#include "host/clustered/ClusteredAssigner.hpp"

#include "gl/GlCheck.hpp"
#include "gl/ShaderProgram.hpp"
#include "host/assign/LightFootprint.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/shared/shading_bindings.h"
#include "host/util/IdColour.hpp"

namespace ml {

ClusteredAssigner::ClusteredAssigner(ClRuntime& rt, unsigned tile_size, UniqueMethod unique,
                                     ClusterAssignMethod assign, ClusterBounds bounds, KernelShape shape)
    : rt_(rt), tile_size_(tile_size), bounds_(bounds), uniquer_(rt, unique, 6, shape), lights_(rt, assign, 32, shape) {
  ranges_ = std::make_unique<SharedBuffer>(rt, 4096 * sizeof(gpu::LightRange), "cluster light ranges");
  records_ = std::make_unique<SharedBuffer>(rt, 65536 * sizeof(cl_uint2), "cluster light records");
  leaf_lights_ = std::make_unique<SharedBuffer>(rt, 65536 * sizeof(std::uint32_t), "cluster leaf lights");
  map_ = std::make_unique<SharedBuffer>(rt, 65536 * sizeof(std::uint32_t), "pixel cluster map");
}

void ClusteredAssigner::assign(const FrameInputs& in) {
  cl::CommandQueue& q = rt_.queue();
  // Rebuilt per frame: it depends on the camera's near/far/fov and viewport.
  if (!tile_size_) light_pixels_ = coveringLightPixels(in.host_lights, in.camera_params);  // only auto reads it
  grid_ = ClusterGrid::make(in.camera_params, tile_size_ ? tile_size_ : autoClusterTile(in.width, in.height, light_pixels_));
  map_->reserve(std::size_t(in.width) * in.height * sizeof(std::uint32_t));
  in.lights.acquireForCl(q, ClAccess::Read);
  in.depth->acquireForCl(q, ClAccess::Read);
  map_->acquireForCl(q, ClAccess::Write);
  uniquer_.keys(q, in.depth->cl(), in.camera_params, grid_, &in.cl_timer);
  clusters_ = uniquer_.unique(q, grid_, &in.cl_timer, &map_->cl());
  // The explicit bounds read the depth and the map, so CL keeps them until the boxes are done.
  const ClusterPixels pixels{in.depth->cl(), map_->cl()};
  lights_.boxes(q, in.camera_params, grid_, uniquer_.uniqueKeys(), clusters_, &in.cl_timer,
                bounds_ == ClusterBounds::Pixels ? &pixels : nullptr);
  map_->releaseToGl(q);
  in.depth->releaseToGl(q);
  const std::uint32_t records = lights_.assign(q, in.lights.cl(), in.light_count, in.camera_params, &in.cl_timer);
  last_records_ = records;
  // GL owns the output buffers while they grow; CL takes them for the fill.
  ranges_->reserve(std::size_t(clusters_) * sizeof(gpu::LightRange));
  records_->reserve(std::size_t(records) * sizeof(cl_uint2));
  leaf_lights_->reserve(lights_.leafLightSlots() * sizeof(std::uint32_t));
  for (SharedBuffer* b : {ranges_.get(), records_.get(), leaf_lights_.get()}) b->acquireForCl(q, ClAccess::Write);
  lights_.fill(q, ranges_->cl(), records_->cl(), leaf_lights_->cl(), &in.cl_timer);
  for (SharedBuffer* b : {leaf_lights_.get(), records_.get(), ranges_.get()}) b->releaseToGl(q);
  in.lights.releaseToGl(q);
}

void ClusteredAssigner::bindForShading(const ShaderProgram& program) const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_CLUSTER_RECORDS, records_->gl());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_CLUSTER_RANGES, ranges_->gl());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_CLUSTER_MAP, map_->gl());
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_CLUSTER_LEAF_LIGHTS, leaf_lights_->gl());
  program.set("u_cluster_width", grid_.width);
  glCheck("binding the cluster buffers");
}

std::vector<std::uint32_t> ClusteredAssigner::readClusterMap() {
  std::vector<std::uint32_t> out(std::size_t(grid_.width) * grid_.height);
  cl::CommandQueue& q = rt_.queue();
  map_->acquireForCl(q, ClAccess::Read);
  if (!out.empty()) q.enqueueReadBuffer(map_->cl(), CL_TRUE, 0, out.size() * 4, out.data());
  map_->releaseToGl(q);
  q.finish();
  return out;
}

std::vector<float> ClusteredAssigner::clusterViewRgba(const std::vector<std::uint32_t>& cluster_map) {
  std::vector<float> rgba(cluster_map.size() * 4, 0.0f);
  for (std::size_t p = 0; p < cluster_map.size(); ++p) {
    rgba[p * 4 + 3] = 1.0f;
    if (cluster_map[p] == kClusterInvalid) continue;
    // Up to 2^18 clusters get distinct colours, none of them black (sky).
    const Rgb c = idColour(cluster_map[p]);
    rgba[p * 4] = c.r;
    rgba[p * 4 + 1] = c.g;
    rgba[p * 4 + 2] = c.b;
  }
  return rgba;
}

std::size_t ClusteredAssigner::memoryBytes() const {
  return std::size_t(clusters_) * sizeof(gpu::LightRange) + std::size_t(last_records_) * sizeof(cl_uint2) +
         lights_.leafLightSlots() * sizeof(std::uint32_t) +
         std::size_t(grid_.width) * grid_.height * sizeof(std::uint32_t) + uniquer_.scratchBytes() +
         lights_.scratchBytes();
}

std::vector<std::pair<std::string, double>> ClusteredAssigner::stats() const {
  return {{"unique clusters", double(clusters_)},
          {"cluster list records", double(last_records_)},
          {"cluster list lights", double(lights_.listedLights(rt_.queue()))},
          {"cluster tile", double(grid_.tile_size)},
          {"light radius px", light_pixels_},
          {"pixel bounds", bounds_ == ClusterBounds::Pixels ? 1.0 : 0.0},
          {"depth slices", double(grid_.slices)},
          {"bvh levels", double(lights_.method() == ClusterAssignMethod::Bvh ? lights_.bvhLevels() : 0)},
          {"bvh lights", double(lights_.method() == ClusterAssignMethod::Bvh ? lights_.treeLights() : 0)}};
}

}  // namespace ml
