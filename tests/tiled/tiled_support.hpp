#pragma once
// Shared by the tiled culling tests: random views over a random "scene" depth
// with lights in front, behind, around the eye and huge; the OpenCL culler run
// with poisoned outputs (grid layout and no write past the total checked) and
// the C++ reference, both as per-tile lists.
#include <gtest/gtest.h>

#include <glm/gtc/matrix_transform.hpp>

#include <algorithm>
#include <random>
#include <vector>

#include "host/scene/Camera.hpp"
#include "host/scene/LightSet.hpp"
#include "host/tiled/TileCullerReference.hpp"
#include "host/tiled/TileLightCuller.hpp"
#include "support/RandomView.hpp"
#include "support/TestDevice.hpp"

namespace ml::test {

using CullCase = RandomView;

// A random view (support/RandomView.hpp) with rectangles within 30 units.
inline CullCase randomCase(std::mt19937_64& rng, unsigned w, unsigned h, std::size_t n_lights) {
  return randomView(rng, w, h, n_lights);
}

// Runs `culler` on the case with poisoned outputs and checks the grid's
// layout; each tile's list in the kernel's order, or sorted.
inline std::vector<std::vector<std::uint32_t>> runCuller(TileLightCuller& culler, const CullCase& c,
                                                         bool sorted = true) {
  ClRuntime& rt = test::runtime();
  auto& q = rt.queue();
  const auto cam = c.camera.params(c.width, c.height);
  cl::Buffer lights(rt.context(), CL_MEM_READ_ONLY, std::max<std::size_t>(16, c.lights.size() * 32));
  if (!c.lights.empty()) q.enqueueWriteBuffer(lights, CL_TRUE, 0, c.lights.size() * 32, c.lights.data());
  cl::Buffer depth(rt.context(), CL_MEM_READ_ONLY, c.depth.size() * 4);
  q.enqueueWriteBuffer(depth, CL_TRUE, 0, c.depth.size() * 4, c.depth.data());
  const auto n = std::uint32_t(c.lights.size());
  const std::uint32_t total = culler.count(q, lights, n, cam, &depth);
  const unsigned tiles = culler.tileGrid().count();
  cl::Buffer grid(rt.context(), CL_MEM_READ_WRITE, tiles * 8);
  cl::Buffer indices(rt.context(), CL_MEM_READ_WRITE, std::max<std::size_t>(16, total * 4 + 64));
  q.enqueueFillBuffer(grid, 0xDEADBEEFu, 0, tiles * 8);  // poison
  q.enqueueFillBuffer(indices, 0xDEADBEEFu, 0, std::max<std::size_t>(16, total * 4 + 64));
  culler.fill(q, lights, n, cam, grid, indices);
  std::vector<gpu::LightRange> g(tiles);
  std::vector<std::uint32_t> idx(total + 16);
  q.enqueueReadBuffer(grid, CL_TRUE, 0, tiles * 8, g.data());
  q.enqueueReadBuffer(indices, CL_TRUE, 0, idx.size() * 4, idx.data());
  // Nothing written past the total.
  for (std::size_t i = total; i < idx.size(); ++i) EXPECT_EQ(idx[i], 0xDEADBEEFu) << "write past the list end";
  std::vector<std::vector<std::uint32_t>> lists(tiles);
  std::uint32_t expected_offset = 0;
  for (unsigned t = 0; t < tiles; ++t) {
    EXPECT_EQ(g[t].offset, expected_offset) << "tile " << t;
    expected_offset += g[t].count;
    if (g[t].offset + g[t].count > total) {
      ADD_FAILURE() << "tile " << t << " out of range";
      continue;
    }
    lists[t].assign(idx.begin() + g[t].offset, idx.begin() + g[t].offset + g[t].count);
    if (sorted) std::sort(lists[t].begin(), lists[t].end());
  }
  EXPECT_EQ(expected_offset, total);
  return lists;
}

inline std::vector<std::vector<std::uint32_t>> runKernel(const CullCase& c, unsigned tile, TileDepthMode mode,
                                                         KernelShape shape,
                                                         TileCullAlgorithm algo = TileCullAlgorithm::ChunkCounts,
                                                         bool sorted = true) {
  TileLightCuller culler(test::runtime(), tile, mode, shape, algo);
  EXPECT_EQ(culler.shape(), shape);
  return runCuller(culler, c, sorted);
}

inline std::vector<std::vector<std::uint32_t>> runReference(const CullCase& c, unsigned tile, TileDepthMode mode) {
  TileGrid g{tile, c.width, c.height};
  const auto ref = cullTilesReference(c.lights, c.depth.data(), c.camera.params(c.width, c.height), g, mode);
  std::vector<std::vector<std::uint32_t>> lists(g.count());
  for (unsigned t = 0; t < g.count(); ++t)
    lists[t].assign(ref.indices.begin() + ref.grid[t].offset, ref.indices.begin() + ref.grid[t].offset + ref.grid[t].count);
  return lists;
}

}  // namespace ml::test
