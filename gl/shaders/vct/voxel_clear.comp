// Clears one window box of the level-0 accumulation buffer (VoxelAccum per
// voxel, stored where the toroidal shift puts it: voxel_types.h, wrap)
// before the box is voxelized again (VoxelizePass with a region).
#include "vct_bindings.h"
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;
struct VoxelAccum {
  uvec4 albedo_count;
  ivec4 normal_sum;
};
layout(std430, binding = ML_BINDING_VOXELIZE_ACCUM) buffer VoxelAccumBuffer { VoxelAccum voxels[]; };
uniform uint u_edge;
uniform uvec3 u_shift;
uniform uvec3 u_lo, u_size;  // the box, window coordinates

void main() {
  uvec3 g = gl_GlobalInvocationID;
  if (any(greaterThanEqual(g, u_size))) return;
  uvec3 v = (u_lo + g + u_shift) & uvec3(u_edge - 1u);
  voxels[v.x + u_edge * (v.y + u_edge * v.z)] = VoxelAccum(uvec4(0u), ivec4(0));
}
