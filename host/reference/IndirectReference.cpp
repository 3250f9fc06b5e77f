#include "host/reference/IndirectReference.hpp"

#include <embree3/rtcore.h>
#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

#include "host/reference/LightSphereGrid.hpp"
#include "host/util/Error.hpp"
#include "host/util/SplitMix64.hpp"

namespace ml {
namespace {

// The scene in an Embree BVH; owns the device and scene handles.
class EmbreeScene {
 public:
  explicit EmbreeScene(const Scene& s) {
    device_ = rtcNewDevice(nullptr);
    if (!device_) throw std::runtime_error("Embree: rtcNewDevice failed (error " + std::to_string(rtcGetDeviceError(nullptr)) + ")");
    scene_ = rtcNewScene(device_);
    // Watertight intersection: a reference must not let rays slip between
    // triangles that share an edge.
    rtcSetSceneFlags(scene_, RTC_SCENE_FLAG_ROBUST);
    RTCGeometry g = rtcNewGeometry(device_, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* v = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                                                          3 * sizeof(float), s.vertices.size()));
    auto* idx = static_cast<unsigned*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                                                              3 * sizeof(unsigned), s.triangleCount()));
    for (std::size_t i = 0; i < s.vertices.size(); ++i)
      for (int c = 0; c < 3; ++c) v[3 * i + c] = s.vertices[i].position[c];
    std::copy(s.indices.begin(), s.indices.begin() + 3 * s.triangleCount(), idx);
    rtcCommitGeometry(g);
    rtcAttachGeometry(scene_, g);
    rtcReleaseGeometry(g);
    rtcCommitScene(scene_);
    if (rtcGetDeviceError(device_) != RTC_ERROR_NONE) throw std::runtime_error("Embree: building the scene failed");
  }
  ~EmbreeScene() {
    rtcReleaseScene(scene_);
    rtcReleaseDevice(device_);
  }
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;
  RTCScene get() const { return scene_; }

 private:
  RTCDevice device_ = nullptr;
  RTCScene scene_ = nullptr;
};

// A per-pixel stream (SplitMix64.hpp: seeded in a few instructions).
using PixelRng = SplitMix64;

struct Surface {
  glm::vec3 p, n, albedo;
};

glm::vec3 texel(const Texture& t, int x, int y) {
  x = ((x % t.width) + t.width) % t.width;
  y = ((y % t.height) + t.height) % t.height;
  const std::uint8_t* px = &t.rgba8[(std::size_t(y) * t.width + x) * 4];
  return glm::vec3(px[0], px[1], px[2]) / 255.0f;
}

// Bilinear, repeat, level 0; texel row 0 at v = 0 as SceneGpu uploads it.
glm::vec3 sampleTexture(const Texture& t, glm::vec2 uv) {
  const float fx = uv.x * t.width - 0.5f, fy = uv.y * t.height - 0.5f;
  if (!std::isfinite(fx) || !std::isfinite(fy)) return glm::vec3(1.0f);
  const float x0 = std::floor(fx), y0 = std::floor(fy), ax = fx - x0, ay = fy - y0;
  const int ix = int(std::fmod(x0, float(t.width))), iy = int(std::fmod(y0, float(t.height)));
  return glm::mix(glm::mix(texel(t, ix, iy), texel(t, ix + 1, iy), ax),
                  glm::mix(texel(t, ix, iy + 1), texel(t, ix + 1, iy + 1), ax), ay);
}

class Tracer {
 public:
  Tracer(const Scene& s, const std::vector<gpu::PointLight>& lights, const IndirectOptions& o)
      : scene_(s), bvh_(s), lights_(lights), grid_(lights), options_(o), tri_material_(s.triangleCount()) {
    for (const DrawBatch& b : s.batches)
      for (std::uint32_t t = b.first_index / 3; t < (b.first_index + b.index_count) / 3; ++t) tri_material_[t] = b.material;
    const glm::vec3 ext = s.bounds.empty() ? glm::vec3(1.0f) : s.bounds.max - s.bounds.min;
    eps_ = 1e-4f * std::max(glm::length(ext), 1e-6f);
    rtcInitIntersectContext(&ctx_);
  }

