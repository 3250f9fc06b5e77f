// Cone tracing through the voxel volume's mip-mapped 3D textures
// (gl/VoxelTextures: premultiplied radiance rgb, opacity a; the 6 direction
// textures when anisotropic). Uniforms: host/vct/ConeTracing.hpp.
// A cone marches front to back from a surface point (each sample lifted off
// the surface along its normal: kLevelOffset): at distance t its diameter is
// max(voxel, 2 t tan(aperture / 2)) and it samples the level whose voxel is
// half that wide (kLodBias; trilinear within and between levels); each step
// is half the sampled level's voxel (a quarter of a diameter until the lod
// reaches the coarsest level). The sample's opacity becomes an optical
// density (opticalDensity: trilinear interpolation of a solid voxel's
// opacity would let 13.5% through it) taken over the step's length,
// a_step = 1 - exp(-density * step / edge), before
//   c += (1 - A) c_step,  A += (1 - A) a_step.
// It stops at opacity 0.99 or where it leaves the grid (outside is empty).
// Cornell box with its camera, 320x320, anisotropic, 9 cones of 45 degrees,
// --levels auto, against a 4096-sample reference (relative RMSE, energy):
// 32^3 0.164 (0.93), 64^3 0.159 (0.91), 128^3 0.142 (0.94); before the
// density, the bias, this offset and the faces' colour mix: 0.197, 0.227,
// 0.185 at 4 levels (docs/vct.md, "Accuracy").
#include "vct_bindings.h"
layout(binding = ML_UNIT_VCT_VOXELS) uniform sampler3D u_voxels;
layout(binding = ML_UNIT_VCT_VOXEL_DIRS) uniform sampler3D u_voxel_dirs[6];  // +X -X +Y -Y +Z -Z (direction of travel)
uniform vec4 u_grid_origin_size;  // corner xyz, level-0 voxel edge w
uniform float u_grid_edge;        // level-0 voxels per axis
uniform float u_grid_max_lod;     // levels - 1
uniform int u_anisotropic;
uniform float u_cone_tan;         // tan(aperture / 2) of the diffuse cones
uniform int u_cone_count;
uniform vec4 u_cones[32];         // tangent-frame direction (z the normal), weight (sum pi)

const float kConeStep = 0.5;        // step, in voxels of the sampled level
// The level read is log2(diameter / level-0 voxel) - kLodBias. A mip level's
// box filter followed by trilinear interpolation spreads a point over a
// footprint whose standard deviation is half the level's voxel per axis; a
// disk of diameter D has D / 4. So the level whose voxel is half the cone's
// diameter (bias 1) matches the cone's cross-section, where bias 0 blurred
// it twice as wide: the finer the grid, the worse (Cornell box as above,
// 32^3 / 64^3 / 128^3: bias 0.5 0.165 / 0.176 / 0.173; 1 0.164 / 0.159 /
// 0.142; 1.5 0.173 / 0.166 / 0.150; bias 0, from the glTF's default view
// before the colour mix: 0.166 / 0.234 / 0.264 against 0.160 / 0.148 / 0.141
// at bias 1).
const float kLodBias = 1.0;
// Each sample sits off the surface along the normal by the larger of one
// level-0 voxel and kLevelOffset voxels of the level it reads, so a coarse
// sample's trilinear footprint does not take in the surface's own voxel
// (self-occlusion and self-lighting). Cornell box as above at 32^3 / 64^3 /
// 128^3: 0 0.164 / 0.159 / 0.143; 0.25 0.164 / 0.159 / 0.142; 0.5 0.163 /
// 0.171 / 0.155.
const float kLevelOffset = 0.25;
const float kConeOpaque = 0.99;
const float kPi = 3.14159265358979;

// A face's colour, its premultiplied radiance over its opacity (black when empty).
vec3 faceColour(vec4 f) { return f.a > 1e-6 ? f.rgb / f.a : vec3(0.0); }

vec4 sampleVoxels(vec3 uvw, float lod, vec3 d) {
  if (u_anisotropic == 0) return textureLod(u_voxels, uvw, lod);
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
  vec4 x = d.x >= 0.0 ? textureLod(u_voxel_dirs[0], uvw, lod) : textureLod(u_voxel_dirs[1], uvw, lod);
  vec4 y = d.y >= 0.0 ? textureLod(u_voxel_dirs[2], uvw, lod) : textureLod(u_voxel_dirs[3], uvw, lod);
  vec4 z = d.z >= 0.0 ? textureLod(u_voxel_dirs[4], uvw, lod) : textureLod(u_voxel_dirs[5], uvw, lod);
  vec3 alpha = clamp(vec3(x.a, y.a, z.a), 0.0, 1.0);
  vec3 share = w * -log(max(vec3(1.0) - alpha, vec3(1e-4)));
  float depth = share.x + share.y + share.z;
  if (depth <= 1e-6) return vec4(0.0);
  vec3 rgb = share.x * faceColour(x) + share.y * faceColour(y) + share.z * faceColour(z);
  float a = 1.0 - exp(-depth);
  return vec4(rgb * (a / depth), a);
}

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

// Premultiplied radiance along the cone (rgb) and its opacity (a), from the
// surface point P with normal N (the samples' offset: kLevelOffset).
vec4 traceCone(vec3 P, vec3 N, vec3 d, float tan_half) {
  float vs = u_grid_origin_size.w;
  float extent = vs * u_grid_edge;
  vec3 acc = vec3(0.0);
  float a = 0.0;
  float t = vs;
  for (int i = 0; i < 512 && a < kConeOpaque; ++i) {
    float diam = max(vs, 2.0 * t * tan_half);
    float lod = clamp(log2(diam / vs) - kLodBias, 0.0, u_grid_max_lod);
    float edge = vs * exp2(lod);  // the sampled level's voxel
    vec3 uvw = (P + N * max(vs, kLevelOffset * edge) + t * d - u_grid_origin_size.xyz) / extent;
    if (any(lessThan(uvw, vec3(0.0))) || any(greaterThan(uvw, vec3(1.0)))) break;
    vec4 s = sampleVoxels(uvw, lod, d);
    // Half the sampled level's voxel (the cone's diameter while the lod
    // follows it; steps of half the cone's width once the lod was clamped at
    // the coarsest level skipped voxels: streaks on the Cornell box's ceiling
    // at 128^3, cones leaving the grid through walls), shortened by the lift's
    // growth along the normal (2 kLevelOffset tan_half per unit of t), so the
    // sample itself moves at most half a voxel per step.
    float step = kConeStep * edge / (1.0 + 2.0 * kLevelOffset * tan_half);
    float a_step = 1.0 - exp(-opticalDensity(s.a) * step / edge);
    vec3 c_step = s.a > 1e-6 ? s.rgb * (a_step / s.a) : vec3(0.0);
    acc += (1.0 - a) * c_step;
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
// (1: nothing in the way).
vec4 traceDiffuse(vec3 P, vec3 N) {
  mat3 frame = tangentFrame(N);
  vec3 e = vec3(0.0);
  float occlusion = 0.0;
  for (int i = 0; i < u_cone_count; ++i) {
    vec4 r = traceCone(P, N, normalize(frame * u_cones[i].xyz), u_cone_tan);
    e += u_cones[i].w * r.rgb;
    occlusion += u_cones[i].w * r.a;
  }
  return vec4(e / kPi, 1.0 - occlusion / kPi);
}
