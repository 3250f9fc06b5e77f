#pragma once
// Debug images of the voxel volume "as cubes": per pixel, the camera ray is
// marched through one level's grid (3D DDA, Amanatides-Woo) to the first voxel
// whose opacity is > 0 (from an eye inside the grid, the voxel holding the
// eye is passed over: at a coarse level it would fill the image), and the
// image shows that voxel's
//   albedo:   mean albedo of the voxelized fragments under it (level 0's
//             VoxelAccum sums over the 2^level-cube of level-0 voxels it covers);
//   radiance: its radiance, un-premultiplied (rgb / opacity);
//   opacity:  its opacity as grey.
// The result is linear RGBA, rows bottom-up, alpha 1 where a voxel was hit and
// 0 (black) where the ray left the grid empty.
// Slices (renderSlice, host/vct/VoxelSlice.hpp): one plane of the level,
// nearest voxels, filling the image's centred square (outside it: 0); each
// voxel with opacity > 0 as above, an empty one 0. Anisotropic volumes at
// levels >= 1 show the mean of the 6 directions' premultiplied values (what
// an average cone sees; the cubes show the isotropic mips). GL compute shader
// gl/shaders/vct/voxel_view.comp reading the volume's SharedBuffers (GL owns them
// between updates); voxelViewPixelTwin (VoxelViewTwin.hpp) is its C++ twin.
// parseVoxelView / checkVoxelLevel: UserError naming --voxel-view / --voxel-level;
// so is a volume buffer larger than the GL's shader storage block limit (the
// shader indexes each buffer whole).
#include <glm/glm.hpp>

#include <string>
#include <vector>

#include "gl/ShaderProgram.hpp"
#include "host/vct/VoxelSlice.hpp"
#include "host/vct/VoxelVolume.hpp"

namespace ml::vct {

enum class VoxelViewKind : unsigned { Albedo = 0, Radiance = 1, Opacity = 2 };  // voxel_view.comp's u_kind

inline constexpr const char* kVoxelViewNames = "albedo|radiance|opacity";
VoxelViewKind parseVoxelView(const std::string& name);
const char* voxelViewName(VoxelViewKind kind);
void checkVoxelLevel(unsigned level, unsigned levels);
// As displayed (render's PNG, the viewer): radiance with the GI tone-map
// (host/util/GiToneMap.hpp), albedo and opacity as they are; alpha 1.
std::vector<float> voxelViewDisplay(const std::vector<float>& rgba, VoxelViewKind kind);

// The camera of one image: the frame's matrices and size.
struct VoxelViewCamera {
  glm::mat4 view, proj;
  unsigned width = 0, height = 0;
};

class VoxelViewPass {
 public:
  VoxelViewPass();
  // Needs the volume's GL context; level is checked (checkVoxelLevel).
  std::vector<float> render(const VoxelVolume& volume, VoxelViewKind kind, unsigned level,
                            const VoxelViewCamera& camera);
  std::vector<float> renderSlice(const VoxelVolume& volume, VoxelViewKind kind, unsigned level,
                                 const VoxelSlice& slice, unsigned width, unsigned height);

 private:
  // Binds the volume and the level's uniforms, runs the shader over a
  // poisoned width x height image and reads it back.
  std::vector<float> dispatch(const VoxelVolume& volume, VoxelViewKind kind, unsigned level, unsigned width,
                              unsigned height);

  ShaderProgram program_;
};

}  // namespace ml::vct
