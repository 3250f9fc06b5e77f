// The 1080p-sized cases of the kernel bench (kernel_bench_cases.hpp): what
// the tiled and clustered passes feed the primitives at 1920 x 1080.
#include <algorithm>
#include <limits>
#include <memory>
#include <numeric>
#include <random>

#include "host/compute/HostIo.hpp"
#include "kernel_bench_cases.hpp"

namespace ml::kbench {

using compute::download;
using compute::upload;

namespace {

constexpr std::size_t kW = 1920, kH = 1080, kN = kW * kH, kTile = 16;
constexpr std::size_t kTiles = ((kW + kTile - 1) / kTile) * ((kH + kTile - 1) / kTile);

struct FrameInputs {
  FrameInputs(const cl::Context& ctx, cl::CommandQueue& q) : in(ctx, q, kN, 99) {
    // Variable segment sizes (1..511, mean 256), as per-tile light lists are.
    std::mt19937 rng(7);
    offsets.push_back(0);
    while (offsets.back() < kN) offsets.push_back(std::min<std::uint32_t>(kN, offsets.back() + 1 + rng() % 511));
    offsets_buf = upload(ctx, q, offsets);
    for (std::uint32_t i = 0; i <= kN; i += 256) fixed.push_back(i);
    if (fixed.back() != kN) fixed.push_back(kN);
    depth.resize(kN);
    std::uniform_real_distribution<float> u(0.f, 1.f);
    for (auto& d : depth) d = u(rng);
    depth_buf = upload(ctx, q, depth);
    mn = cl::Buffer(ctx, CL_MEM_READ_WRITE, kTiles * 4);
    mx = cl::Buffer(ctx, CL_MEM_READ_WRITE, kTiles * 4);
  }
  SizeInputs in;
  std::vector<std::uint32_t> offsets, fixed;  // variable and 256-element segments
  cl::Buffer offsets_buf;
  std::vector<float> depth;
  cl::Buffer depth_buf, mn, mx;
};

FrameInputs& frame(Bench& b) {
  return b.slot.get<FrameInputs>({1, kN}, [&] { return std::make_unique<FrameInputs>(b.rt.context(), b.q); });
}

std::string checkSegments(Bench& b, const std::vector<std::uint32_t>& offsets) {
  SizeInputs& in = frame(b).in;
  return checkSegmentedPairs(in.keys, offsets, download<std::uint32_t>(b.q, in.work, kN),
                             download<std::uint32_t>(b.q, in.vwork, kN));
}

std::string checkTileMinMax(Bench& b) {
  FrameInputs& f = frame(b);
  const auto got_min = download<float>(b.q, f.mn, kTiles), got_max = download<float>(b.q, f.mx, kTiles);
  const std::size_t tx = (kW + kTile - 1) / kTile;
  for (std::size_t t = 0; t < kTiles; ++t) {
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    const std::size_t x0 = (t % tx) * kTile, y0 = (t / tx) * kTile;
    for (std::size_t y = y0; y < std::min(kH, y0 + kTile); ++y)
      for (std::size_t x = x0; x < std::min(kW, x0 + kTile); ++x) {
        lo = std::min(lo, f.depth[y * kW + x]);
        hi = std::max(hi, f.depth[y * kW + x]);
      }
    if (got_min[t] != lo || got_max[t] != hi)
      return "tile " + std::to_string(t) + ": min/max " + std::to_string(got_min[t]) + "/" +
             std::to_string(got_max[t]) + ", expected " + std::to_string(lo) + "/" + std::to_string(hi);
  }
  return "";
}

void addSegmented(Bench& b) {
  auto restore = [&b] { frame(b).in.restorePairs(); };
  b.h.add(Case("segmented_sort.pairs.seg256.1080p", kN, 16.0 * kN)
              .before(restore)
              .run([&b] { b.segsort.sortFixed(b.q, frame(b).in.work, &frame(b).in.vwork, kN, kTile * kTile); })
              .checkedBy([&b] { return checkSegments(b, frame(b).fixed); })
              .profiledBy([&b](ClPassTimer& t) {
                b.segsort.sortFixed(b.q, frame(b).in.work, &frame(b).in.vwork, kN, kTile * kTile, &t);
              }));
  b.h.add(Case("segmented_sort.pairs.var256.1080p", kN, 16.0 * kN)
              .before(restore)
              .run([&b] {
                FrameInputs& f = frame(b);
                b.segsort.sort(b.q, f.in.work, &f.in.vwork, kN, f.offsets_buf, f.offsets.size() - 1);
              })
              .checkedBy([&b] { return checkSegments(b, frame(b).offsets); }));
}

}  // namespace

void add1080pCases(Bench& b) {
  b.h.add(Case("scan.exclusive.u32.1080p", kN, 8.0 * kN)
              .before([&b] { frame(b).in.poisonWork(); })
              .run([&b] { b.scanner.exclusive(b.q, frame(b).in.src, frame(b).in.work, kN); })
              .checkedBy([&b] {
                SizeInputs& in = frame(b).in;
                std::vector<std::uint32_t> want(kN);
                std::exclusive_scan(in.keys.begin(), in.keys.end(), want.begin(), 0u);
                return firstDifference("exclusive scan", download<std::uint32_t>(b.q, in.work, kN), want);
              }));
  addSegmented(b);
  b.h.add(Case("tile_minmax.depth16.1080p", kN, 4.0 * kN)
              .before([&b] {
                compute::poison(b.q, frame(b).mn);
                compute::poison(b.q, frame(b).mx);
              })
              .run([&b] {
                FrameInputs& f = frame(b);
                b.reducer.tileMinMax(b.q, f.depth_buf, kW, kH, kTile, f.mn, f.mx);
              })
              .checkedBy([&b] { return checkTileMinMax(b); }));
}

}  // namespace ml::kbench
