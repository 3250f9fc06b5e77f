#include "host/vct/VoxelMipsReference.hpp"

#include <stdexcept>

namespace ml::vct {

namespace {

using F4 = gpu::ml_float4;

F4 add(F4 a, F4 b) { return {a.x + b.x, a.y + b.y, a.z + b.z, a.w + b.w}; }
F4 scale(F4 a, float s) { return {a.x * s, a.y * s, a.z * s, a.w * s}; }
// front + (1 - front.a) * back, as the kernel's over().
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

F4 mean8(const Children& k) {
  const std::size_t sy = k.sy, sz = k.sz;
  const F4 a = add(add(k.at(0), k.at(1)), add(k.at(sy), k.at(sy + 1)));
  const F4 b = add(add(k.at(sz), k.at(sz + 1)), add(k.at(sz + sy), k.at(sz + sy + 1)));
  return scale(add(a, b), 0.125f);
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
    for (std::size_t p = 0; p < std::size_t(ep) * ep * ep; ++p) parent[p] = mean8(childrenOf(child, ep, p));
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
