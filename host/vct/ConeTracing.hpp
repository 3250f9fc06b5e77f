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

struct ConeTraceSetup {
  gpu::VoxelGridParams grid;
  const VoxelTextures* textures = nullptr;
  bool anisotropic = false;
  std::vector<Cone> cones;
  float aperture_deg = 45.0f;
  ConeBreak broken = ConeBreak::None;
};

// Binds the volume's textures (units 4, 5..10) and sets the cone uniforms of
// `p`, which must include vct_cones.glsl and be in use.
void bindConeTracing(const ShaderProgram& p, const ConeTraceSetup& s);

}  // namespace ml::vct