  bool intersect(const glm::vec3& org, const glm::vec3& dir, Surface& out) const;
  glm::vec3 directRadiance(const Surface& y) const;
  bool visible(const glm::vec3& from, const glm::vec3& to) const;
  glm::vec3 pixel(const glm::vec3& eye, const glm::vec3& dir, PixelRng& rng, bool& covered, float& noise_var) const;
  glm::dvec3 replicaSum(const Surface& x, unsigned s, PixelRng& rng) const;
  glm::vec3 pathRadiance(Surface y, PixelRng& rng) const;

 private:
  const Scene& scene_;
  EmbreeScene bvh_;
  const std::vector<gpu::PointLight>& lights_;
  LightSphereGrid grid_;
  IndirectOptions options_;
  std::vector<std::uint32_t> tri_material_;
  float eps_ = 0;
  RTCIntersectContext ctx_;
};

bool Tracer::intersect(const glm::vec3& org, const glm::vec3& dir, Surface& out) const {
  RTCRayHit rh{};
  rh.ray.org_x = org.x, rh.ray.org_y = org.y, rh.ray.org_z = org.z;
  rh.ray.dir_x = dir.x, rh.ray.dir_y = dir.y, rh.ray.dir_z = dir.z;
  rh.ray.tnear = 0.0f;
  rh.ray.tfar = std::numeric_limits<float>::infinity();
  rh.ray.mask = ~0u;
  rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
  RTCIntersectContext ctx = ctx_;
  rtcIntersect1(bvh_.get(), &ctx, &rh);
  if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) return false;
  const std::uint32_t t = rh.hit.primID;
  const Vertex* v[3];
  for (int k = 0; k < 3; ++k) v[k] = &scene_.vertices[scene_.indices[3 * t + k]];
  const float u = rh.hit.u, w = rh.hit.v, b0 = 1.0f - u - w;
  out.p = org + rh.ray.tfar * dir;
  // The side the ray arrived on is the geometric normal's business: a grazing
  // ray can meet a face whose interpolated normal leans towards it.
  const glm::vec3 ng(rh.hit.Ng_x, rh.hit.Ng_y, rh.hit.Ng_z);
  glm::vec3 n = b0 * v[0]->normal + u * v[1]->normal + w * v[2]->normal;
  if (!(glm::dot(n, n) > 0.0f)) n = ng;
  n = glm::normalize(n);
  out.n = glm::dot(ng, dir) > 0.0f ? -n : n;
  const Material& m = scene_.materials.at(tri_material_[t]);
  out.albedo = glm::vec3(m.base_color);
  if (m.base_color_texture >= 0 && m.base_color_texture < int(scene_.textures.size()))
    out.albedo *= sampleTexture(scene_.textures[std::size_t(m.base_color_texture)],
                                b0 * v[0]->uv + u * v[1]->uv + w * v[2]->uv);
  return true;
}

// The variance of a pixel's mean R = (n0 A + n1 B) / (n0 + n1), from its two
// independent replica means A and B: E[(A - B)^2] / 4 is Var(R) for equal
// replicas (and within a few percent for n0 = n1 + 1), summed over rgb; 0
// with a single sample (no second replica).
float replicaVariance(const glm::dvec3 (&sums)[2], const unsigned (&counts)[2], const glm::vec3& albedo) {
  if (counts[1] == 0) return 0.0f;
  const glm::dvec3 d = glm::dvec3(albedo) * (sums[0] / double(counts[0]) - sums[1] / double(counts[1]));
  return float(glm::dot(d, d) / 4.0);
}

bool Tracer::visible(const glm::vec3& from, const glm::vec3& to) const {
  const glm::vec3 d = to - from;
  const float len = glm::length(d);
  RTCRay r{};
  r.org_x = from.x, r.org_y = from.y, r.org_z = from.z;
  r.dir_x = d.x / len, r.dir_y = d.y / len, r.dir_z = d.z / len;
  r.tnear = 0.0f;
  r.tfar = len - eps_;
  r.mask = ~0u;
  RTCIntersectContext ctx = ctx_;
  rtcOccluded1(bvh_.get(), &ctx, &r);
  return r.tfar >= 0.0f;  // Embree sets tfar to -inf on a hit
}

