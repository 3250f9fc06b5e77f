// manylights-kernel-bench: the compute primitives against their peers, on the
// same device and the same inputs, in one run.
//
//   manylights-kernel-bench [--sizes 65536,1048576,...] [--reps N] [--quick] [--json F] [--device D]
//                           [--filter TEXT[,TEXT...]] [--profile] [--shape auto|cpu|gpu] [--chunks N] [--radix-bits B]
//                           [--sort-chunk C]
//
// Per size: copy bandwidth four ways (host memcpy on one core and on both,
// clEnqueueCopyBuffer, an OpenCL uint4 copy kernel; the fastest is the
// physical limit), our radix sort (uint32 keys, pairs, uint64 keys), our bitonic sort,
// Boost.Compute's sort on our OpenCL queue, std::sort and
// std::sort(std::execution::par) (TBB) on the host, and scan / reduce /
// compaction throughput. At 1080p (1920 x 1080 elements): scan, segmented sort
// (16x16-tile-sized segments) and per-tile depth min/max. Each case runs once
// untimed (compiles, page faults), then --reps times; the median is reported
// (the best too, in the table). Sort inputs are restored before every rep,
// outside the timed region. `bytes_per_second` counts the minimum traffic of
// the operation: a sort or scan reads and writes each element once. The radix
// sort is also stated as a share of its bandwidth bound: one device copy of
// the same keys per pass, timed in the same run (see "bandwidth bound").
#include <CL/opencl.hpp>

#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <execution>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <memory>
#include <numeric>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "host/cl/ClPassTimer.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/compute/BitonicSort.hpp"
#include "host/compute/Compact.hpp"
#include "host/compute/Distributions.hpp"
#include "host/compute/HostIo.hpp"
#include "host/compute/RadixSort.hpp"
#include "host/compute/Reduce.hpp"
#include "host/compute/Scan.hpp"
#include "host/compute/SegmentedSort.hpp"
#include "host/util/Error.hpp"
#include "host/util/PassTimings.hpp"
#include "BenchCommon.hpp"

namespace ml::bench {
void boostComputeSortU32(cl_command_queue queue, cl_mem buffer, std::size_t n);
}

namespace {

using namespace ml;
using namespace ml::compute;
using Clock = std::chrono::steady_clock;

struct Result {
  std::string name;
  std::size_t n = 0;
  double seconds = 0;  // median
  double best = 0;
  double items_per_second = 0;
  double bytes_per_second = 0;
};

struct Bench {
  int reps = 5;
  std::string filter;  // comma-separated: run only cases whose name contains one of these

  bool wanted(const std::string& name) const {
    if (filter.empty()) return true;
    std::stringstream ss(filter);
    std::string part;
    while (std::getline(ss, part, ','))
      if (!part.empty() && name.find(part) != std::string::npos) return true;
    return false;
  }
  std::vector<Result> results;

  // Runs `setup` (untimed) and `body` (timed) once as warm-up, then `reps`
  // times; records the median.
  void run(const std::string& name, std::size_t n, double bytes, const std::function<void()>& setup,
           const std::function<void()>& body, int reps_override = 0) {
    if (!wanted(name)) return;
    setup();
    body();
    std::vector<double> times;
    const int r = reps_override ? reps_override : reps;
    for (int i = 0; i < r; ++i) {
      setup();
      auto t0 = Clock::now();
      body();
      times.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
    }
    std::sort(times.begin(), times.end());
    Result res;
    res.name = name;
    res.n = n;
    res.seconds = times[times.size() / 2];
    res.best = times.front();
    res.items_per_second = n / res.seconds;
    res.bytes_per_second = bytes / res.seconds;
    results.push_back(res);
    std::printf("%-34s %10zu %11.3f %11.3f %12.2f %9.2f\n", name.c_str(), n, res.seconds * 1e3, res.best * 1e3,
                res.items_per_second * 1e-6, res.bytes_per_second * 1e-9);
    std::fflush(stdout);
  }

  const Result* find(const std::string& name, std::size_t n) const {
    for (const auto& r : results)
      if (r.name == name && r.n == n) return &r;
    return nullptr;
  }
};

std::string sizeLabel(std::size_t n) {
  for (int b = 0; b < 63; ++b)
    if (n == (std::size_t(1) << b)) return "2^" + std::to_string(b);
  return std::to_string(n);
}

// The OpenCL copy kernel of the limit: one uint4 per work-item, which is the
// fastest shape measured on PoCL (pocl-performance.md) and the usual one on GPUs.
const char* kCopySource = R"CL(
__kernel void copy4(__global const uint4* restrict a, __global uint4* restrict b) {
  const size_t i = get_global_id(0);
  b[i] = a[i];
}
)CL";

