#include "host/vct/ConeTracing.hpp"

#include <glm/gtc/type_ptr.hpp>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <string>

#include "gl/GlCheck.hpp"
#include "host/shared/vct_bindings.h"
#include "host/util/Error.hpp"

namespace ml::vct {
namespace {
constexpr float kPi = 3.14159265358979f;
}  // namespace

void checkConeSettings(unsigned count, float aperture_deg, float lod_bias) {
  if (count < 1 || count > kMaxCones)
    throw UserError("--cones: expected 1.." + std::to_string(kMaxCones) + ", got " + std::to_string(count));
  if (!(aperture_deg > 0.0f && aperture_deg < 180.0f))
    throw UserError("--cone-aperture: expected degrees in (0, 180), got " + std::to_string(aperture_deg));
  if (!(lod_bias >= 0.0f && lod_bias <= kMaxConeLodBias))
    throw UserError("--cone-lod-bias: expected levels in [0, " + std::to_string(int(kMaxConeLodBias)) + "], got " +
                    std::to_string(lod_bias));
}

// Ring counts: the centre cone, then round(sqrt(count) / 2) rings sharing the
// rest evenly (the larger rings outside); 2 and 3 cones are one ring.
std::vector<unsigned> coneRings(unsigned count) {
  if (count <= 3) return {count};
  const auto rings = std::max(1u, static_cast<unsigned>(std::lround(std::sqrt(double(count)) / 2.0)));
  std::vector<unsigned> out{1u};
  const unsigned rest = count - 1;
  for (unsigned j = 0; j < rings; ++j) out.push_back(rest / rings + (j >= rings - rest % rings ? 1u : 0u));
  return out;
}

float coneSetTurn(unsigned count) {
  checkConeSettings(count, 45.0f);
  if (count == 1) return 0.0f;  // the normal alone
  unsigned period = 0;          // the gcd of the rings' counts, the centre cone (a ring of 1) aside
  for (const unsigned k : coneRings(count))
    if (k > 1) period = std::gcd(period, k);
  return 2.0f * kPi / float(period) / 4.0f;
}

std::vector<Cone> diffuseCones(unsigned count) {
  checkConeSettings(count, 45.0f);
  const std::vector<unsigned> rings = coneRings(count);
  // Each ring at the middle of its equal-area band in r^2 (the disk's area
  // coordinate); a lone centre cone sits at r = 0, so the rings' r^2 are
  // scaled to keep the cosine lobe's E[r^2] = 1/2 (the second moments; one
  // cone is the normal).
  std::vector<float> r2(rings.size());
  float area = 0.0f, moment = 0.0f;
  for (std::size_t j = 0; j < rings.size(); ++j) {
    const float band = float(rings[j]) / float(count);
    r2[j] = (rings[j] == 1 && j == 0) ? 0.0f : area + 0.5f * band;
    moment += band * r2[j];
    area += band;
  }
  std::vector<Cone> cones;
  for (std::size_t j = 0; j < rings.size(); ++j) {
    const float r = moment > 0.0f ? std::sqrt(std::min(1.0f, r2[j] * 0.5f / moment)) : 0.0f;
    for (unsigned i = 0; i < rings[j]; ++i) {
      const float phi = 2.0f * kPi * (float(i) + 0.5f * float(j % 2)) / float(rings[j]);
      const glm::vec3 d(r * std::cos(phi), r * std::sin(phi), std::sqrt(std::max(0.0f, 1.0f - r * r)));
      cones.push_back({d, kPi / float(count)});
    }
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
  p.set("u_lod_bias", s.lod_bias);
  std::vector<float> packed;
  for (const Cone& c : s.cones)
    packed.insert(packed.end(), {c.dir.x, c.dir.y, c.dir.z, s.broken == ConeBreak::Weights ? 1.0f : c.weight});
  p.set("u_cone_count", static_cast<int>(s.cones.size()));
  glProgramUniform4fv(p.id(), glGetUniformLocation(p.id(), "u_cones"), static_cast<GLsizei>(s.cones.size()),
                      packed.data());
  glCheck("setting the cone-tracing uniforms");
}

}  // namespace ml::vct
