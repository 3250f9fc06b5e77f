#pragma once
// The diffuse cone set and the uniforms of gl/shaders/vct/vct_cones.glsl, shared
// by the frame's trace pass (VctGiPass) and the tests that trace given points.
// Contract of diffuseCones(count):
//  - count directions on the hemisphere around +z (the normal, tangent frame),
//    distributed by cosine: the points of an equal-area partition of the unit
//    disk (the first at its centre, the rest on a sunflower spiral at the
//    centres of equal-area rings) lifted onto the hemisphere (Malley's
//    method), so each cone stands for the same projected solid angle;
//  - every weight is pi / count: sum_i w_i L_i is the irradiance
//    integral of L cos over the hemisphere, pi * L for uniform radiance L;
//  - count 1 is the normal alone. UserError outside 1..kMaxCones (--cones).
// checkConeSettings(): --cones in 1..32, --cone-aperture in (0, 180) degrees.
#include <glm/glm.hpp>

#include <vector>

#include "gl/ShaderProgram.hpp"
#include "host/vct/VoxelTextures.hpp"
#include "host/shared/voxel_types.h"

namespace ml::vct {

inline constexpr unsigned kMaxCones = 32;  // vct_cones.glsl's uniform array

struct Cone {
  glm::vec3 dir;  // tangent frame, z the normal
  float weight;
};

void checkConeSettings(unsigned count, float aperture_deg);
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
