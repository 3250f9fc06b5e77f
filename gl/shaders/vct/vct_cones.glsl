// Cone tracing through the voxel volume's mip-mapped 3D textures
// (gl/VoxelTextures: premultiplied radiance rgb, opacity a; the 6 direction
// textures when anisotropic). Uniforms: host/vct/ConeTracing.hpp.
// A cone marches front to back from a surface point (each sample lifted off
// the surface along its normal: kLevelOffset): at distance t its diameter is
// max(voxel, 2 t tan(aperture / 2)) and it samples the level whose voxel is
// 2^-u_lod_bias of that (trilinear within and between levels); each step
// is half the sampled level's voxel (a quarter of a diameter until the lod
// reaches the coarsest level). The sample's opacity becomes an optical
// density (opticalDensity: trilinear interpolation of a solid voxel's
// opacity would let 13.5% through it) taken over the step's length,
// a_step = 1 - exp(-density * step / edge), before
//   c += (1 - A) c_step,  A += (1 - A) a_step.
// It stops at opacity 0.99 or where it leaves the grid (outside is empty).
// Cascades (u_levels > 1, host/vct/VoxelCascade.hpp): the lod counts from the
// finest level's voxel; a sample reads the finest level whose mips reach its
// lod (inner levels hold kInnerLevels mip levels, the next level takes over
// from there) or, where no such level's window holds it, the finest one that does,
// and within kBlendVoxels of an inner window's face it fades into the next
// level, so a cone crosses from level to level without a seam. Toroidal
// levels are sampled through their shift (GL_REPEAT textures).
// Cornell box with its camera, 320x320, anisotropic, 9 cones of 45 degrees,
// --levels auto, against a 4096-sample reference without its noise
// (relative RMSE, energy): 32^3 0.134 (0.92), 64^3 0.130 (0.91), 128^3
// 0.118 (0.93) at lod bias 1.5 with vct_trace.comp's interleaved turns
// (0.139, 0.132, 0.121 at bias 1.25; 0.156, 0.147, 0.138 with one set);
// before the density, the bias, this offset, the faces' colour mix, the
// ring cone set and the turns: 0.197, 0.227, 0.185 at 4 levels
// (docs/vct.md, "Accuracy").
#include "vct_bindings.h"
// Level c's textures: radiance at unit ML_UNIT_VCT_VOXELS + c, its 6
// directions (+X -X +Y -Y +Z -Z, direction of travel) from
// ML_UNIT_VCT_VOXEL_DIRS + 6 c.
layout(binding = ML_UNIT_VCT_VOXELS) uniform sampler3D u_level_voxels[ML_VCT_MAX_LEVELS];
layout(binding = ML_UNIT_VCT_VOXEL_DIRS) uniform sampler3D u_level_dirs[6 * ML_VCT_MAX_LEVELS];
uniform vec4 u_grid_origin_size;  // the outermost level: corner xyz, level-0 voxel edge w
uniform float u_grid_edge;        // level-0 voxels per axis (every level)
uniform int u_levels;             // cascade levels, 1..ML_VCT_MAX_LEVELS (0 finest)
uniform vec4 u_level_origin_size[ML_VCT_MAX_LEVELS];  // window corner xyz, level-0 voxel edge w
uniform vec4 u_level_shift_lod[ML_VCT_MAX_LEVELS];    // voxel_shift / edge xyz (toroidal), levels - 1 w
uniform int u_anisotropic;
uniform float u_cone_tan;         // tan(aperture / 2) of the diffuse cones
uniform int u_cone_count;
uniform vec4 u_cones[32];         // tangent-frame direction (z the normal), weight (sum pi)
uniform float u_lod_bias;         // levels finer than the cone's width (ConeTracing.hpp kConeLodBias)

