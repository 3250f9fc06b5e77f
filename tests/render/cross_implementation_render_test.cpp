// Every registered technique renders the same image with the same light counts
// on two independent OpenCL implementations: PoCL (work-items of a group run
// one after another) and Mesa rusticl (clang -> SPIR-V -> NIR -> llvmpipe,
// work-items as SIMD lanes). A kernel that relies on an order of work-items,
// on reading what another item writes without a barrier, or on one compiler's
// output gives different lists on one of them, and so a different image or
// count here. The tiled and clustered techniques run both kernel shapes,
// named, on both (Auto differs: rusticl's loop cap makes tiled pick the GPU
// shape there). The CPU shape's lists come out in light order, so its images
// are equal byte for byte; the GPU shape's are in atomic order, which may
// differ between runs and implementations, so its shading sums may round
// apart: its counts are equal and its images within one 8-bit step.
// Needs both implementations (scripts/packages.txt installs them); with one
// missing the test is skipped saying which package to install.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "host/util/ImageIO.hpp"
#include "support/ImageCompare.hpp"
#include "support/RunCommand.hpp"

namespace {

using ml::test::CommandResult;
using ml::test::runManylights;

const char* const kRusticlEnv = "RUSTICL_ENABLE=llvmpipe";

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::vector<std::string> registeredTechniques() {
  const CommandResult r = runManylights("techniques");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  std::vector<std::string> names;
  std::istringstream in(r.out);
  for (std::string line; std::getline(in, line);)
    if (!line.empty()) names.push_back(line.substr(0, line.find(' ')));
  return names;
}

bool isTime(const std::string& key) { return key.size() > 3 && key.compare(key.size() - 3, 3, " ms") == 0; }

// The fields of the stats JSON that must not depend on the implementation:
// everything but times, clocks and the names of the devices.
nlohmann::json countsOf(const nlohmann::json& stats) {
  nlohmann::json out;
  for (const char* key : {"technique", "lights", "light_evaluations", "lower_bound", "missed_lights",
                          "covered_pixels", "fragment_evaluations", "memory_bytes"})
    out[key] = stats.at(key);
  for (const auto& [key, value] : stats.at("technique_stats").items())
    if (!isTime(key)) out["technique_stats"][key] = value;
  return out;
}

struct Rendered {
  std::string image, heatmap, path;
  nlohmann::json counts;
};

std::string shapeSuffix(const std::string& extra) {
  if (extra.empty()) return "";
  return extra.find("gpu") != std::string::npos ? "-gpu" : "-cpu";
}

Rendered render(const std::string& device, const std::string& technique, const std::string& extra) {
  const std::string base = ml::test::tempDir() + "/" + device + "-" + technique + shapeSuffix(extra);
  const std::string args = "render --device " + device + " --technique " + technique +
                           " --size 96x64 --lights 300 --frames 1 --counts --out " + base + ".png --heatmap " +
                           base + "-heat.png --stats-json " + base + ".json " + extra;
  const CommandResult r = runManylights(args, kRusticlEnv);
  EXPECT_EQ(r.exit_code, 0) << args << "\n" << r.err;
  if (r.exit_code != 0) return {};
  return {slurp(base + ".png"), slurp(base + "-heat.png"), base + ".png", countsOf(ml::test::readJson(base + ".json"))};
}

bool hasKernelShapes(const std::string& technique) {
  return technique.rfind("tiled", 0) == 0 || technique.rfind("clustered", 0) == 0;
}

TEST(CrossImplementation, EveryTechniqueRendersTheSameOnPoclAndRusticl) {
  const CommandResult devices = runManylights("devices", kRusticlEnv);
  ASSERT_EQ(devices.exit_code, 0) << devices.err;
  if (devices.out.find("rusticl") == std::string::npos || devices.out.find("Portable Computing Language") ==
                                                              std::string::npos)
    GTEST_SKIP() << "needs PoCL and Mesa rusticl (apt-get install pocl-opencl-icd mesa-opencl-icd); found:\n"
                 << devices.out;
  const std::vector<std::string> techniques = registeredTechniques();
  ASSERT_GE(techniques.size(), 8u);
  for (const std::string& t : techniques) {
    std::vector<std::string> variants{""};
    if (hasKernelShapes(t)) variants = {"--kernel-shape cpu", "--kernel-shape gpu"};
    for (const std::string& extra : variants) {
      SCOPED_TRACE(t + " " + extra);
      Rendered pocl = render("pocl", t, extra);
      Rendered rusticl = render("rusticl", t, extra);
      ASSERT_FALSE(pocl.image.empty());
      ASSERT_FALSE(rusticl.image.empty());
      if (t.rfind("tiled", 0) == 0 && extra == "--kernel-shape cpu") {
        // The CPU shape's per-chunk tile counters follow the device: llvmpipe
        // caps a work-item's loops, so rusticl takes shorter chunks (more
        // counter rows) than PoCL for the same lists.
        EXPECT_GE(rusticl.counts.at("memory_bytes"), pocl.counts.at("memory_bytes"));
        pocl.counts.erase("memory_bytes");
        rusticl.counts.erase("memory_bytes");
      }
      EXPECT_EQ(pocl.counts, rusticl.counts);
      EXPECT_EQ(pocl.counts.at("missed_lights"), 0);
      EXPECT_TRUE(pocl.heatmap == rusticl.heatmap) << "the heat maps differ";
      if (extra != "--kernel-shape gpu") {
        EXPECT_TRUE(pocl.image == rusticl.image) << "the images differ";
        continue;
      }
      unsigned w = 0, h = 0, w2 = 0, h2 = 0;
      const auto a = ml::readImageRgba(pocl.path, w, h), b = ml::readImageRgba(rusticl.path, w2, h2);
      ASSERT_EQ(w * h, w2 * h2);
      EXPECT_LE(ml::test::compareImages(a, b, 0.0).max_abs, 1.0 / 255.0 + 1e-6);
    }
  }
}

}  // namespace