// shading.glsl's computeLight, summed over the lights whose sphere holds y.
glm::vec3 Tracer::directRadiance(const Surface& y) const {
  glm::vec3 sum(0.0f);
  const glm::vec3 off = y.p + eps_ * y.n;
  grid_.forEachCandidate(y.p, [&](std::uint32_t i) {
    const gpu::PointLight& l = lights_[i];
    const glm::vec3 pos(l.position_radius.x, l.position_radius.y, l.position_radius.z);
    glm::vec3 L = pos - y.p;
    const float d = glm::length(L);
    if (!(d < l.position_radius.w)) return;
    L /= std::max(d, 1e-20f);
    const float att = std::clamp(1.0f - d / l.position_radius.w, 0.0f, 1.0f);
    const float cos_i = std::clamp(glm::dot(y.n, L), 0.0f, 1.0f);
    if (cos_i <= 0.0f || att <= 0.0f) return;
    if (options_.shadow_rays && !visible(off, pos)) return;
    sum += glm::vec3(l.color.x, l.color.y, l.color.z) * cos_i * att * att;
  });
  return y.albedo * sum;
}

glm::vec3 Tracer::pixel(const glm::vec3& eye, const glm::vec3& dir, PixelRng& rng, bool& covered,
                        float& noise_var) const {
  Surface x;
  noise_var = 0.0f;
  covered = intersect(eye, dir, x);
  if (!covered) return glm::vec3(0.0f);
  // Two independent replicas of ceil(s/2) and floor(s/2) samples: their means'
  // difference estimates the pixel's noise without bias, which the strata of
  // one set cannot (they are not independent).
  const unsigned s = options_.samples, counts[2] = {(s + 1) / 2, s / 2};
  glm::dvec3 sums[2] = {glm::dvec3(0.0), glm::dvec3(0.0)};
  for (unsigned k = 0; k < 2; ++k) sums[k] = replicaSum(x, counts[k], rng);
  noise_var = replicaVariance(sums, counts, x.albedo);
  return x.albedo * glm::vec3((sums[0] + sums[1]) / double(s));
}

// A cosine-weighted direction around n from two uniform numbers (Malley), in
// the orthonormal basis around n of Duff et al. 2017.
glm::vec3 cosineDirection(const glm::vec3& n, float u1, float u2) {
  const float sign = std::copysign(1.0f, n.z), a = -1.0f / (sign + n.z), b = n.x * n.y * a;
  const glm::vec3 t1(1.0f + sign * n.x * n.x * a, sign * b, -sign * n.x), t2(b, sign + n.y * n.y * a, -n.y);
  const float r = std::sqrt(u1), phi = 6.28318530718f * u2;
  return glm::normalize(r * std::cos(phi) * t1 + r * std::sin(phi) * t2 + std::sqrt(std::max(0.0f, 1.0f - u1)) * n);
}

// The sum of `s` Latin-hypercube, cosine-weighted bounces from x: stratum i
// in u1, a shuffled stratum in u2.
glm::dvec3 Tracer::replicaSum(const Surface& x, unsigned s, PixelRng& rng) const {
  glm::dvec3 sum(0.0);
  if (s == 0) return sum;
  std::vector<unsigned> perm(s);
  std::iota(perm.begin(), perm.end(), 0u);
  for (unsigned i = s; i > 1; --i) std::swap(perm[i - 1], perm[rng.next() % i]);
  const glm::vec3 org = x.p + eps_ * x.n;
  for (unsigned i = 0; i < s; ++i) {
    const float u1 = (float(i) + rng.uniform()) / float(s), u2 = (float(perm[i]) + rng.uniform()) / float(s);
    Surface y;
    if (intersect(org, cosineDirection(x.n, u1, u2), y)) sum += glm::dvec3(pathRadiance(y, rng));
  }
  return sum;
}

// The radiance a path sample brings back from its first hit y: y's direct
// light, then, for bounces > 1, the light of one cosine-weighted continuation
// per further bounce, weighted by the albedos along the way (each continuation
// is the estimate of albedo/pi * integral of B cos, as at x).
glm::vec3 Tracer::pathRadiance(Surface y, PixelRng& rng) const {
  glm::vec3 sum = directRadiance(y), throughput(1.0f);
  for (unsigned b = 1; b < options_.bounces; ++b) {
    throughput *= y.albedo;
    const float u1 = rng.uniform(), u2 = rng.uniform();
    Surface z;
    if (!intersect(y.p + eps_ * y.n, cosineDirection(y.n, u1, u2), z)) break;
    sum += throughput * directRadiance(z);
    y = z;
  }
  return sum;
}

}  // namespace