const float kConeStep = 0.5;        // step, in voxels of the sampled level
// The level read is log2(diameter / level-0 voxel) - u_lod_bias
// (--cone-lod-bias, host/vct/ConeTracing.hpp kConeLodBias: why 1.5).
// Each sample sits off the surface along the normal by the larger of one
// level-0 voxel and kLevelOffset voxels of the level it reads, so a coarse
// sample's trilinear footprint does not take in the surface's own voxel
// (self-occlusion and self-lighting). Cornell box as above at 32^3 / 64^3 /
// 128^3: 0 0.164 / 0.159 / 0.143; 0.25 0.164 / 0.159 / 0.142; 0.5 0.163 /
// 0.171 / 0.155 (bias 1); at bias 1.5 with the turns 0.125 0.132 / 0.131 /
// 0.119; 0.25 0.134 / 0.130 / 0.118; 0.375 0.134 / 0.132 / 0.122.
const float kLevelOffset = 0.25;
const float kConeOpaque = 0.99;
// A sample reads a cascade level only this many voxels of the mip level it
// reads inside the window (its trilinear footprint, kept off the seam of a
// toroidal level), and fades into the next level over kBlendVoxels more.
const float kLevelMargin = 3.0;
const float kBlendVoxels = 4.0;
const float kPi = 3.14159265358979;

// A face's colour, its premultiplied radiance over its opacity (black when empty).
vec3 faceColour(vec4 f) { return f.a > 1e-6 ? f.rgb / f.a : vec3(0.0); }

// Optical depth per voxel edge of a sample whose interpolated opacity is a.
// Trilinear interpolation spreads a voxel of opacity a over a hat two voxels
// wide; with -log(1 - a) as the density a march through a solid voxel (a = 1)
// collects 2 int_0^1 -log(u) du = 2 in all, 13.5% let through: the light
// that one-voxel walls leaked, the 7-11% the Cornell box's indirect light
// missed. g(a) = (-log(1 - a) + a / (1 - a)) / 2 is the density whose
// integral over the hat, 2 int_0^1 g(a u) du, is -log(1 - a) for every a: an
// isolated voxel lets through 1 - a again, a solid one nothing, and for
// small a it is a as before. (A uniform medium of opacity a reads
// denser than it is, 0.85 instead of 0.69 at a = 0.5: its opacity is
// coverage here, surfaces rather than fog.)
float opticalDensity(float a) {
  a = clamp(a, 0.0, 0.9999);
  return 0.5 * (-log(1.0 - a) + a / (1.0 - a));
}

// One level's sample at texture coordinates uvw (its radiance texture r and
// direction textures px..nz).
vec4 sampleFaces(sampler3D r, sampler3D px, sampler3D nx, sampler3D py, sampler3D ny, sampler3D pz, sampler3D nz,
                 vec3 uvw, float lod, vec3 d) {
  if (u_anisotropic == 0) return textureLod(r, uvw, lod);
  // Crassin's anisotropic voxels: the three faces the cone travels through,
  // weighted by the squared direction components (which sum to 1).
  // The faces' optical depths are mixed, not their opacities: a wall the cone
  // crosses at a slant is opaque through the face it faces, and half covers
  // a coarse voxel's pairs along the other two axes; mixing opacities let
  // such cones through (a one-voxel shell at the grid's edge lost 28-31%).
  // The colours are mixed with the same weights as the medium they belong
  // to, each face's colour (rgb / a) by its share of the optical depth. The
  // mean premultiplied colour over the mean opacity gave the faces along a
  // wall as much say as the face across it: a 0.1 m slab inside one coarse
  // voxel mixes its lit face with its dark back along the wall, and every
  // slanted crossing came out darker (Cornell box, its camera, 320x320,
  // 32^3 / 64^3 / 128^3: 0.173 / 0.178 / 0.158 -> 0.164 / 0.159 / 0.142).
  vec3 w = d * d;
  vec4 x = d.x >= 0.0 ? textureLod(px, uvw, lod) : textureLod(nx, uvw, lod);
  vec4 y = d.y >= 0.0 ? textureLod(py, uvw, lod) : textureLod(ny, uvw, lod);
  vec4 z = d.z >= 0.0 ? textureLod(pz, uvw, lod) : textureLod(nz, uvw, lod);
  vec3 alpha = clamp(vec3(x.a, y.a, z.a), 0.0, 1.0);
  vec3 share = w * -log(max(vec3(1.0) - alpha, vec3(1e-4)));
  float depth = share.x + share.y + share.z;
  if (depth <= 1e-6) return vec4(0.0);
  vec3 rgb = share.x * faceColour(x) + share.y * faceColour(y) + share.z * faceColour(z);
  float a = 1.0 - exp(-depth);
  return vec4(rgb * (a / depth), a);
}

