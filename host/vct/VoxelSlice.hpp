#pragma once
// A plane of the voxel volume for the voxel view's slice mode
// (`render --voxel-slice x|y|z[:position]`, the viewer's slice setting): the
// axis the plane is normal to and its position along the grid, 0..1 (default
// 0.5). At a level of e voxels per axis the plane is the voxel layer
// voxelSlicePlane() = min(floor(position * e), e - 1). The image's axes:
// slice x shows (z, y), y shows (x, z), z shows (x, y) (horizontal, vertical;
// rows bottom-up), so that y is up wherever it lies in the plane.
// parseVoxelSlice: UserError naming `flag` for anything else.
#include <string>

namespace ml::vct {

struct VoxelSlice {
  unsigned axis = 2;  // 0 x, 1 y, 2 z
  float position = 0.5f;
};

inline constexpr const char* kVoxelSliceSyntax = "x|y|z[:position in 0..1]";
VoxelSlice parseVoxelSlice(const std::string& text, const std::string& flag);
std::string voxelSliceText(const VoxelSlice& slice);  // "z:0.5"
unsigned voxelSlicePlane(const VoxelSlice& slice, unsigned edge_at_level);

}  // namespace ml::vct
