// One level of a voxel volume (host/shared/voxel_types.h: float4 per voxel,
// x fastest) into one level of an RGBA16F 3D texture (gl/VoxelTextures).
layout(local_size_x = 4, local_size_y = 4, local_size_z = 4) in;

layout(std430, binding = 0) readonly buffer Volume { vec4 voxels[]; };
layout(rgba16f, binding = 0) uniform writeonly image3D u_level;

uniform uint u_offset;  // the level's first voxel in `voxels`
uniform uint u_edge;    // voxels per axis at this level

void main() {
  const uvec3 p = gl_GlobalInvocationID;
  if (any(greaterThanEqual(p, uvec3(u_edge)))) return;
  imageStore(u_level, ivec3(p), voxels[u_offset + p.x + u_edge * (p.y + u_edge * p.z)]);
}
