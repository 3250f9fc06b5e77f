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

#include "host/bench/BenchInputs.hpp"
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
           const std::function<void()>& body) {
    if (!wanted(name)) return;
    setup();
    body();
    std::vector<double> times;
    for (int i = 0; i < reps; ++i) {
      setup();
      auto t0 = Clock::now();
      body();
      times.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
    }
    Result res;
    res.name = name;
    res.n = n;
    res.seconds = benchutil::median(times);
    res.best = *std::min_element(times.begin(), times.end());
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


struct Args {
  std::string sizes_text = "65536,1048576,4194304,16777216";
  std::string json_path, device, filter, shape = "auto";
  int reps = 0;
  bool quick = false, profile = false;
  Options tune;
};

void addOptions(CLI::App& app, Args& a) {
  app.add_option("--sizes", a.sizes_text, "comma-separated element counts (default 2^16,2^20,2^22,2^24)");
  app.add_option("--reps", a.reps, "timed repetitions per case (default 5; 3 for >= 2^22 elements)");
  app.add_flag("--quick", a.quick, "2^16 and 2^20 only, 2 reps: a smoke run");
  app.add_option("--json", a.json_path, "write the records as JSON to this file");
  app.add_option("--device", a.device, "OpenCL device: gpu, cpu or an index (default as the app)");
  app.add_option("--filter", a.filter, "run only the cases whose name contains this text (comma-separated: any of these)");
  app.add_option("--chunks", a.tune.chunks, "tuning override: CPU-shape work-items per launch");
  app.add_option("--radix-bits", a.tune.radix_bits, "tuning override: radix digit width");
  app.add_option("--sort-chunk", a.tune.sort_chunk, "tuning override: CPU-shape bitonic block (power of two)");
  app.add_option("--shape", a.shape, "kernel shape: auto, cpu (chunked work-items) or gpu (work-groups)")
      ->check(CLI::IsMember({"auto", "cpu", "gpu"}));
  app.add_flag("--profile", a.profile, "print per-pass CL event times at every size (default: the largest only)");
}

std::vector<std::size_t> benchSizes(Args& a) {
  std::vector<std::size_t> sizes;
  if (a.quick) {
    if (!a.reps) a.reps = 2;
    return {1u << 16, 1u << 20};
  }
  for (const auto& item : splitList(a.sizes_text)) {
    const bool digits = !item.empty() && item.size() <= 12 && item.find_first_not_of("0123456789") == std::string::npos;
    if (!digits || std::stoull(item) == 0)
      throw UserError("--sizes: '" + item + "' is not a positive element count");
    sizes.push_back(std::stoull(item));
  }
  if (sizes.empty()) throw UserError("--sizes: no sizes given");
  return sizes;
}

// One size's inputs: random keys and their indices, on the device, with a
// work copy that each sort case restores (untimed) before it runs.
struct SizeInputs {
  std::size_t n;
  std::vector<std::uint32_t> keys;
  cl::Buffer src, work, vsrc, vwork;
  cl::CommandQueue& q;

  SizeInputs(const cl::Context& ctx, cl::CommandQueue& queue, std::size_t count, std::uint64_t seed)
      : n(count), keys(makeKeys<std::uint32_t>(count, KeyDist::Random, seed)), q(queue) {
    std::vector<std::uint32_t> values(n);
    std::iota(values.begin(), values.end(), 0u);
    src = upload(ctx, q, keys);
    work = cl::Buffer(ctx, CL_MEM_READ_WRITE, std::max<std::size_t>(n, 1) * 4);
    vsrc = upload(ctx, q, values);
    vwork = cl::Buffer(ctx, CL_MEM_READ_WRITE, std::max<std::size_t>(n, 1) * 4);
  }
  void restore() {
    q.enqueueCopyBuffer(src, work, 0, 0, n * 4);
    q.finish();
  }
  void restorePairs() {
    q.enqueueCopyBuffer(src, work, 0, 0, n * 4);
    q.enqueueCopyBuffer(vsrc, vwork, 0, 0, n * 4);
    q.finish();
  }
};

struct Ratio {
  std::string name;
  std::size_t n;
  double value;
  std::string text;
};

// Every case of one run, on one device, with the ratios between them.
class KernelBench {
 public:
  KernelBench(ClRuntime& rt, const Options& tune, Bench& bench)
      : rt_(rt), q_(rt.queue()), radix_(rt, tune), bitonic_(rt, tune), scanner_(rt, tune), reducer_(rt, tune),
        compactor_(rt, tune), segsort_(rt, tune),
        copy4_(rt.programs().buildSource("bench_copy.cl", kCopySource), "copy4"), bench_(bench) {}

  void printTuning() const {
    std::printf("tuning: shape %s, radix digit %u bits, %zu chunks, work-group %zu, bitonic block %zu\n\n",
                shapeName(radix_.tuning().shape), radix_.tuning().radix_bits, radix_.tuning().chunks,
                radix_.tuning().wg, bitonic_.blockSize());
  }

  void runSize(std::size_t n, bool profile, bool last) {
    std::printf("-- n = %s\n", sizeLabel(n).c_str());
    SizeInputs in(rt_.context(), q_, n, 12345 + n);
    copies(in);
    sorts(in);
    scanReduceCompact(in);
    ratio("radix_sort.u32", "boost_compute_sort.u32", n);
    ratio("radix_sort.u32", "std_sort_par.u32", n);
    ratio("radix_sort.u32", "std_sort.u32", n);
    ratio("bitonic_sort.u32", "boost_compute_sort.u32", n);
    scanShareOfCopy(n);
    radixShareOfBound(n);
    if (last || profile) profileSorts(in);
  }

  void run1080p();
  nlohmann::json json() const;

 private:
  void copies(SizeInputs& in);
  void sorts(SizeInputs& in);
  void scanReduceCompact(SizeInputs& in);
  void ratio(const std::string& a, const std::string& b, std::size_t n);
  void addRatio(const std::string& name, std::size_t n, double value, const std::string& text) {
    std::printf("  ratio %s\n", text.c_str());
    ratios_.push_back({name, n, value, text});
  }
  void scanShareOfCopy(std::size_t n);
  void radixShareOfBound(std::size_t n);
  void profileSorts(SizeInputs& in);

  ClRuntime& rt_;
  cl::CommandQueue& q_;
  RadixSorter radix_;
  BitonicSorter bitonic_;
  Scanner scanner_;
  Reducer reducer_;
  Compactor compactor_;
  SegmentedSorter segsort_;
  cl::Kernel copy4_;
  Bench& bench_;
  std::vector<Ratio> ratios_;
};

// The physical limit: copy bandwidth, counted as bytes read + written, the way
// each side can copy (the best of them is the reference).
void KernelBench::copies(SizeInputs& in) {
  const std::size_t n = in.n;
  std::vector<std::uint32_t> a(in.keys), b(n);
  bench_.run("copy.host_memcpy", n, 8.0 * n, [] {}, [&] { std::memcpy(b.data(), a.data(), n * 4); });
  // Both cores: 1 MiB blocks over TBB's pool (the std::execution::par backend).
  const std::size_t block = 1u << 18;
  std::vector<std::size_t> starts;
  for (std::size_t i = 0; i < n; i += block) starts.push_back(i);
  bench_.run("copy.host_memcpy_par", n, 8.0 * n, [] {}, [&] {
    std::for_each(std::execution::par, starts.begin(), starts.end(), [&](std::size_t i) {
      std::memcpy(b.data() + i, a.data() + i, std::min(block, n - i) * 4);
    });
  });
  bench_.run("copy.cl_enqueue_copy", n, 8.0 * n, [] {}, [&] { in.restore(); });
  copy4_.setArg(0, in.src);
  copy4_.setArg(1, in.work);
  bench_.run("copy.cl_kernel_uint4", n, 8.0 * n, [] {}, [&] {
    q_.enqueueNDRangeKernel(copy4_, cl::NullRange, cl::NDRange(std::max<std::size_t>(n / 4, 1)));
    q_.finish();
  });
}

void KernelBench::sorts(SizeInputs& in) {
  const std::size_t n = in.n;
  auto restore = [&] { in.restore(); };
  auto restore_pairs = [&] { in.restorePairs(); };
  bench_.run("radix_sort.u32", n, 8.0 * n, restore, [&] {
    radix_.sort(q_, in.work, nullptr, n, 32);
    q_.finish();
  });
  bench_.run("radix_sort.u32_pairs", n, 16.0 * n, restore_pairs, [&] {
    radix_.sort(q_, in.work, &in.vwork, n, 32);
    q_.finish();
  });
  const auto keys64 = makeKeys<std::uint64_t>(n, KeyDist::Random, 777 + n);
  cl::Buffer src64 = upload(rt_.context(), q_, keys64);
  cl::Buffer work64(rt_.context(), CL_MEM_READ_WRITE, std::max<std::size_t>(n, 1) * 8);
  bench_.run("radix_sort.u64", n, 16.0 * n, [&] {
    q_.enqueueCopyBuffer(src64, work64, 0, 0, n * 8);
    q_.finish();
  }, [&] {
    radix_.sort64(q_, work64, nullptr, n, 64);
    q_.finish();
  });
  bench_.run("bitonic_sort.u32", n, 8.0 * n, restore, [&] {
    bitonic_.sort(q_, in.work, nullptr, n);
    q_.finish();
  });
  bench_.run("boost_compute_sort.u32", n, 8.0 * n, restore, [&] { bench::boostComputeSortU32(q_(), in.work(), n); });
  std::vector<std::uint32_t> v;
  bench_.run("std_sort.u32", n, 8.0 * n, [&] { v = in.keys; }, [&] { std::sort(v.begin(), v.end()); });
  bench_.run("std_sort_par.u32", n, 8.0 * n, [&] { v = in.keys; },
             [&] { std::sort(std::execution::par, v.begin(), v.end()); });
}

void KernelBench::scanReduceCompact(SizeInputs& in) {
  const std::size_t n = in.n;
  bench_.run("scan.exclusive.u32", n, 8.0 * n, [] {}, [&] {
    scanner_.exclusive(q_, in.src, in.work, n);
    q_.finish();
  });
  bench_.run("reduce.sum.u32", n, 4.0 * n, [] {},
             [&] { (void)reducer_.reduce<std::uint32_t>(q_, in.src, n, ReduceOp::Sum); });
  std::vector<std::uint32_t> flags(n);
  for (std::size_t i = 0; i < n; ++i) flags[i] = in.keys[i] & 1u;
  cl::Buffer fbuf = upload(rt_.context(), q_, flags);
  bench_.run("compact.half.u32", n, 12.0 * n, [] {}, [&] { (void)compactor_.compact(q_, in.src, fbuf, in.work, n); });
}

// Items per second of `a` over `b`, from this run's medians.
void KernelBench::ratio(const std::string& a, const std::string& b, std::size_t n) {
  const Result* ra = bench_.find(a, n);
  const Result* rb = bench_.find(b, n);
  if (!ra || !rb) return;
  const double value = ra->items_per_second / rb->items_per_second;
  char line[200];
  std::snprintf(line, sizeof line, "%s / %s at %s: %.2fx", a.c_str(), b.c_str(), sizeLabel(n).c_str(), value);
  addRatio(a + " / " + b, n, value, line);
}

// Scan bandwidth against the fastest copy measured at this size.
void KernelBench::scanShareOfCopy(std::size_t n) {
  const Result* scan = bench_.find("scan.exclusive.u32", n);
  const Result* best_copy = nullptr;
  for (const char* c : {"copy.host_memcpy", "copy.host_memcpy_par", "copy.cl_enqueue_copy", "copy.cl_kernel_uint4"})
    if (const Result* r = bench_.find(c, n); r && (!best_copy || r->bytes_per_second > best_copy->bytes_per_second))
      best_copy = r;
  if (!scan || !best_copy) return;
  const double value = scan->bytes_per_second / best_copy->bytes_per_second;
  char line[240];
  std::snprintf(line, sizeof line, "scan GB/s at %s: %.1f%% of the fastest copy (%s, %.1f GB/s)",
                sizeLabel(n).c_str(), 100 * value, best_copy->name.c_str(), best_copy->bytes_per_second * 1e-9);
  addRatio("scan.exclusive.u32 / " + best_copy->name + " (bytes/s)", n, value, line);
}

// The radix sort's bandwidth bound, from this run's device copy of the same n
// keys (the faster of clEnqueueCopyBuffer and the uint4 copy kernel): an LSD
// pass must read and write every key at least once, which is one copy, so P
// passes take at least P copy times:  bound(P) keys/s = n / (P * t_copy(n keys)).
// Reported for P = 4 (8-bit digits: issue 17's reference, fixed so that runs
// compare) and for the passes this sorter makes for 32 bits.
void KernelBench::radixShareOfBound(std::size_t n) {
  const Result* sort = bench_.find("radix_sort.u32", n);
  const Result* copy = nullptr;
  for (const char* c : {"copy.cl_enqueue_copy", "copy.cl_kernel_uint4"})
    if (const Result* r = bench_.find(c, n); r && (!copy || r->seconds < copy->seconds)) copy = r;
  if (!sort || !copy) return;
  const unsigned digit = radix_.tuning().radix_bits;
  const unsigned used = n >= (1u << 16) || radix_.tuning().gpu() ? (32 + digit - 1) / digit
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
    addRatio("radix_sort.u32 / bandwidth bound (" + std::to_string(passes) + " passes)", n, value, line);
    if (used == 4) break;
  }
}

