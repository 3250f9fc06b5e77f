#pragma once
// C++ twin of gl/shaders/vct/voxel_view.comp (host/vct/VoxelView.hpp): one pixel
// of the voxel view from the volume read back to the host (`radiance`: every
// level, voxel_types.h layout; `accum`: level 0). The same operations in the
// same order as the shader, so the two differ only where rounding moves a ray
// across a voxel face (a grazing hit).
#include <glm/glm.hpp>

#include <vector>

#include "host/shared/voxel_types.h"
#include "host/vct/VoxelView.hpp"

namespace ml::vct {

// The ray of pixel (x, y) (rows bottom-up, through the pixel centre): origin
// the eye, direction unnormalized towards the point at NDC depth 0.5.
struct PixelRay {
  glm::vec3 origin, direction;
};
PixelRay voxelViewRay(const VoxelViewCamera& camera, unsigned x, unsigned y);

glm::vec4 voxelViewPixelTwin(const std::vector<gpu::ml_float4>& radiance, const std::vector<gpu::VoxelAccum>& accum,
                             const gpu::VoxelGridParams& grid, VoxelViewKind kind, unsigned level,
                             const VoxelViewCamera& camera, unsigned x, unsigned y);

// Pixel (x, y) of VoxelViewPass::renderSlice's width x height image. `aniso`:
// the anisotropic volume read back (voxel_types.h layout), empty when the
// volume is isotropic.
glm::vec4 voxelSlicePixelTwin(const std::vector<gpu::ml_float4>& radiance, const std::vector<gpu::ml_float4>& aniso,
                              const std::vector<gpu::VoxelAccum>& accum, const gpu::VoxelGridParams& grid,
                              VoxelViewKind kind, unsigned level, const VoxelSlice& slice, unsigned width,
                              unsigned height, unsigned x, unsigned y);

}  // namespace ml::vct
