#include "host/vct/VoxelMipsReference.hpp"

#include <algorithm>
#include <array>
#include <stdexcept>

namespace ml::vct {

namespace {

using F4 = gpu::ml_float4;

F4 add(F4 a, F4 b) { return {a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w}; }
F4 scale(F4 a, float s) { return {a.x * s, a.y * s, a.z * s, a.w * s}; }
// front + (1 - front.a) * back, as each half of the kernel's over8().
F4 over(F4 f, F4 b) { return add(f, scale(b, 1.0f - f.w)); }

// Parent (x, y, z)'s child (0, 0, 0) in a level of edge ec, and the strides.
struct Children {
  const F4* c;
  std::size_t sy, sz;
  const F4& at(std::size_t i) const { return c[i]; }
};

Children childrenOf(const F4* level, unsigned ep, std::size_t p) {
  const std::size_t x = p % ep, y = p / ep % ep, z = p / (std::size_t(ep) * ep);
  const std::size_t ec = 2 * std::size_t(ep);
  return {level + 2 * x + ec * (2 * y + ec * 2 * z), ec, ec * ec};
}

// As the kernel's AXIS_OVERLAP, AXIS_MAX and iso_parent(): pairs
// (f[i], b[i]) of one axis.
using Quad = std::array<F4, 4>;
float axisOverlap(const Quad& f, const Quad& b) {
  return (f[0].w * b[0].w + f[1].w * b[1].w) + (f[2].w * b[2].w + f[3].w * b[3].w);
}

// The kernel's PAIR_MAX: over(f, b) where b.a S(f) >= f.a S(b) (S: (r + g) + b), else over(b, f).
float rgbSum(F4 a) { return (a.x + a.y) + a.z; }
F4 brighterOrder(F4 f, F4 b) { return b.w * rgbSum(f) >= f.w * rgbSum(b) ? over(f, b) : over(b, f); }

F4 axisMax(const Quad& f, const Quad& b) {
  F4 q[4];
  for (int i = 0; i < 4; ++i) q[i] = brighterOrder(f[i], b[i]);
  return add(add(q[0], q[1]), add(q[2], q[3]));
}

F4 isoParent(const Children& c) {
  const std::size_t sy = c.sy, sz = c.sz;
  const std::array<F4, 8> k{c.at(0),  c.at(1),      c.at(sy),      c.at(sy + 1),
                            c.at(sz), c.at(sz + 1), c.at(sz + sy), c.at(sz + sy + 1)};
  const Quad xf{k[0], k[2], k[4], k[6]}, xb{k[1], k[3], k[5], k[7]};
  const Quad yf{k[0], k[1], k[4], k[5]}, yb{k[2], k[3], k[6], k[7]};
  const Quad zf{k[0], k[1], k[2], k[3]}, zb{k[4], k[5], k[6], k[7]};
  const float dx = axisOverlap(xf, xb), dy = axisOverlap(yf, yb), dz = axisOverlap(zf, zb);
  const F4 axis = dz < std::min(dx, dy) ? axisMax(zf, zb) : (dy < dx ? axisMax(yf, yb) : axisMax(xf, xb));
  return scale(axis, 0.25f);
}

F4 anisoDir(const Children& k, unsigned d) {
  const unsigned axis = d / 2;
  const std::size_t s = axis == 0 ? 1 : axis == 1 ? k.sy : k.sz;
  const std::size_t u = axis == 0 ? k.sy : 1;
  const std::size_t v = axis == 2 ? k.sy : k.sz;
  const std::size_t f = (d & 1) ? s : 0, b = s - f;
  const F4 p0 = over(k.at(f), k.at(b)), p1 = over(k.at(u + f), k.at(u + b));
  const F4 p2 = over(k.at(v + f), k.at(v + b)), p3 = over(k.at(u + v + f), k.at(u + v + b));
  return scale(add(add(p0, p1), add(p2, p3)), 0.25f);
}

void checkSize(std::size_t have, std::size_t want, const char* what) {
  if (have < want) throw std::invalid_argument(std::string(what) + ": volume smaller than the grid");
}

}  // namespace

void mipIsotropicTwin(std::vector<F4>& radiance, unsigned edge, unsigned levels) {
  checkSize(radiance.size(), gpu::voxel_level_offset(edge, levels), "mipIsotropicTwin");
  for (unsigned l = 1; l < levels; ++l) {
    const unsigned ep = edge >> l;
    const F4* child = radiance.data() + gpu::voxel_level_offset(edge, l - 1);
    F4* parent = radiance.data() + gpu::voxel_level_offset(edge, l);
    for (std::size_t p = 0; p < std::size_t(ep) * ep * ep; ++p) parent[p] = isoParent(childrenOf(child, ep, p));
  }
}

void mipAnisotropicTwin(const std::vector<F4>& radiance, std::vector<F4>& aniso, unsigned edge, unsigned levels) {
  checkSize(radiance.size(), std::size_t(edge) * edge * edge, "mipAnisotropicTwin");
  aniso.resize(gpu::voxel_aniso_index(edge, levels, 0, 0));
  for (unsigned l = 1; l < levels; ++l) {
    const unsigned ep = edge >> l;
    const std::size_t n = std::size_t(ep) * ep * ep;
    for (unsigned d = 0; d < ML_VOXEL_DIRECTIONS; ++d) {
      const F4* child = l == 1 ? radiance.data() : aniso.data() + gpu::voxel_aniso_index(edge, l - 1, d, 0);
      F4* parent = aniso.data() + gpu::voxel_aniso_index(edge, l, d, 0);
      for (std::size_t p = 0; p < n; ++p) parent[p] = anisoDir(childrenOf(child, ep, p), d);
    }
  }
}

}  // namespace ml::vct