// Sampler arrays are indexed by constants only (the level differs between
// neighbouring invocations: not dynamically uniform).
vec4 sampleLevelTextures(int c, vec3 uvw, float lod, vec3 d) {
#define ML_LEVEL_FACES(C)                                                                                     \
  sampleFaces(u_level_voxels[C], u_level_dirs[6 * C], u_level_dirs[6 * C + 1], u_level_dirs[6 * C + 2],       \
              u_level_dirs[6 * C + 3], u_level_dirs[6 * C + 4], u_level_dirs[6 * C + 5], uvw, lod, d)
  if (c == 0) return ML_LEVEL_FACES(0);
#if ML_VCT_MAX_LEVELS > 1
  if (c == 1) return ML_LEVEL_FACES(1);
#endif
#if ML_VCT_MAX_LEVELS > 2
  if (c == 2) return ML_LEVEL_FACES(2);
#endif
#if ML_VCT_MAX_LEVELS > 3
  if (c == 3) return ML_LEVEL_FACES(3);
#endif
#undef ML_LEVEL_FACES
  return vec4(0.0);
}

// Voxel coordinates of x in level c's window (level 0 of that level).
vec3 levelVoxel(int c, vec3 x) { return (x - u_level_origin_size[c].xyz) / u_level_origin_size[c].w; }

// How far x lies inside level c's window, in its level-0 voxels (< 0: outside).
float insideVoxels(int c, vec3 x) {
  vec3 g = levelVoxel(c, x);
  vec3 m = min(g, vec3(u_grid_edge) - g);
  return min(m.x, min(m.y, m.z));
}

// The lod level c is read at for a footprint of lod `lod` (counted from the
// finest level's voxel), and its margin: kLevelMargin of those voxels, in
// level-0 voxels of c.
float localLod(int c, float lod) { return clamp(lod - float(c), 0.0, u_level_shift_lod[c].w); }
float levelMargin(int c, float lod) { return kLevelMargin * exp2(localLod(c, lod)); }

// The finest level whose mips reach the footprint and whose window holds x
// with its margin to spare (the outermost when none does).
int levelFor(vec3 x, float lod) {
  for (int c = 0; c < u_levels - 1; ++c)
    if (lod - float(c) <= u_level_shift_lod[c].w && insideVoxels(c, x) >= levelMargin(c, lod)) return c;
  return u_levels - 1;
}

// Level c at x, at lod `lod` counted from its own level-0 voxel (clamped to its levels).
vec4 sampleLevel(int c, vec3 x, float lod, vec3 d) {
  vec3 uvw = levelVoxel(c, x) / u_grid_edge + u_level_shift_lod[c].xyz;
  return sampleLevelTextures(c, uvw, clamp(lod, 0.0, u_level_shift_lod[c].w), d);
}

// The cascade's medium at x for a footprint of lod `lod` (counted from the
// finest level's voxel): colour (rgb, radiance over opacity) and density per
// unit length (a, opticalDensity over the voxel edge it was read at), from
// the finest level whose mips reach that footprint, or the finest one whose
// window holds x; near an inner window's face the densities of this level and the next
// are mixed (and the colours by their share of it): mixing opacities read
// at two voxel sizes counted the coarse one's twice over a fine step (a
// band too bright where the levels meet). `edge` returns the voxel edge of
// the level the footprint asked for.
vec4 levelMedium(int c, vec3 x, float lod, vec3 d, out float edge) {
  float local = localLod(c, lod);
  edge = u_level_origin_size[c].w * exp2(local);
  vec4 s = sampleLevel(c, x, local, d);
  vec3 colour = s.a > 1e-6 ? s.rgb / s.a : vec3(0.0);
  return vec4(colour, opticalDensity(s.a) / edge);
}

