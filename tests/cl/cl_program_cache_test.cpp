// The kernel binary cache cannot poison later runs: damaged, swapped, empty
// and refused entries are deleted with one warning line and recompiled; an
// unusable folder or a failed write turns caching off with one warning line;
// entries carry a header with key, size and checksum. Unit level on
// ProgramBuilder/KernelCache first (fast), then whole renders as a user runs them.
#include <gtest/gtest.h>

#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>

#include "host/cl/KernelCache.hpp"
#include "host/cl/ProgramBuilder.hpp"
#include "ml_test_paths.h"  // MANYLIGHTS_BINARY
#include "support/RunCommand.hpp"
#include "support/ScopedEnv.hpp"
#include "support/TempDir.hpp"
#include "support/TestDevice.hpp"

namespace ml {
namespace {
namespace fs = std::filesystem;
using Bytes = std::vector<unsigned char>;

Bytes readBytes(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  return Bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}
void writeBytes(const fs::path& p, const Bytes& b) {
  std::ofstream(p, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(b.data()),
                                                               static_cast<std::streamsize>(b.size()));
}

// Every file in `dir`, sorted (entries and anything a writer left behind).
std::vector<fs::path> filesIn(const std::string& dir) {
  std::vector<fs::path> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec)) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

std::uint64_t keyOf(const fs::path& entry) { return std::stoull(entry.filename().string().substr(0, 16), nullptr, 16); }

int warningLines(const std::string& text) {
  int n = 0;
  std::size_t start = 0;
  while (start < text.size()) {
    std::size_t end = text.find('\n', start);
    if (end == std::string::npos) end = text.size();
    n += text.substr(start, end - start).find("warning") != std::string::npos;
    start = end + 1;
  }
  return n;
}

// A kernel that writes `value`: running it tells which program was loaded.
std::string probeSource(cl_uint value) {
  return "__kernel void probe(__global uint* a) { a[0] = " + std::to_string(value) + "u; }\n";
}
cl_uint runProbe(const cl::Program& p) {
  auto& rt = test::runtime();
  cl::Buffer buf(rt.context(), CL_MEM_WRITE_ONLY, sizeof(cl_uint));
  cl::Kernel k(p, "probe");
  k.setArg(0, buf);
  rt.queue().enqueueNDRangeKernel(k, cl::NullRange, cl::NDRange(1));
  cl_uint out = 0;
  rt.queue().enqueueReadBuffer(buf, CL_TRUE, 0, sizeof out, &out);
  return out;
}

std::unique_ptr<ProgramBuilder> builderFor(const std::string& dir) {
  auto& rt = test::runtime();
  return std::make_unique<ProgramBuilder>(rt.context(), rt.device(), rt.info(), KernelCache(dir, "test cache " + dir));
}

// Builds `source` with a fresh builder on `dir`; returns the probe's output,
// the builder's stats and what it printed on stderr.
struct BuildOutcome {
  cl_uint value = 0;
  ProgramBuilder::Stats stats;
  std::string err;
};
BuildOutcome buildWith(const std::string& dir, const std::string& source) {
  auto builder = builderFor(dir);
  ::testing::internal::CaptureStderr();
  BuildOutcome o;
  try {
    o.value = runProbe(builder->buildSource("probe.cl", source));
  } catch (...) {
    ::testing::internal::GetCapturedStderr();
    throw;
  }
  o.err = ::testing::internal::GetCapturedStderr();
  o.stats = builder->stats();
  return o;
}

// Whether the test device's driver gets binaries at all (host/cl/KernelCacheProbe.hpp):
// on one that ends the process when it refuses a binary (Mesa rusticl) the
// tests below check instead that no binary is ever stored or loaded.
bool deviceCachesBinaries() {
  test::TempDir tmp;
  return builderFor(tmp.file("kernels"))->cachesBinaries();
}

// Builds of `value`'s probe store no entry, and do not load one forged at its
// key (intact header and checksum around bytes no driver accepts: on rusticl,
// loading it would abort the process).
void expectNoBinariesUsed(const std::string& dir, cl_uint value) {
  const auto first = buildWith(dir, probeSource(value));
  EXPECT_EQ(first.value, value);
  EXPECT_EQ(first.stats.compiles, 1);
  EXPECT_EQ(first.err, "");
  EXPECT_TRUE(filesIn(dir).empty()) << "a binary was stored";
  const std::uint64_t key = builderFor(dir)->cacheKey("probe.cl", probeSource(value));
  const std::string entry = KernelCache(dir, "forger").entryPath(key);
  const Bytes forged = encodeKernelCacheEntry(key, Bytes(4096, 0));
  writeBytes(entry, forged);
  const auto again = buildWith(dir, probeSource(value));
  EXPECT_EQ(again.value, value);
  EXPECT_EQ(again.stats.compiles, 1);
  EXPECT_EQ(again.stats.disk_hits, 0);
  EXPECT_EQ(again.err, "");
  EXPECT_TRUE(readBytes(entry) == forged) << "the forged entry was read or replaced";
}

enum class Damage { TruncatedBinary, TruncatedHeader, FlippedByte, Swapped, Empty, Padded };
const char* damageName(Damage d) {
  switch (d) {
    case Damage::TruncatedBinary: return "TruncatedBinary";
    case Damage::TruncatedHeader: return "TruncatedHeader";
    case Damage::FlippedByte: return "FlippedByte";
    case Damage::Swapped: return "Swapped";
    case Damage::Empty: return "Empty";
    case Damage::Padded: return "Padded";
  }
  return "?";
}

// Damages `entry` as a full disk, a bad sector or a misplaced file would;
// `other` is another valid entry of the same folder (for Swapped).
void damage(Damage d, const fs::path& entry, const fs::path& other, std::mt19937_64& rng) {
  Bytes b = readBytes(entry);
  ASSERT_GT(b.size(), KernelCache::kHeaderSize);
  auto pick = [&](std::size_t lo, std::size_t hi) { return std::uniform_int_distribution<std::size_t>(lo, hi)(rng); };
  switch (d) {
    case Damage::TruncatedBinary: b.resize(pick(KernelCache::kHeaderSize, b.size() - 1)); break;
    case Damage::TruncatedHeader: b.resize(pick(1, KernelCache::kHeaderSize - 1)); break;
    case Damage::FlippedByte: b[pick(0, b.size() - 1)] ^= static_cast<unsigned char>(1u << pick(0, 7)); break;
    case Damage::Swapped: b = readBytes(other); break;
    case Damage::Empty: b.clear(); break;
    case Damage::Padded: b.resize(b.size() + pick(1, 4096), 0); break;
  }
  writeBytes(entry, b);
}

// PoCL refuses a bad binary with an error, rusticl aborts the process: the
// probe must tell them apart (an always-unsafe probe would leave PoCL uncached).
TEST(ProgramCache, ProbeTellsWhetherTheDriverRefusesBinariesSafely) {
  const std::string platform = test::runtime().info().platform_name;
  const bool caches = deviceCachesBinaries();
  if (platform.find("rusticl") != std::string::npos) {
    EXPECT_FALSE(caches);
  }
  if (platform.find("Portable Computing Language") != std::string::npos) {
    EXPECT_TRUE(caches);
  }
  test::ScopedEnv hook("MANYLIGHTS_TEST_BINARIES", "unsafe");
  EXPECT_FALSE(deviceCachesBinaries());
}

// The path rusticl takes, on every device (the hook pretends the driver cannot
// refuse a binary safely).
TEST(ProgramCache, DriverThatCannotRefuseABinarySafelyNeverGetsOne) {
  test::ScopedEnv hook("MANYLIGHTS_TEST_BINARIES", "unsafe");
  test::TempDir tmp;
  expectNoBinariesUsed(tmp.file("kernels"), static_cast<cl_uint>(test::freshSeed()));
}

TEST(ProgramCache, EntryHasHeaderAndIsReusedWithoutWarnings) {
  test::TempDir tmp;
  const std::string dir = tmp.file("kernels");
  const cl_uint value = static_cast<cl_uint>(test::freshSeed());
  if (!deviceCachesBinaries()) return expectNoBinariesUsed(dir, value);
  const auto first = buildWith(dir, probeSource(value));
  EXPECT_EQ(first.value, value);
  EXPECT_EQ(first.stats.compiles, 1);
  const auto files = filesIn(dir);
  ASSERT_EQ(files.size(), 1u) << "one entry, no temp file left behind";
  EXPECT_TRUE(files[0].filename().string().ends_with(".v1.bin")) << files[0];
  const Bytes b = readBytes(files[0]);
  ASSERT_GT(b.size(), KernelCache::kHeaderSize);
  EXPECT_EQ(std::memcmp(b.data(), "MLKCACHE", 8), 0);
  std::uint64_t key = 0, size = 0;
  std::memcpy(&key, b.data() + 16, 8);
  std::memcpy(&size, b.data() + 24, 8);
  EXPECT_EQ(key, keyOf(files[0]));
  EXPECT_EQ(size, b.size() - KernelCache::kHeaderSize);
  // The stored bytes are exactly what the encoder makes of the binary.
  EXPECT_EQ(encodeKernelCacheEntry(key, Bytes(b.begin() + KernelCache::kHeaderSize, b.end())), b);

  const auto second = buildWith(dir, probeSource(value));
  EXPECT_EQ(second.value, value);
  EXPECT_EQ(second.stats.disk_hits, 1);
  EXPECT_EQ(second.stats.compiles, 0);
  EXPECT_EQ(second.err, "");
}

class ProgramCacheDamage : public ::testing::TestWithParam<Damage> {};

TEST_P(ProgramCacheDamage, EntryIsDeletedRecompiledAndRewritten) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("MANYLIGHTS_TEST_SEED=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  test::TempDir tmp;
  const std::string dir = tmp.file("kernels");
  const cl_uint a = static_cast<cl_uint>(rng()), b = a ^ 0x5a5a5a5au;
  if (!deviceCachesBinaries()) return expectNoBinariesUsed(dir, a);
  buildWith(dir, probeSource(a));
  const fs::path entry_a = filesIn(dir).at(0);
  buildWith(dir, probeSource(b));
  auto files = filesIn(dir);
  ASSERT_EQ(files.size(), 2u);
  const fs::path entry_b = files[0] == entry_a ? files[1] : files[0];
  damage(GetParam(), entry_a, entry_b, rng);

  const auto again = buildWith(dir, probeSource(a));
  EXPECT_EQ(again.value, a) << "the program of the damaged entry's key, not another";
  EXPECT_EQ(again.stats.compiles, 1);
  EXPECT_EQ(again.stats.disk_hits, 0);
  EXPECT_EQ(warningLines(again.err), 1) << again.err;
  EXPECT_NE(again.err.find(entry_a.string()), std::string::npos) << "names the file: " << again.err;
  // Rewritten whole: the next run loads it silently; the other entry is untouched.
  const auto third = buildWith(dir, probeSource(a));
  EXPECT_EQ(third.stats.disk_hits, 1);
  EXPECT_EQ(third.err, "");
  EXPECT_EQ(buildWith(dir, probeSource(b)).stats.disk_hits, 1);
  EXPECT_EQ(filesIn(dir).size(), 2u);
}

INSTANTIATE_TEST_SUITE_P(Kinds, ProgramCacheDamage,
                         ::testing::Values(Damage::TruncatedBinary, Damage::TruncatedHeader, Damage::FlippedByte,
                                           Damage::Swapped, Damage::Empty, Damage::Padded),
                         [](const auto& info) { return std::string(damageName(info.param)); });

TEST(ProgramCache, EntryTheDriverRefusesIsDeletedAndRecompiled) {
  test::TempDir tmp;
  const std::string dir = tmp.file("kernels");
  const cl_uint value = static_cast<cl_uint>(test::freshSeed());
  if (!deviceCachesBinaries()) return expectNoBinariesUsed(dir, value);
  buildWith(dir, probeSource(value));
  const fs::path entry = filesIn(dir).at(0);
  // Intact header and checksum around a binary the driver cannot load.
  writeBytes(entry, encodeKernelCacheEntry(keyOf(entry), Bytes(4096, 0)));
  const auto again = buildWith(dir, probeSource(value));
  EXPECT_EQ(again.value, value);
  EXPECT_EQ(again.stats.compiles, 1);
  EXPECT_EQ(warningLines(again.err), 1) << again.err;
  EXPECT_NE(again.err.find(entry.string()), std::string::npos) << again.err;
  EXPECT_EQ(buildWith(dir, probeSource(value)).stats.disk_hits, 1);
}

TEST(ProgramCache, UnusableFolderWarnsOnceAndCachesNothing) {
  test::TempDir tmp;
  const std::string file = tmp.write("not-a-folder", "x");
  const std::string dir = file + "/kernels";
  const cl_uint value = static_cast<cl_uint>(test::freshSeed());
  ::testing::internal::CaptureStderr();
  auto builder = builderFor(dir);
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(warningLines(err), 1) << err;
  EXPECT_NE(err.find(dir), std::string::npos) << err;
  EXPECT_EQ(builder->cacheDir(), "");
  // Later builders on the same folder stay silent; builds work uncached.
  const auto out = buildWith(dir, probeSource(value));
  EXPECT_EQ(out.value, value);
  EXPECT_EQ(out.stats.compiles, 1);
  EXPECT_EQ(out.err, "");
}

TEST(KernelCache, OffAndEmptyDisable) {
  EXPECT_FALSE(KernelCache("").enabled());
  const char* old = std::getenv("MANYLIGHTS_CACHE_DIR");
  const std::string saved = old ? old : "";
  ::setenv("MANYLIGHTS_CACHE_DIR", "off", 1);
  EXPECT_FALSE(KernelCache::fromEnvironment().enabled());
  test::TempDir tmp;
  ::setenv("MANYLIGHTS_CACHE_DIR", tmp.file("c").c_str(), 1);
  EXPECT_EQ(KernelCache::fromEnvironment().dir(), tmp.file("c") + "/kernels");
  if (old)
    ::setenv("MANYLIGHTS_CACHE_DIR", saved.c_str(), 1);
  else
    ::unsetenv("MANYLIGHTS_CACHE_DIR");
}

// A full disk, simulated with the file-size limit (EFBIG instead of ENOSPC:
// the same short-write path) because tests cannot mount a small file system.
TEST(KernelCache, FailedWriteWarnsOnceDisablesAndLeavesNothing) {
  test::TempDir tmp;
  const std::string dir = tmp.file("kernels");
  KernelCache cache(dir, "test");
  ASSERT_TRUE(cache.enabled());
  rlimit old{};
  ASSERT_EQ(::getrlimit(RLIMIT_FSIZE, &old), 0);
  rlimit small = old;
  small.rlim_cur = 8192;
  auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
  ::testing::internal::CaptureStderr();
  ASSERT_EQ(::setrlimit(RLIMIT_FSIZE, &small), 0);
  cache.store(42, Bytes(64 * 1024, 7));
  cache.store(43, Bytes(64 * 1024, 7));
  ::setrlimit(RLIMIT_FSIZE, &old);
  std::signal(SIGXFSZ, old_handler);
  const std::string err = ::testing::internal::GetCapturedStderr();
  EXPECT_EQ(warningLines(err), 1) << err;
  EXPECT_NE(err.find(dir), std::string::npos) << err;
  EXPECT_FALSE(cache.enabled());
  EXPECT_FALSE(KernelCache(dir, "test").enabled()) << "off for the rest of the process";
  EXPECT_TRUE(filesIn(dir).empty()) << "no entry and no temp file left";
}

// Writers in several processes storing the same key at once (the race of two
// runs on an empty cache, many times over): every store succeeds (a clash of
// temp names would fail O_EXCL and turn the cache off), no temp file is left
// and the entry that remains is whole.
TEST(KernelCache, ConcurrentWritersOfOneKeyLeaveOneWholeEntry) {
  test::TempDir tmp;
  const std::string dir = tmp.file("kernels");
  constexpr int kWriters = 4, kStores = 25;
  std::vector<pid_t> kids;
  for (int w = 0; w < kWriters; ++w) {
    const pid_t pid = ::fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      KernelCache cache(dir, "writer");
      for (int i = 0; i < kStores; ++i) cache.store(7, Bytes(20000 + 1000 * w + i, static_cast<unsigned char>(w)));
      ::_exit(cache.enabled() ? 0 : 1);
    }
    kids.push_back(pid);
  }
  for (pid_t pid : kids) {
    int status = 0;
    ASSERT_EQ(::waitpid(pid, &status, 0), pid);
    EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "a writer failed to store";
  }
  const auto files = filesIn(dir);
  ASSERT_EQ(files.size(), 1u) << "temp files left behind";
  ::testing::internal::CaptureStderr();
  const auto bin = KernelCache(dir, "reader").load(7);
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
  ASSERT_TRUE(bin.has_value());
  EXPECT_EQ(std::count(bin->begin(), bin->end(), bin->front()), static_cast<std::ptrdiff_t>(bin->size()))
      << "bytes of two writers mixed";
}