IndirectImage traceIndirectReference(const Scene& scene, const std::vector<gpu::PointLight>& lights,
                                     const Camera& camera, unsigned width, unsigned height,
                                     const IndirectOptions& options) {
  if (options.samples == 0) throw UserError("indirect reference: samples must be at least 1");
  if (options.bounces < 1 || options.bounces > kMaxIndirectBounces)
    throw UserError("indirect reference: bounces must be 1.." + std::to_string(kMaxIndirectBounces));
  if (width == 0 || height == 0) throw UserError("indirect reference: empty image");
  const auto start = std::chrono::steady_clock::now();
  IndirectImage img;
  img.width = width;
  img.height = height;
  img.rgba.assign(std::size_t(width) * height * 4, 0.0f);
  img.noise_var.assign(std::size_t(width) * height, 0.0f);
  const Tracer tracer(scene, lights, options);
  const glm::mat4 proj = camera.projection(float(width) / float(height));
  const glm::mat4 inv_view = glm::inverse(camera.view());
  // common.glsl windowToView: view-space ray through the pixel centre.
  tbb::parallel_for(tbb::blocked_range<unsigned>(0, height), [&](const tbb::blocked_range<unsigned>& rows) {
    for (unsigned y = rows.begin(); y < rows.end(); ++y)
      for (unsigned x = 0; x < width; ++x) {
        const glm::vec2 ndc = (glm::vec2(x, y) + 0.5f) / glm::vec2(width, height) * 2.0f - 1.0f;
        const glm::vec2 xy = (ndc + glm::vec2(proj[2][0], proj[2][1])) / glm::vec2(proj[0][0], proj[1][1]);
        const glm::vec3 dir = glm::normalize(glm::vec3(inv_view * glm::vec4(xy, -1.0f, 0.0f)));
        const std::size_t i = std::size_t(y) * width + x;
        PixelRng rng{options.seed ^ (0xD1B54A32D192ED03ull * (i + 1))};
        bool covered = false;
        const glm::vec3 c = tracer.pixel(camera.eye, dir, rng, covered, img.noise_var[i]);
        img.rgba[4 * i + 0] = c.r;
        img.rgba[4 * i + 1] = c.g;
        img.rgba[4 * i + 2] = c.b;
        img.rgba[4 * i + 3] = covered ? 1.0f : 0.0f;
      }
  });
  if (options.samples < 2) img.noise_var.clear();  // one replica: no estimate
  img.ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count();
  return img;
}

IndirectError indirectRelRmse(const std::vector<float>& image, const std::vector<float>& reference) {
  if (image.size() != reference.size() || image.size() % 4 != 0)
    throw std::invalid_argument("indirectRelRmse: images of different sizes");
  IndirectError e;
  double err = 0, norm = 0;
  for (std::size_t i = 0; i < image.size(); i += 4) {
    const bool a = image[i + 3] > 0, r = reference[i + 3] > 0;
    if (a != r) ++e.mismatched;
    if (!a || !r) continue;
    ++e.pixels;
    for (std::size_t c = 0; c < 3; ++c) {
      const double d = double(image[i + c]) - double(reference[i + c]);
      err += d * d;
      norm += double(reference[i + c]) * double(reference[i + c]);
    }
  }
  if (norm > 0) e.rel_rmse = std::sqrt(err / norm);
  return e;
}

IndirectComparison compareWithReference(const std::vector<float>& image, const IndirectImage& reference) {
  IndirectComparison c;
  c.error = indirectRelRmse(image, reference.rgba);
  if (reference.noise_var.size() * 4 != reference.rgba.size() || c.error.rel_rmse < 0) return c;
  double var = 0, norm = 0;
  for (std::size_t p = 0; p < reference.noise_var.size(); ++p) {
    if (!(image[4 * p + 3] > 0) || !(reference.rgba[4 * p + 3] > 0)) continue;
    var += reference.noise_var[p];
    for (std::size_t k = 0; k < 3; ++k) norm += double(reference.rgba[4 * p + k]) * double(reference.rgba[4 * p + k]);
  }
  if (!(norm > 0)) return c;
  c.ref_noise = std::sqrt(var / norm);
  c.corrected = std::sqrt(std::max(0.0, c.error.rel_rmse * c.error.rel_rmse - var / norm));
  return c;
}

}  // namespace ml
