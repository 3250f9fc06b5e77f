// The tile light culling cases of the kernel bench (kernel_bench_cases.hpp):
// count + fill of the OpenCL culler (host/tiled/TileLightCuller.hpp) at
// 1920 x 1080, 16-pixel tiles, min/max depth bounds, over a random view
// (sloped depth rectangles over sky) with lights of radius 0.3-2 around it.
// Peers in the same run, on the same lights and depth: the previous culler
// (an atomic per list entry, TileCullAlgorithm::PairAtomics) and the C++
// culler on TBB (cullTilesReference), which is also the check: each tile's
// list, sorted, must equal the reference's. bytes counts the depth buffer and
// the lights read once.
#include <algorithm>
#include <memory>
#include <random>

#include "host/compute/HostIo.hpp"
#include "host/tiled/TileCullerReference.hpp"
#include "host/tiled/TileLightCuller.hpp"
#include "kernel_bench_cases.hpp"
#include "tests/support/RandomView.hpp"

namespace ml::kbench {

using compute::download;
using compute::upload;

namespace {

constexpr unsigned kW = 1920, kH = 1080, kTile = 16;

struct CullInputs {
  CullInputs(Bench& b, std::size_t n_lights) {
    std::mt19937_64 rng(1234 + n_lights);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    view.width = kW;
    view.height = kH;
    view.camera.eye = {0, 1, 0};
    view.camera.center = {0, 1, -1};
    view.camera.fovy_degrees = 60;
    view.camera.near_plane = 0.1f;
    view.camera.far_plane = 100.f;
    test::addDepthRectangles(view, rng, {});
    const glm::mat4 inv_view = glm::inverse(view.camera.view());
    for (std::size_t i = 0; i < n_lights; ++i) {
      const glm::vec4 v{u(rng) * 40 - 20, u(rng) * 24 - 12, -0.5f - u(rng) * 35, 1};
      view.lights.push_back(makeLight(glm::vec3(inv_view * v), 0.3f + u(rng) * 1.7f, {u(rng), u(rng), u(rng)}));
    }
    cam = view.cam();
    lights = upload(b.rt.context(), b.q, view.lights);
    depth = upload(b.rt.context(), b.q, view.depth);
    reference = cullTilesReference(view.lights, view.depth.data(), cam, grid, TileDepthMode::MinMax, true);
    grid_buf = cl::Buffer(b.rt.context(), CL_MEM_READ_WRITE, std::size_t(grid.count()) * 8);
    indices = cl::Buffer(b.rt.context(), CL_MEM_READ_WRITE, std::max<std::size_t>(16, reference.indices.size() * 4));
  }
  test::RandomView view;
  gpu::CameraParams cam{};
  TileGrid grid{kTile, kW, kH};
  TileLists reference;
  cl::Buffer lights, depth, grid_buf, indices;
  std::uint32_t total = 0;  // of the culler's last count()
};

CullInputs& inputs(Bench& b, std::size_t n) {
  return b.slot.get<CullInputs>({3, n}, [&] { return std::make_unique<CullInputs>(b, n); });
}

// count + fill; a total past the reference's buffer is reported by check().
void cull(Bench& b, TileLightCuller& culler, CullInputs& in) {
  const auto n = std::uint32_t(in.view.lights.size());
  in.total = culler.count(b.q, in.lights, n, in.cam, &in.depth);
  if (in.total > in.reference.indices.size()) return;
  culler.fill(b.q, in.lights, n, in.cam, in.grid_buf, in.indices);
}

std::string check(Bench& b, CullInputs& in) {
  const auto& ref = in.reference;
  if (in.total != ref.indices.size())
    return "list total " + std::to_string(in.total) + ", reference " + std::to_string(ref.indices.size());
  const auto got_grid = download<gpu::LightRange>(b.q, in.grid_buf, ref.grid.size());
  const auto got = download<std::uint32_t>(b.q, in.indices, ref.indices.size());
  for (std::size_t t = 0; t < ref.grid.size(); ++t) {
    const auto g = got_grid[t], r = ref.grid[t];
    if (g.offset != r.offset || g.count != r.count)
      return "tile " + std::to_string(t) + ": range " + std::to_string(g.offset) + "+" + std::to_string(g.count) +
             ", reference " + std::to_string(r.offset) + "+" + std::to_string(r.count);
    std::vector<std::uint32_t> list(got.begin() + g.offset, got.begin() + g.offset + g.count);
    std::sort(list.begin(), list.end());
    if (!std::equal(list.begin(), list.end(), ref.indices.begin() + r.offset))
      return "tile " + std::to_string(t) + ": its light list differs from the reference's";
  }
  return "";
}

void addDeviceCase(Bench& b, std::size_t n, const std::string& name, TileCullAlgorithm algo) {
  auto culler = std::make_shared<TileLightCuller>(b.rt, kTile, TileDepthMode::MinMax, b.tune.shape, algo);
  const double bytes = 4.0 * kW * kH + 32.0 * double(n);
  b.h.add(Case(name + ".minmax.1080p", n, bytes)
              .before([&b, n] {
                compute::poison(b.q, inputs(b, n).grid_buf);
                compute::poison(b.q, inputs(b, n).indices);
              })
              .run([&b, n, culler] { cull(b, *culler, inputs(b, n)); })
              .checkedBy([&b, n] { return check(b, inputs(b, n)); })
              .profiledBy([&b, n, culler](ClPassTimer& t) {
                CullInputs& in = inputs(b, n);
                const auto count = std::uint32_t(in.view.lights.size());
                if (culler->count(b.q, in.lights, count, in.cam, &in.depth, &t) <= in.reference.indices.size())
                  culler->fill(b.q, in.lights, count, in.cam, in.grid_buf, in.indices, &t);
              }));
}

}  // namespace

void addTileCullCases(Bench& b, std::size_t n) {
  addDeviceCase(b, n, "tile_cull", TileCullAlgorithm::ChunkCounts);
  addDeviceCase(b, n, "tile_cull_pair_atomics", TileCullAlgorithm::PairAtomics);
  b.h.add(Case("tile_cull_cpp_tbb.minmax.1080p", n, 4.0 * kW * kH + 32.0 * double(n))
              .onHost()
              .run([&b, n] {
                CullInputs& in = inputs(b, n);
                benchmark::DoNotOptimize(
                    cullTilesReference(in.view.lights, in.view.depth.data(), in.cam, in.grid, TileDepthMode::MinMax));
              }));
}

}  // namespace ml::kbench
