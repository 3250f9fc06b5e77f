#pragma once
// The exact lower bound of a frame's light evaluations, computed once per
// counted frame and the same way for every technique: for each covered pixel,
// the lights whose sphere strictly contains the surface point
// (|L - P|^2 < r^2 in float), P reconstructed from the depth buffer
// (windowToWorld, the one place depth becomes a position). Every technique's
// lists are conservative, so a technique evaluates at least this many lights.
//
//   ExactLowerBound bound(rt);
//   bound.setLights(q, lights);                        // builds the light grid (host) and uploads it
//   bound.count(q, depth, boundParams(view, proj, w, h), counts);   // counts: uint per pixel
//
// The light grid has one dense level per power-of-two band of radii, cells
// twice the band's smallest radius, so a light sits in at most 27 cells and a
// point tests each level's one cell: exact (the kernel applies the predicate
// to every listed light), and ~1 s for 1M lights at 1080p on two CPU cores.
// kernels/assign/exact_lower_bound.cl is the device side; boundAtPixel its C++ twin.
#include <CL/opencl.hpp>
#include <glm/glm.hpp>

#include <cstdint>
#include <vector>

#include "host/cl/ClPassTimer.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/shared/gpu_types.h"

namespace ml {

struct LightGrid {
  std::vector<gpu::BoundGridLevel> levels;
  std::vector<std::uint32_t> cell_start;  // per global cell, plus one: entries[cell_start[c] .. cell_start[c+1])
  std::vector<std::uint32_t> entries;     // light indices
  std::vector<gpu::ml_float4> spheres;    // per light: position, radius (as the shaders read them)
};

// Lights with a non-finite position or radius, or r * r == 0, contain no point
// and are left out.
LightGrid buildLightGrid(const std::vector<gpu::PointLight>& lights);

gpu::BoundParams boundParams(const glm::mat4& view, const glm::mat4& proj, unsigned width, unsigned height);

// Window depth of pixel (x, y) -> world position; false for background
// (depth 1). Twin of window_to_world in the kernel and of windowToView /
// viewToWorld in gl/shaders/common/common.glsl.
bool windowToWorld(float depth, unsigned x, unsigned y, const gpu::BoundParams& p, glm::vec3& world);

// The kernel's per-pixel value, in C++ (0 for background).
std::uint32_t boundAtPixel(const LightGrid& grid, const gpu::BoundParams& p, float depth, unsigned x, unsigned y);

class ExactLowerBound {
 public:
  explicit ExactLowerBound(ClRuntime& rt);

  void setLights(cl::CommandQueue& q, const std::vector<gpu::PointLight>& lights);
  // depth: float[width * height], row 0 at the bottom; counts: uint[width * height].
  // p.level_count is filled in from the grid.
  void count(cl::CommandQueue& q, const cl::Buffer& depth, gpu::BoundParams p, cl::Buffer& counts,
             ClPassTimer* timer = nullptr);

  const LightGrid& grid() const { return grid_; }

 private:
  ClRuntime& rt_;
  cl::Program program_;
  cl::Kernel kernel_;
  LightGrid grid_;
  std::uint32_t longest_list_ = 0;  // entries of the grid's longest cell list
  // Loop iterations per work-item and launch, all loops together: under
  // llvmpipe's 65,535 with a margin (kernels/assign/exact_lower_bound.cl).
  static constexpr std::uint32_t kLoopCap = 60000;
  cl::Buffer params_, levels_, cell_start_, entries_, spheres_;
};

}  // namespace ml