void printProfile(const char* title, ClPassTimer& timer) {
  PassTimings t;
  timer.collect(t);
  std::printf("  profile %s (CL event times, ms):", title);
  for (const auto& [name, ms] : t.entries()) std::printf("  %s %.2f", name.c_str(), ms);
  std::printf("  | sum %.2f\n", t.total());
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("manylights kernel microbenchmarks: compute primitives vs Boost.Compute and std::sort");
  std::string sizes_text = "65536,1048576,4194304,16777216";
  std::string json_path, device;
  int reps = 0;
  bool quick = false;
  app.add_option("--sizes", sizes_text, "comma-separated element counts (default 2^16,2^20,2^22,2^24)");
  app.add_option("--reps", reps, "timed repetitions per case (default 5; 3 for >= 2^22 elements)");
  app.add_flag("--quick", quick, "2^16 and 2^20 only, 2 reps: a smoke run");
  app.add_option("--json", json_path, "write the records as JSON to this file");
  app.add_option("--device", device, "OpenCL device: gpu, cpu or an index (default as the app)");
  std::string filter;
  bool profile = false;
  app.add_option("--filter", filter, "run only the cases whose name contains this text (comma-separated: any of these)");
  Options tune;
  app.add_option("--chunks", tune.chunks, "tuning override: CPU-shape work-items per launch");
  app.add_option("--radix-bits", tune.radix_bits, "tuning override: radix digit width");
  app.add_option("--sort-chunk", tune.sort_chunk, "tuning override: CPU-shape bitonic block (power of two)");
  std::string shape = "auto";
  app.add_option("--shape", shape, "kernel shape: auto, cpu (chunked work-items) or gpu (work-groups)")
      ->check(CLI::IsMember({"auto", "cpu", "gpu"}));
  app.add_flag("--profile", profile, "print per-pass CL event times at every size (default: the largest only)");
  CLI11_PARSE(app, argc, argv);
  try {
    ml::benchutil::requireWritable("--json", json_path);
  } catch (const UserError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
  tune.shape = shape == "cpu" ? Shape::CpuChunked : shape == "gpu" ? Shape::GpuWorkGroup : Shape::Auto;

  std::vector<std::size_t> sizes;
  if (quick) {
    sizes = {1u << 16, 1u << 20};
    if (!reps) reps = 2;
  } else {
    std::stringstream ss(sizes_text);
    std::string item;
    while (std::getline(ss, item, ',')) sizes.push_back(std::stoull(item));
  }

  try {
    auto rt = ClRuntime::create(DeviceChoice::resolve(device));
    auto& q = rt->queue();
    const auto& ctx = rt->context();
    std::printf("%s\n", rt->describe().c_str());
    std::printf("host threads for std::execution::par: %u\n\n", std::thread::hardware_concurrency());

    RadixSorter radix(*rt, tune);
    BitonicSorter bitonic(*rt, tune);
    Scanner scanner(*rt, tune);
    Reducer reducer(*rt, tune);
    Compactor compactor(*rt, tune);
    SegmentedSorter segsort(*rt, tune);
    cl::Kernel copy4(rt->programs().buildSource("bench_copy.cl", kCopySource), "copy4");
    std::printf("tuning: shape %s, radix digit %u bits, %zu chunks, work-group %zu, bitonic block %zu\n\n",
                shapeName(radix.tuning().shape), radix.tuning().radix_bits, radix.tuning().chunks, radix.tuning().wg,
                bitonic.blockSize());

    Bench bench;
    bench.filter = filter;
    std::printf("%-34s %10s %11s %11s %12s %9s\n", "case", "n", "median ms", "best ms", "Mitems/s", "GB/s");
    struct Ratio {
      std::string name;
      std::size_t n;
      double value;
      std::string text;
    };
    std::vector<Ratio> ratios;

    for (const std::size_t n : sizes) {
      bench.reps = reps ? reps : (n >= (1u << 22) ? 3 : 5);
      std::printf("-- n = %s\n", sizeLabel(n).c_str());
      const auto keys = makeKeys<std::uint32_t>(n, KeyDist::Random, 12345 + n);
      std::vector<std::uint32_t> values(n);
      std::iota(values.begin(), values.end(), 0u);
      cl::Buffer src = upload(ctx, q, keys);
      cl::Buffer work(ctx, CL_MEM_READ_WRITE, n * 4);
      cl::Buffer vsrc = upload(ctx, q, values);
      cl::Buffer vwork(ctx, CL_MEM_READ_WRITE, n * 4);
      auto restore = [&] {
        q.enqueueCopyBuffer(src, work, 0, 0, n * 4);
        q.finish();
      };
      auto restore_pairs = [&] {
        q.enqueueCopyBuffer(src, work, 0, 0, n * 4);
        q.enqueueCopyBuffer(vsrc, vwork, 0, 0, n * 4);
        q.finish();
      };

      // The physical limit: copy bandwidth, counted as bytes read + written,
      // the way each side can copy (the best of them is the reference).
      {
        std::vector<std::uint32_t> a(keys), b(n);
        bench.run("copy.host_memcpy", n, 8.0 * n, [] {}, [&] { std::memcpy(b.data(), a.data(), n * 4); });
        // Both cores: 1 MiB blocks over TBB's pool (the std::execution::par backend).
        const std::size_t block = 1u << 18;
        std::vector<std::size_t> starts;
        for (std::size_t i = 0; i < n; i += block) starts.push_back(i);
        bench.run("copy.host_memcpy_par", n, 8.0 * n, [] {}, [&] {
          std::for_each(std::execution::par, starts.begin(), starts.end(), [&](std::size_t i) {
            std::memcpy(b.data() + i, a.data() + i, std::min(block, n - i) * 4);
          });
        });
        bench.run("copy.cl_enqueue_copy", n, 8.0 * n, [] {}, [&] {
          q.enqueueCopyBuffer(src, work, 0, 0, n * 4);
          q.finish();
        });
        copy4.setArg(0, src);
        copy4.setArg(1, work);
        bench.run("copy.cl_kernel_uint4", n, 8.0 * n, [] {}, [&] {
          q.enqueueNDRangeKernel(copy4, cl::NullRange, cl::NDRange(std::max<std::size_t>(n / 4, 1)));
          q.finish();
        });
      }

      bench.run("radix_sort.u32", n, 8.0 * n, restore, [&] {
        radix.sort(q, work, nullptr, n, 32);
        q.finish();
      });
      bench.run("radix_sort.u32_pairs", n, 16.0 * n, restore_pairs, [&] {
        radix.sort(q, work, &vwork, n, 32);
        q.finish();
      });
      {
        const auto keys64 = makeKeys<std::uint64_t>(n, KeyDist::Random, 777 + n);
        cl::Buffer src64 = upload(ctx, q, keys64);
        cl::Buffer work64(ctx, CL_MEM_READ_WRITE, n * 8);
        bench.run("radix_sort.u64", n, 16.0 * n, [&] {
          q.enqueueCopyBuffer(src64, work64, 0, 0, n * 8);
          q.finish();
        }, [&] {
          radix.sort64(q, work64, nullptr, n, 64);
          q.finish();
        });
      }
      bench.run("bitonic_sort.u32", n, 8.0 * n, restore, [&] {
        bitonic.sort(q, work, nullptr, n);
        q.finish();
      });
      bench.run("boost_compute_sort.u32", n, 8.0 * n, restore, [&] { bench::boostComputeSortU32(q(), work(), n); });
      {
        std::vector<std::uint32_t> v;
        bench.run("std_sort.u32", n, 8.0 * n, [&] { v = keys; }, [&] { std::sort(v.begin(), v.end()); });
        bench.run("std_sort_par.u32", n, 8.0 * n, [&] { v = keys; },
                  [&] { std::sort(std::execution::par, v.begin(), v.end()); });
      }
      bench.run("scan.exclusive.u32", n, 8.0 * n, [] {}, [&] {
        scanner.exclusive(q, src, work, n);
        q.finish();
      });
      bench.run("reduce.sum.u32", n, 4.0 * n, [] {}, [&] { (void)reducer.reduce<std::uint32_t>(q, src, n, ReduceOp::Sum); });
      {
        std::vector<std::uint32_t> flags(n);
        for (std::size_t i = 0; i < n; ++i) flags[i] = keys[i] & 1u;
        cl::Buffer fbuf = upload(ctx, q, flags);
        bench.run("compact.half.u32", n, 12.0 * n, [] {}, [&] { (void)compactor.compact(q, src, fbuf, work, n); });
      }

      // Ratios computed from this run's medians.
      auto ratio = [&](const std::string& a, const std::string& b) {
        const Result* ra = bench.find(a, n);
        const Result* rb = bench.find(b, n);
        if (!ra || !rb) return;
        const double value = ra->items_per_second / rb->items_per_second;
        char line[200];
        std::snprintf(line, sizeof line, "%s / %s at %s: %.2fx", a.c_str(), b.c_str(), sizeLabel(n).c_str(), value);
        std::printf("  ratio %s\n", line);
        ratios.push_back({a + " / " + b, n, value, line});
      };
      ratio("radix_sort.u32", "boost_compute_sort.u32");
      ratio("radix_sort.u32", "std_sort_par.u32");
      ratio("radix_sort.u32", "std_sort.u32");
      ratio("bitonic_sort.u32", "boost_compute_sort.u32");
      {
        // Scan bandwidth against the fastest copy measured at this size.
        const Result* scan = bench.find("scan.exclusive.u32", n);
        const Result* best_copy = nullptr;
        for (const char* c : {"copy.host_memcpy", "copy.host_memcpy_par", "copy.cl_enqueue_copy", "copy.cl_kernel_uint4"})
          if (const Result* r = bench.find(c, n); r && (!best_copy || r->bytes_per_second > best_copy->bytes_per_second))
            best_copy = r;
        if (scan && best_copy) {
          const double value = scan->bytes_per_second / best_copy->bytes_per_second;
          char line[240];
          std::snprintf(line, sizeof line, "scan GB/s at %s: %.1f%% of the fastest copy (%s, %.1f GB/s)",
                        sizeLabel(n).c_str(), 100 * value, best_copy->name.c_str(), best_copy->bytes_per_second * 1e-9);
          std::printf("  ratio %s\n", line);
          ratios.push_back({"scan.exclusive.u32 / " + best_copy->name + " (bytes/s)", n, value, line});
        }
      }
      {
        // The radix sort's bandwidth bound, from this run's device copy of the
        // same n keys (the faster of clEnqueueCopyBuffer and the uint4 copy
        // kernel): an LSD pass must read and write every key at least once,
        // which is one copy, so P passes take at least P copy times:
        //   bound(P) keys/s = n / (P * t_copy(n keys)).
        // Reported for P = 4 (8-bit digits: issue 17's reference, fixed so
        // that runs compare) and for the passes this sorter makes for 32 bits.
        const Result* sort = bench.find("radix_sort.u32", n);
        const Result* copy = nullptr;
        for (const char* c : {"copy.cl_enqueue_copy", "copy.cl_kernel_uint4"})
          if (const Result* r = bench.find(c, n); r && (!copy || r->seconds < copy->seconds)) copy = r;
        if (sort && copy) {
          const unsigned digit = radix.tuning().radix_bits;
          const unsigned used = n >= (1u << 16) || radix.tuning().gpu() ? (32 + digit - 1) / digit
                                                                        : (32 + std::min(digit, 8u) - 1) / std::min(digit, 8u);
          for (const unsigned passes : {4u, used}) {
            const double bound = copy->items_per_second / passes;
            const double value = sort->items_per_second / bound;
            char line[320];
            std::snprintf(line, sizeof line,
                          "radix_sort.u32 at %s: %.1f%% of the bandwidth bound for %u passes, %.1f Mkeys/s = n / "
                          "(%u x %.3f ms per device copy of n keys, %s)%s",
                          sizeLabel(n).c_str(), 100 * value, passes, bound * 1e-6, passes, copy->seconds * 1e3,
                          copy->name.c_str(), passes == 4 ? " [issue 17 reference]" : " [passes used]");
            std::printf("  ratio %s\n", line);
            ratios.push_back({"radix_sort.u32 / bandwidth bound (" + std::to_string(passes) + " passes)", n, value,
                              line});
            if (used == 4) break;
          }
        }
      }
      if (n == sizes.back() || profile) {
        // One more run of each with CL event timing per pass: where the time goes.
        auto wanted = [&](const char* name) { return bench.wanted(name); };
        ClPassTimer timer;
        if (wanted("radix_sort.u32")) {
          restore();
          radix.sort(q, work, nullptr, n, 32, &timer);
          printProfile("radix_sort.u32", timer);
        }
        if (wanted("bitonic_sort.u32")) {
          restore();
          bitonic.sort(q, work, nullptr, n, &timer);
          printProfile("bitonic_sort.u32", timer);
        }
        if (wanted("scan.exclusive.u32")) {
          scanner.exclusive(q, src, work, n, nullptr, &timer);
          printProfile("scan.exclusive.u32", timer);
        }
      }
    }

    // 1080p-sized inputs: what the tiled and clustered passes feed these primitives.
    {
      const std::size_t w = 1920, h = 1080, n = w * h, tile = 16;
      bench.reps = reps ? reps : 5;
      std::printf("-- 1080p (%zu x %zu = %zu elements)\n", w, h, n);
      const auto keys = makeKeys<std::uint32_t>(n, KeyDist::Random, 99);
      std::vector<std::uint32_t> values(n);
      std::iota(values.begin(), values.end(), 0u);
      cl::Buffer src = upload(ctx, q, keys), work(ctx, CL_MEM_READ_WRITE, n * 4);
      cl::Buffer vsrc = upload(ctx, q, values), vwork(ctx, CL_MEM_READ_WRITE, n * 4);
      auto restore_pairs = [&] {
        q.enqueueCopyBuffer(src, work, 0, 0, n * 4);
        q.enqueueCopyBuffer(vsrc, vwork, 0, 0, n * 4);
        q.finish();
      };
      bench.run("scan.exclusive.u32.1080p", n, 8.0 * n, [] {}, [&] {
        scanner.exclusive(q, src, work, n);
        q.finish();
      });
      bench.run("segmented_sort.pairs.seg256.1080p", n, 16.0 * n, restore_pairs, [&] {
        segsort.sortFixed(q, work, &vwork, n, tile * tile);
        q.finish();
      });
      // Variable segment sizes (1..511, mean 256), as per-tile light lists are.
      std::mt19937 rng(7);
      std::vector<std::uint32_t> offsets{0};
      while (offsets.back() < n) offsets.push_back(std::min<std::uint32_t>(n, offsets.back() + 1 + rng() % 511));
      cl::Buffer obuf = upload(ctx, q, offsets);
      const std::size_t segs = offsets.size() - 1;
      bench.run("segmented_sort.pairs.var256.1080p", n, 16.0 * n, restore_pairs, [&] {
        segsort.sort(q, work, &vwork, n, obuf, segs);
        q.finish();
      });
      std::vector<float> depth(n);
      std::uniform_real_distribution<float> u(0.f, 1.f);
      for (auto& d : depth) d = u(rng);
      cl::Buffer dbuf = upload(ctx, q, depth);
      const std::size_t tiles = ((w + tile - 1) / tile) * ((h + tile - 1) / tile);
      cl::Buffer mn(ctx, CL_MEM_READ_WRITE, tiles * 4), mx(ctx, CL_MEM_READ_WRITE, tiles * 4);
      bench.run("tile_minmax.depth16.1080p", n, 4.0 * n, [] {}, [&] {
        reducer.tileMinMax(q, dbuf, w, h, tile, mn, mx);
        q.finish();
      });
      if (bench.wanted("segmented_sort.pairs.seg256.1080p")) {
        ClPassTimer timer;
        restore_pairs();
        segsort.sortFixed(q, work, &vwork, n, tile * tile, &timer);
        printProfile("segmented_sort.pairs.seg256.1080p", timer);
      }
    }

    if (!json_path.empty()) {
      nlohmann::json j;
      j["device"] = rt->describe();
      j["cases"] = nlohmann::json::array();
      for (const auto& r : bench.results)
        j["cases"].push_back({{"name", r.name},
                              {"n", r.n},
                              {"seconds", r.seconds},
                              {"items_per_second", r.items_per_second},
                              {"bytes_per_second", r.bytes_per_second}});
      j["ratios"] = nlohmann::json::array();
      for (const auto& r : ratios)
        j["ratios"].push_back({{"name", r.name}, {"n", r.n}, {"ratio", r.value}, {"text", r.text}});
      std::ofstream out(json_path);
      out << j.dump(2) << "\n";
      if (!out) throw UserError("--json: cannot write " + json_path);
      std::printf("\nwrote %s\n", json_path.c_str());
    }
  } catch (const UserError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  } catch (const cl::Error& e) {
    std::fprintf(stderr, "OpenCL error: %s\n", describeClError(e).c_str());
    return 1;
  }
  return 0;
}