// ---- Whole renders, as a user runs them ----

constexpr const char* kRenderArgs = "render --size 64x48 --technique tiled-deferred --frames 1 --warmup 0";

struct CleanRun {
  test::TempDir tmp;
  std::string cache = tmp.file("cache");  // MANYLIGHTS_CACHE_DIR of the clean run
  Bytes image;
};

// One clean render, shared by the tests below: its image and its cache.
const CleanRun& cleanRun() {
  static const std::unique_ptr<CleanRun> run = [] {
    auto r = std::make_unique<CleanRun>();
    const std::string png = r->tmp.file("clean.png");
    const auto res = test::runManylights(std::string(kRenderArgs) + " --out " + png, "MANYLIGHTS_CACHE_DIR=" + r->cache);
    EXPECT_EQ(res.exit_code, 0) << res.err;
    EXPECT_EQ(warningLines(res.err + res.out), 0) << res.err;
    r->image = readBytes(png);
    return r;
  }();
  return *run;
}

// Renders with MANYLIGHTS_CACHE_DIR=`cache`; checks exit 0, `warnings` warning
// lines (naming `named`) and the clean-cache image.
void expectCleanImage(const std::string& cache, int warnings, const std::string& named) {
  test::TempDir tmp;
  const std::string png = tmp.file("out.png");
  const auto res = test::runManylights(std::string(kRenderArgs) + " --out " + png, "MANYLIGHTS_CACHE_DIR=" + cache);
  EXPECT_EQ(res.exit_code, 0) << res.err;
  EXPECT_EQ(warningLines(res.err), warnings) << res.err;
  EXPECT_EQ(warningLines(res.out), 0) << "warnings go to stderr";
  if (!named.empty()) {
    EXPECT_NE(res.err.find(named), std::string::npos) << res.err;
  }
  EXPECT_TRUE(readBytes(png) == cleanRun().image) << "image differs from the clean-cache render";
}

