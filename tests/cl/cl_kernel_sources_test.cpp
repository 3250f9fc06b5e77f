// The embedded kernel and shader sources as cmake/embed_files.cmake lays them
// out: one folder per feature under each layer's root (kernels/compute/scan.cl,
// shaders/vct/voxelize.frag; shared/<name>.h flat), every file's includes
// resolve, and no OpenCL C function, kernel or macro is defined in two kernel
// files: what several features use lives once in kernels/common/ (view
// coordinates, frustum boxes, the light grid) or in a feature's own shared
// file (compute/prim_common.cl, clustered/bvh_layout.cl). The texts are those
// the program runs (MANYLIGHTS_SOURCE_DIR reads them from a tree instead).
// GCC 12 misreports std::regex's internal std::function as maybe-uninitialized
// at -O1 (the sanitizer build), and -Werror would fail the build on it; the
// same false positive tests/arch/ parses around. Off for this file only.
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#endif
#include <gtest/gtest.h>

#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "gl/ShaderProgram.hpp"
#include "host/cl/ProgramBuilder.hpp"
#include "host/util/EmbeddedFiles.hpp"

namespace ml {
namespace {

// Whether a line of `text` is still a quoted #include (comments may quote one).
bool hasIncludeLine(const std::string& text) {
  static const std::regex include(R"(^\s*#\s*include\s*")");
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line))
    if (std::regex_search(line, include)) return true;
  return false;
}

std::vector<std::string> keysUnder(const std::string& root) {
  std::vector<std::string> keys;
  for (const auto& f : embeddedFiles())
    if (std::string(f.name).rfind(root, 0) == 0) keys.emplace_back(f.name);
  return keys;
}

// Names a kernel file defines at file scope: functions and kernels (a line
// that opens with __kernel, inline, ML_INLINE or an always_inline attribute,
// up to the first '('), and macros.
std::set<std::string> definedNames(const std::string& text) {
  static const std::regex attribute(R"(__attribute__\(\([^)]*\)\)\s*)");
  static const std::regex function(R"(^(?:__kernel|inline|ML_INLINE)\b[^(]*?\b(\w+)\s*\()");
  static const std::regex macro(R"(^#define\s+(\w+))");
  std::set<std::string> names;
  std::istringstream in(text);
  std::string line;
  std::smatch m;
  while (std::getline(in, line)) {
    const std::string bare = std::regex_replace(line, attribute, "");
    if (std::regex_search(bare, m, function) || std::regex_search(line, m, macro)) names.insert(m[1]);
  }
  return names;
}

TEST(ClKernelSources, KeysNameAFeatureFolderUnderTheirLayer) {
  const std::regex kernel(R"(kernels/[a-z_]+/[a-z0-9_]+\.cl)");
  const std::regex shader(R"(shaders/[a-z_]+/[a-z0-9_]+\.(glsl|vert|frag|geom|comp))");
  const std::regex shared(R"(shared/[a-z0-9_]+\.h)");
  std::size_t kernels = 0, shaders = 0;
  for (const auto& f : embeddedFiles()) {
    const std::string key = f.name;
    const bool ok = std::regex_match(key, kernel) || std::regex_match(key, shader) || std::regex_match(key, shared);
    EXPECT_TRUE(ok) << key;
    kernels += key.rfind("kernels/", 0) == 0;
    shaders += key.rfind("shaders/", 0) == 0;
  }
  EXPECT_GT(kernels, 0u);
  EXPECT_GT(shaders, 0u);
}

TEST(ClKernelSources, EveryKernelFileExpandsItsIncludes) {
  for (const std::string& key : keysUnder("kernels/")) {
    std::string text;
    EXPECT_NO_THROW(text = ProgramBuilder::expandIncludes(key, readEmbeddedFile(key))) << key;
    EXPECT_FALSE(hasIncludeLine(text)) << key << ": an include was left unexpanded";
  }
}

TEST(ClKernelSources, EveryShaderStageExpandsItsIncludes) {
  const ShaderAliases lookup = {{"lookup.glsl", "assign/lookup_brute.glsl"}};
  for (const std::string& key : keysUnder("shaders/")) {
    if (key.ends_with(".glsl")) continue;  // included, never a stage of its own
    const std::string file = key.substr(std::string("shaders/").size());
    std::string text;
    EXPECT_NO_THROW(text = expandShaderSource(file, {}, lookup)) << file;
    EXPECT_FALSE(hasIncludeLine(text)) << file << ": an include was left unexpanded";
  }
}

TEST(ClKernelSources, NoHelperIsDefinedInTwoKernelFiles) {
  std::map<std::string, std::vector<std::string>> where;
  for (const std::string& key : keysUnder("kernels/"))
    for (const std::string& name : definedNames(readEmbeddedFile(key))) where[name].push_back(key);
  ASSERT_GT(where.count("view_coord"), 0u) << "the scan finds no helpers: its patterns no longer fit the sources";
  ASSERT_GT(where.count("write_grid"), 0u);
  for (const auto& [name, files] : where) {
    std::string list;
    for (const auto& f : files) list += " " + f;
    EXPECT_EQ(files.size(), 1u) << name << " is defined in" << list << ": move it into kernels/common/";
  }
}

}  // namespace
}  // namespace ml
