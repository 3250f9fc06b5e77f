#include "host/vct/ConeTracing.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <cmath>
#include <string>

#include "gl/GlCheck.hpp"
#include "host/shared/vct_bindings.h"
#include "host/util/Error.hpp"

namespace ml::vct {
namespace {
constexpr float kPi = 3.14159265358979f;
constexpr float kGoldenAngle = 2.39996322972865f;  // pi (3 - sqrt 5)
}  // namespace

void checkConeSettings(unsigned count, float aperture_deg) {
  if (count < 1 || count > kMaxCones)
    throw UserError("--cones: expected 1.." + std::to_string(kMaxCones) + ", got " + std::to_string(count));
  if (!(aperture_deg > 0.0f && aperture_deg < 180.0f))
    throw UserError("--cone-aperture: expected degrees in (0, 180), got " + std::to_string(aperture_deg));
}

std::vector<Cone> diffuseCones(unsigned count) {
  checkConeSettings(count, 45.0f);
  std::vector<Cone> cones;
  for (unsigned i = 0; i < count; ++i) {
    // Point i of the disk: the centre, then the middle of ring i (areas i/n .. (i+1)/n).
    const float r = i == 0 ? 0.0f : std::sqrt((float(i) + 0.5f) / float(count));
    const float phi = float(i) * kGoldenAngle;
    const glm::vec3 d(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - r * r)));
    cones.push_back({d, kPi / float(count)});
  }
  return cones;
}

ShaderDefines coneTracingDefines(unsigned levels) {
  GLint units = 0;
  glGetIntegerv(GL_MAX_COMPUTE_TEXTURE_IMAGE_UNITS, &units);
  glCheck("reading the compute texture unit limit");
  const unsigned need = ML_UNIT_VCT_VOXELS + 7 * levels;
  if (units > 0 && need > static_cast<unsigned>(units))
    throw UserError("--vct-cascades " + std::to_string(levels) + ": the cones need " + std::to_string(need) +
                    " texture units, this GL has " + std::to_string(units));
  return {{"ML_VCT_MAX_LEVELS", std::to_string(levels)}};
}

void bindConeTracing(const ShaderProgram& p, const ConeTraceSetup& s) {
  const std::vector<ConeLevel> levels = s.levels.empty() ? std::vector<ConeLevel>{{s.grid, s.textures}} : s.levels;
  const auto n = static_cast<unsigned>(levels.size());
  std::vector<float> origin_size, shift_lod;
  for (unsigned c = 0; c < n; ++c) {
    const ConeLevel& l = levels[c];
    glBindTextureUnit(ML_UNIT_VCT_VOXELS + c, l.textures->radiance());
    for (unsigned d = 0; d < ML_VOXEL_DIRECTIONS; ++d)
      glBindTextureUnit(ML_UNIT_VCT_VOXELS + n + 6 * c + d,
                        s.anisotropic ? l.textures->direction(d) : l.textures->radiance());
    const auto& o = l.grid.origin_voxel_size;
    origin_size.insert(origin_size.end(), {o.x, o.y, o.z, o.w});
    const gpu::VoxelShift sh = gpu::voxel_shift(l.grid);
    const float e = float(l.grid.edge);
    shift_lod.insert(shift_lod.end(), {float(sh.x) / e, float(sh.y) / e, float(sh.z) / e, float(l.grid.levels - 1)});
  }
  const auto& o = s.grid.origin_voxel_size;
  p.set4("u_grid_origin_size", o.x, o.y, o.z, o.w);
  p.set("u_grid_edge", float(s.grid.edge));
  p.set("u_levels", static_cast<int>(n));
  p.set4v("u_level_origin_size", static_cast<int>(n), origin_size.data());
  p.set4v("u_level_shift_lod", static_cast<int>(n), shift_lod.data());
  p.set("u_anisotropic", s.anisotropic ? 1 : 0);
  p.set("u_cone_tan", std::tan(s.aperture_deg * kPi / 360.0f));
  std::vector<float> packed;
  for (const Cone& c : s.cones)
    packed.insert(packed.end(), {c.dir.x, c.dir.y, c.dir.z, s.broken == ConeBreak::Weights ? 1.0f : c.weight});
  p.set("u_cone_count", static_cast<int>(s.cones.size()));
  glProgramUniform4fv(p.id(), glGetUniformLocation(p.id(), "u_cones"), static_cast<GLsizei>(s.cones.size()),
                      packed.data());
  glCheck("setting the cone-tracing uniforms");
}

}  // namespace ml::vct
