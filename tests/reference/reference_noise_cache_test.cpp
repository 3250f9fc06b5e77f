// The reference's own noise (IndirectImage::noise_var, compareWithReference)
// and the on-disk reference cache (host/reference/ReferenceCache.hpp), on the
// Cornell box at a small size, against a 1024-sample trace as the truth:
//  - the estimated noise of an N-sample trace matches its measured error
//    against the truth (within 35%), for several N;
//  - the noise-corrected error of one trace against another independent one
//    is far below their raw error (both are the truth plus noise);
//  - the cache reads back exactly what was traced, keys on the lights and the
//    samples, survives a truncated file by tracing again, and can be off.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "host/reference/IndirectReference.hpp"
#include "host/reference/ReferenceCache.hpp"
#include "host/run/SceneInputs.hpp"
#include "ml_test_paths.h"  // MANYLIGHTS_TEST_DATA_DIR
#include "support/RunCommand.hpp"
#include "support/ScopedEnv.hpp"
#include "support/TestDevice.hpp"

namespace ml {
namespace {

namespace fs = std::filesystem;

SceneInputs cornellBox() {
  SceneInputArgs a;
  const std::string dir = std::string(MANYLIGHTS_TEST_DATA_DIR) + "/cornell/";
  a.scene = dir + "cornell.gltf";
  a.lights = dir + "lights.json";
  a.camera = dir + "camera.json";
  return loadSceneInputs(a);
}

constexpr unsigned kW = 48, kH = 36;

TEST(ReferenceNoise, EstimateMatchesTheErrorAgainstAManySampleTrace) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  const SceneInputs in = cornellBox();
  const Camera& cam = in.cameras.frames.front();
  const IndirectImage truth = traceIndirectReference(in.scene, in.lights, cam, kW, kH, {1024, seed + 17, false});
  for (unsigned n : {8u, 32u, 128u}) {
    SCOPED_TRACE(std::to_string(n) + " samples");
    const IndirectImage img = traceIndirectReference(in.scene, in.lights, cam, kW, kH, {n, seed, false});
    ASSERT_EQ(img.noise_var.size(), std::size_t(kW) * kH);
    const double estimated = compareWithReference(truth.rgba, img).ref_noise;
    // Measured: the error of the n-sample trace, less the truth's own noise.
    const IndirectComparison c = compareWithReference(img.rgba, truth);
    const double measured = std::sqrt(std::max(0.0, c.error.rel_rmse * c.error.rel_rmse - c.ref_noise * c.ref_noise));
    EXPECT_GT(estimated, 0.65 * measured) << "estimated " << estimated << ", measured " << measured;
    EXPECT_LT(estimated, 1.35 * measured) << "estimated " << estimated << ", measured " << measured;
  }
}

TEST(ReferenceNoise, CorrectedErrorOfAnIndependentTraceIsSmall) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed=" + std::to_string(seed));
  const SceneInputs in = cornellBox();
  const Camera& cam = in.cameras.frames.front();
  const IndirectImage a = traceIndirectReference(in.scene, in.lights, cam, kW, kH, {32, seed, false});
  const IndirectImage b = traceIndirectReference(in.scene, in.lights, cam, kW, kH, {32, seed + 1, false});
  const IndirectComparison c = compareWithReference(a.rgba, b);
  ASSERT_GT(c.error.rel_rmse, 0.0);
  // a = T + noise_a: its error against T is the noise of a, about the
  // reference's, so the corrected error is about the noise, not sqrt(2) times it.
  EXPECT_LT(c.corrected, 1.25 * c.ref_noise) << "raw " << c.error.rel_rmse << ", noise " << c.ref_noise;
  EXPECT_GT(c.error.rel_rmse, 1.2 * c.ref_noise) << "raw " << c.error.rel_rmse << ", noise " << c.ref_noise;
  // One sample has no estimate: no correction, never a made-up number.
  const IndirectImage one = traceIndirectReference(in.scene, in.lights, cam, kW, kH, {1, seed, false});
  EXPECT_EQ(compareWithReference(a.rgba, one).ref_noise, -1.0);
}

TEST(ReferenceCache, ReadsBackWhatWasTracedAndKeysOnItsInputs) {
  const std::string dir = test::tempDir() + "/ref-cache";
  fs::remove_all(dir);
  test::ScopedEnv env("MANYLIGHTS_CACHE_DIR", dir.c_str());
  test::ScopedEnv on("MANYLIGHTS_GI_REFERENCE_CACHE", nullptr);
  SceneInputs in = cornellBox();
  const Camera& cam = in.cameras.frames.front();
  const IndirectOptions o{16, 5, false};
  const CachedReference first = cachedIndirectReference(in.scene, in.lights, cam, kW, kH, o);
  EXPECT_FALSE(first.from_cache);
  ASSERT_TRUE(fs::exists(first.file)) << first.file;
  const CachedReference second = cachedIndirectReference(in.scene, in.lights, cam, kW, kH, o);
  EXPECT_TRUE(second.from_cache);
  EXPECT_EQ(second.image.rgba, first.image.rgba);
  EXPECT_EQ(second.image.noise_var, first.image.noise_var);
  // Another sample count or another light colour is another reference.
  EXPECT_FALSE(cachedIndirectReference(in.scene, in.lights, cam, kW, kH, {17, 5, false}).from_cache);
  in.lights[0].color.x += 0.5f;
  const CachedReference other = cachedIndirectReference(in.scene, in.lights, cam, kW, kH, o);
  EXPECT_FALSE(other.from_cache);
  EXPECT_NE(other.file, first.file);
  // A truncated file is traced again and rewritten whole.
  fs::resize_file(first.file, fs::file_size(first.file) / 2);
  in.lights[0].color.x -= 0.5f;
  const CachedReference again = cachedIndirectReference(in.scene, in.lights, cam, kW, kH, o);
  EXPECT_FALSE(again.from_cache);
  EXPECT_EQ(again.image.rgba, first.image.rgba);
  EXPECT_TRUE(cachedIndirectReference(in.scene, in.lights, cam, kW, kH, o).from_cache);
}

TEST(ReferenceCache, OffTracesEveryTimeAndWritesNothing) {
  const std::string dir = test::tempDir() + "/ref-cache-off";
  fs::remove_all(dir);
  test::ScopedEnv env("MANYLIGHTS_CACHE_DIR", dir.c_str());
  test::ScopedEnv off("MANYLIGHTS_GI_REFERENCE_CACHE", "0");
  const SceneInputs in = cornellBox();
  const CachedReference r = cachedIndirectReference(in.scene, in.lights, in.cameras.frames.front(), 8, 8, {4, 1, false});
  EXPECT_FALSE(r.from_cache);
  EXPECT_TRUE(r.file.empty());
  EXPECT_FALSE(fs::exists(dir));
}

}  // namespace
}  // namespace ml
