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

void bindConeTracing(const ShaderProgram& p, const ConeTraceSetup& s) {
  glBindTextureUnit(ML_UNIT_VCT_VOXELS, s.textures->radiance());
  for (unsigned d = 0; d < ML_VOXEL_DIRECTIONS; ++d)
    glBindTextureUnit(ML_UNIT_VCT_VOXEL_DIRS + d, s.anisotropic ? s.textures->direction(d) : s.textures->radiance());
  const auto& o = s.grid.origin_voxel_size;
  p.set4("u_grid_origin_size", o.x, o.y, o.z, o.w);
  p.set("u_grid_edge", float(s.grid.edge));
  p.set("u_grid_max_lod", float(s.grid.levels - 1));
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