vec4 sampleMedium(vec3 x, float lod, vec3 d, out float edge) {
  int c = levelFor(x, lod);
  vec4 m = levelMedium(c, x, lod, d, edge);
  if (c == u_levels - 1) return m;
  float margin = levelMargin(c, lod);
  float f = clamp((insideVoxels(c, x) - margin) / (kBlendVoxels / kLevelMargin * margin), 0.0, 1.0);
  if (f >= 1.0) return m;
  float unused;
  vec4 n = levelMedium(c + 1, x, lod, d, unused);
  float sigma = mix(n.a, m.a, f);
  if (sigma <= 0.0) return vec4(0.0);
  return vec4((mix(n.a * n.rgb, m.a * m.rgb, f)) / sigma, sigma);
}


// Premultiplied radiance along the cone (rgb) and its opacity (a), from the
// surface point P with normal N (the samples' offset: kLevelOffset).
vec4 traceCone(vec3 P, vec3 N, vec3 d, float tan_half) {
  float vs0 = u_level_origin_size[0].w;  // the finest level's voxel: lod 0
  float vs = u_level_origin_size[levelFor(P, 0.0)].w;  // the voxel where the cone starts
  int outer = u_levels - 1;
  float max_lod = float(outer) + u_level_shift_lod[outer].w;
  vec3 acc = vec3(0.0);
  float a = 0.0;
  float t = vs;
  for (int i = 0; i < 512 && a < kConeOpaque; ++i) {
    float diam = max(vs, 2.0 * t * tan_half);
    float lod = clamp(log2(diam / vs0) - u_lod_bias, 0.0, max_lod);
    float want = vs0 * exp2(lod);  // the footprint's level voxel, for the lift
    vec3 x = P + N * max(vs, kLevelOffset * want) + t * d;
    if (insideVoxels(outer, x) < 0.0) break;
    float edge;
    vec4 m = sampleMedium(x, lod, d, edge);
    // Half the sampled level's voxel (the cone's diameter while the lod
    // follows it; steps of half the cone's width once the lod was clamped at
    // the coarsest level skipped voxels: streaks on the Cornell box's ceiling
    // at 128^3, cones leaving the grid through walls), shortened by the lift's
    // growth along the normal (2 kLevelOffset tan_half per unit of t), so the
    // sample itself moves at most half a voxel per step.
    float step = kConeStep * edge / (1.0 + 2.0 * kLevelOffset * tan_half);
    float a_step = 1.0 - exp(-m.a * step);
    acc += (1.0 - a) * m.rgb * a_step;
    a += (1.0 - a) * a_step;
    t += step;
  }
  return vec4(acc, a);
}

mat3 tangentFrame(vec3 n) {
  vec3 t = normalize(abs(n.x) < 0.5 ? cross(n, vec3(1.0, 0.0, 0.0)) : cross(n, vec3(0.0, 1.0, 0.0)));
  return mat3(t, cross(n, t), n);
}

// rgb: irradiance / pi (the mean incoming radiance, cosine-weighted) at P
// with normal N; a: ambient occlusion, 1 - the cones' weighted opacity / pi
// (1: nothing in the way). The cone set turned by `turn` radians about the
// normal (vct_trace.comp interleaves four turns over 2x2 pixels).
vec4 traceDiffuse(vec3 P, vec3 N, float turn) {
  float c = cos(turn), s = sin(turn);
  mat3 frame = tangentFrame(N) * mat3(c, s, 0.0, -s, c, 0.0, 0.0, 0.0, 1.0);
  vec3 e = vec3(0.0);
  float occlusion = 0.0;
  for (int i = 0; i < u_cone_count; ++i) {
    vec4 r = traceCone(P, N, normalize(frame * u_cones[i].xyz), u_cone_tan);
    e += u_cones[i].w * r.rgb;
    occlusion += u_cones[i].w * r.a;
  }
  return vec4(e / kPi, 1.0 - occlusion / kPi);
}

vec4 traceDiffuse(vec3 P, vec3 N) { return traceDiffuse(P, N, 0.0); }
