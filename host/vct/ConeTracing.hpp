#pragma once
// The diffuse cone set and the uniforms of gl/shaders/vct/vct_cones.glsl, shared
// by the frame's trace pass (VctGiPass) and the tests that trace given points.
// Contract of diffuseCones(count):
//  - count directions on the hemisphere around +z (the normal, tangent frame),
//    distributed by cosine: an equal-area partition of the unit disk lifted
//    onto the hemisphere (Malley's method), so each cone stands for the same
//    projected solid angle. The disk is cut into rings (coneRings: a centre
//    cone, then round(sqrt(count) / 2) rings; 2 and 3 cones one ring), each
//    ring's cones evenly spaced at the middle of its equal-area band, odd
//    rings turned by half a step: from 4 cones on, the set's mean direction
//    across the normal is 0 and its second moments are the cosine lobe's;
//    the sunflower spiral it replaced (one cone per ring) had neither
//    (Cornell box, 9 cones: 0.165 / 0.160 / 0.143 -> 0.161 / 0.151 / 0.143
//    at 32^3 / 64^3 / 128^3, docs/vct.md);
//  - every weight is pi / count: sum_i w_i L_i is the irradiance
//    integral of L cos over the hemisphere, pi * L for uniform radiance L;
//  - count 1 is the normal alone. UserError outside 1..kMaxCones (--cones).
// coneSetTurn(count): a quarter of the set's rotational period about the
// normal (2 pi / the gcd of its rings' counts; 0 for the normal alone), the
// step of vct_trace.comp's four interleaved turns.
// checkConeSettings(): --cones in 1..32, --cone-aperture in (0, 180) degrees,
// --cone-lod-bias in [0, kMaxConeLodBias].
#include <glm/glm.hpp>

#include <vector>

#include "gl/ShaderProgram.hpp"
#include "host/vct/VoxelTextures.hpp"
#include "host/shared/voxel_types.h"

namespace ml::vct {

inline constexpr unsigned kMaxCones = 32;  // vct_cones.glsl's uniform array

// --cone-lod-bias: a cone samples the mip level whose voxel is 2^-bias of its
// diameter. A level's box filter and trilinear interpolation spread a point
// over a standard deviation of half its voxel, a disk of diameter D has D / 4:
// bias 1 matches the cone's cross-section, and more reads finer levels (less
// blur, more steps). What blur costs at fine grids: marching the 9 cone axes
// as rays through level 0 of the Cornell box's 128^3 volume (with the
// interleaved turns) measures 0.0995 against the cones' 0.121 at 1.25, and 128
// rays per pixel over the hemisphere 0.042 (energy 0.99): the voxels hold the
// light, the wide cones blur it. Cornell box, its camera, 320x320, 9 cones of
// 45 degrees, anisotropic, 4096-sample reference without its noise, 32^3 /
// 64^3 / 128^3: bias 1 0.144 / 0.138 / 0.128; 1.25 0.139 / 0.132 / 0.121; 1.5
// 0.134 / 0.130 / 0.118; 1.75 0.129 / 0.132 / 0.122; 2 0.124 / 0.134 / 0.125.
// The flights (manylights-vct-bench --flight) at 1.5 against 1.25: the default
// scene lower at 5 of 6 cameras with the cascade, 6 of 6 with one 128^3 grid;
// Spaceship Indoor lower at 5 of 6 with one 128^3 grid but higher at 5 of 6
// with 64^3 grids (3-9%; a 64^3 voxel there is coarse against the ship's
// ribs and seams). The cost: 13-30% more trace time (more, shorter steps;
// vct-trace, Cornell box 640x360 on llvmpipe). bench/RESULTS-vct.md.
inline constexpr float kConeLodBias = 1.5f;
inline constexpr float kMaxConeLodBias = 4.0f;

struct Cone {
  glm::vec3 dir;  // tangent frame, z the normal
  float weight;
};

void checkConeSettings(unsigned count, float aperture_deg, float lod_bias = kConeLodBias);
std::vector<unsigned> coneRings(unsigned count);
float coneSetTurn(unsigned count);
std::vector<Cone> diffuseCones(unsigned count);

// A test-only switch that breaks the trace on purpose (the accuracy tests must
// notice): every cone weighted 1 instead of pi / count.
enum class ConeBreak { None, Weights };

// A cascade level the cones read: its grid and textures.
struct ConeLevel {
  gpu::VoxelGridParams grid;
  const VoxelTextures* textures = nullptr;
};

struct ConeTraceSetup {
  gpu::VoxelGridParams grid;                // the single grid, or the cascade's outermost level
  const VoxelTextures* textures = nullptr;  // its textures
  bool anisotropic = false;
  std::vector<Cone> cones;
  float aperture_deg = 45.0f;
  ConeBreak broken = ConeBreak::None;
  std::vector<ConeLevel> levels;  // a cascade, finest first (empty: {grid, textures} alone)
  float lod_bias = kConeLodBias;  // --cone-lod-bias
};

// The define a program that includes vct_cones.glsl needs for `levels`
// cascade levels (ML_VCT_MAX_LEVELS); UserError naming --vct-cascades when
// the GL has too few compute texture units for them.
ShaderDefines coneTracingDefines(unsigned levels);

// Binds the levels' textures (level c: unit ML_UNIT_VCT_VOXELS + c and its 6
// directions from ML_UNIT_VCT_VOXELS + L + 6 c) and sets the cone uniforms of
// `p`, which must include vct_cones.glsl built with coneTracingDefines(L).
void bindConeTracing(const ShaderProgram& p, const ConeTraceSetup& s);

}  // namespace ml::vct