class RenderCacheDamage : public ::testing::TestWithParam<Damage> {};

TEST_P(RenderCacheDamage, RecoversWithOneWarningAndTheSameImage) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("MANYLIGHTS_TEST_SEED=" + std::to_string(seed));
  std::mt19937_64 rng(seed);
  const CleanRun& clean = cleanRun();
  test::TempDir tmp;
  const std::string cache = tmp.file("cache");
  fs::copy(clean.cache, cache, fs::copy_options::recursive);
  const auto entries = filesIn(cache + "/kernels");
  if (!deviceCachesBinaries()) {  // nothing to damage: no binary was stored
    EXPECT_TRUE(entries.empty());
    return expectCleanImage(cache, 0, "");
  }
  ASSERT_GE(entries.size(), 2u);
  const std::size_t i = rng() % entries.size(), j = (i + 1 + rng() % (entries.size() - 1)) % entries.size();
  damage(GetParam(), entries[i], entries[j], rng);
  expectCleanImage(cache, 1, entries[i].string());
  // (That the entry is rewritten whole is checked at unit level above.)
}

INSTANTIATE_TEST_SUITE_P(Kinds, RenderCacheDamage,
                         ::testing::Values(Damage::TruncatedBinary, Damage::FlippedByte, Damage::Swapped,
                                           Damage::Empty),
                         [](const auto& info) { return std::string(damageName(info.param)); });