// One more run of each sort and the scan with CL event timing per pass: where the time goes.
void KernelBench::profileSorts(SizeInputs& in) {
  ClPassTimer timer;
  if (bench_.wanted("radix_sort.u32")) {
    in.restore();
    radix_.sort(q_, in.work, nullptr, in.n, 32, &timer);
    printProfile("radix_sort.u32", timer);
  }
  if (bench_.wanted("bitonic_sort.u32")) {
    in.restore();
    bitonic_.sort(q_, in.work, nullptr, in.n, &timer);
    printProfile("bitonic_sort.u32", timer);
  }
  if (bench_.wanted("scan.exclusive.u32")) {
    scanner_.exclusive(q_, in.src, in.work, in.n, nullptr, &timer);
    printProfile("scan.exclusive.u32", timer);
  }
}

// 1080p-sized inputs: what the tiled and clustered passes feed these primitives.
void KernelBench::run1080p() {
  const std::size_t w = 1920, h = 1080, n = w * h, tile = 16;
  std::printf("-- 1080p (%zu x %zu = %zu elements)\n", w, h, n);
  SizeInputs in(rt_.context(), q_, n, 99);
  auto restore_pairs = [&] { in.restorePairs(); };
  bench_.run("scan.exclusive.u32.1080p", n, 8.0 * n, [] {}, [&] {
    scanner_.exclusive(q_, in.src, in.work, n);
    q_.finish();
  });
  bench_.run("segmented_sort.pairs.seg256.1080p", n, 16.0 * n, restore_pairs, [&] {
    segsort_.sortFixed(q_, in.work, &in.vwork, n, tile * tile);
    q_.finish();
  });
  // Variable segment sizes (1..511, mean 256), as per-tile light lists are.
  std::mt19937 rng(7);
  std::vector<std::uint32_t> offsets{0};
  while (offsets.back() < n) offsets.push_back(std::min<std::uint32_t>(n, offsets.back() + 1 + rng() % 511));
  cl::Buffer obuf = upload(rt_.context(), q_, offsets);
  const std::size_t segs = offsets.size() - 1;
  bench_.run("segmented_sort.pairs.var256.1080p", n, 16.0 * n, restore_pairs, [&] {
    segsort_.sort(q_, in.work, &in.vwork, n, obuf, segs);
    q_.finish();
  });
  std::vector<float> depth(n);
  std::uniform_real_distribution<float> u(0.f, 1.f);
  for (auto& d : depth) d = u(rng);
  cl::Buffer dbuf = upload(rt_.context(), q_, depth);
  const std::size_t tiles = ((w + tile - 1) / tile) * ((h + tile - 1) / tile);
  cl::Buffer mn(rt_.context(), CL_MEM_READ_WRITE, tiles * 4), mx(rt_.context(), CL_MEM_READ_WRITE, tiles * 4);
  bench_.run("tile_minmax.depth16.1080p", n, 4.0 * n, [] {}, [&] {
    reducer_.tileMinMax(q_, dbuf, w, h, tile, mn, mx);
    q_.finish();
  });
  if (bench_.wanted("segmented_sort.pairs.seg256.1080p")) {
    ClPassTimer timer;
    in.restorePairs();
    segsort_.sortFixed(q_, in.work, &in.vwork, n, tile * tile, &timer);
    printProfile("segmented_sort.pairs.seg256.1080p", timer);
  }
}