TEST(RenderCache, UnwritableFolderWarnsOnceAndRenders) {
  test::TempDir tmp;
  const std::string file = tmp.write("cache-is-a-file", "x");
  expectCleanImage(file, 1, "MANYLIGHTS_CACHE_DIR=" + file);
}

TEST(RenderCache, TwoRacingRunsOnAnEmptyCacheAgreeAndLeaveValidEntries) {
  const CleanRun& clean = cleanRun();
  test::TempDir tmp;
  const std::string dir = tmp.file("race");
  std::string cmd;
  for (int i = 0; i < 2; ++i) {
    const std::string base = dir + "-" + std::to_string(i);
    cmd += "(MANYLIGHTS_CACHE_DIR=" + dir + " " + MANYLIGHTS_BINARY + " " + kRenderArgs + " --out " + base +
           ".png >" + base + ".out 2>" + base + ".err </dev/null; echo $? >" + base + ".rc) & ";
  }
  ASSERT_EQ(std::system(("bash -c '" + cmd + "wait'").c_str()), 0);
  for (int i = 0; i < 2; ++i) {
    const std::string base = dir + "-" + std::to_string(i);
    const Bytes rc = readBytes(base + ".rc"), err = readBytes(base + ".err");
    EXPECT_EQ(std::string(rc.begin(), rc.end()), "0\n") << std::string(err.begin(), err.end());
    EXPECT_EQ(warningLines(std::string(err.begin(), err.end())), 0);
    EXPECT_TRUE(readBytes(base + ".png") == clean.image) << "run " << i;
  }
  // Only whole entries remain (no temp files), each loading without a warning.
  const auto entries = filesIn(dir + "/kernels");
  EXPECT_EQ(entries.size(), filesIn(clean.cache + "/kernels").size());
  KernelCache cache(dir + "/kernels", "race");
  ::testing::internal::CaptureStderr();
  for (const auto& e : entries) {
    ASSERT_TRUE(e.filename().string().ends_with(".v1.bin")) << e;
    EXPECT_TRUE(cache.load(keyOf(e)).has_value()) << e;
  }
  EXPECT_EQ(::testing::internal::GetCapturedStderr(), "");
}

}  // namespace
}  // namespace ml