nlohmann::json KernelBench::json() const {
  nlohmann::json j;
  j["device"] = rt_.describe();
  j["cases"] = nlohmann::json::array();
  for (const auto& r : bench_.results)
    j["cases"].push_back({{"name", r.name},
                          {"n", r.n},
                          {"seconds", r.seconds},
                          {"items_per_second", r.items_per_second},
                          {"bytes_per_second", r.bytes_per_second}});
  j["ratios"] = nlohmann::json::array();
  for (const auto& r : ratios_)
    j["ratios"].push_back({{"name", r.name}, {"n", r.n}, {"ratio", r.value}, {"text", r.text}});
  return j;
}

int run(Args& a) {
  benchutil::requireWritable("--json", a.json_path);
  a.tune.shape = a.shape == "cpu" ? Shape::CpuChunked : a.shape == "gpu" ? Shape::GpuWorkGroup : Shape::Auto;
  const std::vector<std::size_t> sizes = benchSizes(a);
  auto rt = ClRuntime::create(DeviceChoice::resolve(a.device));
  std::printf("%s\n", rt->describe().c_str());
  std::printf("host threads for std::execution::par: %u\n\n", std::thread::hardware_concurrency());
  Bench bench;
  bench.filter = a.filter;
  KernelBench kb(*rt, a.tune, bench);
  kb.printTuning();
  std::printf("%-34s %10s %11s %11s %12s %9s\n", "case", "n", "median ms", "best ms", "Mitems/s", "GB/s");
  for (const std::size_t n : sizes) {
    bench.reps = a.reps ? a.reps : (n >= (1u << 22) ? 3 : 5);
    kb.runSize(n, a.profile, n == sizes.back());
  }
  bench.reps = a.reps ? a.reps : 5;
  kb.run1080p();
  benchutil::writeJson(a.json_path, kb.json());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app("manylights kernel microbenchmarks: compute primitives vs Boost.Compute and std::sort");
  Args a;
  addOptions(app, a);
  CLI11_PARSE(app, argc, argv);
  return benchutil::benchMain("manylights-kernel-bench", [&] {
    try {
      return run(a);
    } catch (const cl::Error& e) {
      std::fprintf(stderr, "OpenCL error: %s\n", describeClError(e).c_str());
      return 1;
    }
  });
}
