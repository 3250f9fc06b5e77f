// Replays the inputs the fuzzers found (tests/fuzz/fuzz_regressions/<target>/) and
// their seed corpora (fuzz/corpus/<target>/) through the fuzzers' own entry
// points (fuzz/FuzzEntryPoints.hpp): each must load or end in a UserError;
// another exception fails here, a crash ends the run (and the ASan/UBSan
// suite reports memory errors the Release build would miss).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fuzz/FuzzEntryPoints.hpp"
#include "ml_build_paths.h"  // MANYLIGHTS_SOURCE_DIR (generated)

namespace ml {
namespace {

namespace fs = std::filesystem;
using Entry = void (*)(const std::uint8_t*, std::size_t);

std::vector<fs::path> filesIn(const fs::path& dir) {
  std::vector<fs::path> out;
  std::error_code ec;
  for (const auto& e : fs::directory_iterator(dir, ec))
    if (e.is_regular_file()) out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

void replay(const std::string& target, Entry entry) {
  const fs::path root(MANYLIGHTS_SOURCE_DIR);
  std::vector<fs::path> inputs = filesIn(root / "fuzz" / "corpus" / target);
  EXPECT_FALSE(inputs.empty()) << "no seed corpus for " << target;
  const auto found = filesIn(root / "tests" / "fuzz" / "fuzz_regressions" / target);
  inputs.insert(inputs.end(), found.begin(), found.end());
  for (const fs::path& file : inputs) {
    SCOPED_TRACE(file.string());
    std::ifstream in(file, std::ios::binary);
    const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    try {
      entry(bytes.data(), bytes.size());
    } catch (const UserError&) {
      // the clean answer to bad input
    } catch (const std::exception& e) {
      ADD_FAILURE() << "not a UserError: " << e.what();
    }
  }
}

TEST(FuzzRegression, GltfInputsLoadOrFailCleanly) { replay("gltf", fuzz::gltf); }
TEST(FuzzRegression, LightInputsLoadOrFailCleanly) { replay("lights", fuzz::lights); }
TEST(FuzzRegression, CameraInputsLoadOrFailCleanly) { replay("camera", fuzz::camera); }
TEST(FuzzRegression, SuiteInputsLoadOrFailCleanly) { replay("suite", fuzz::suite); }
TEST(FuzzRegression, CommandLinesParseOrFailCleanly) { replay("cli", fuzz::cli); }

// The seeds are valid inputs: they must load, not merely fail cleanly, or the
// fuzzers would start from nothing.
TEST(FuzzRegression, SeedCorporaLoad) {
  const fs::path corpus = fs::path(MANYLIGHTS_SOURCE_DIR) / "fuzz" / "corpus";
  const std::pair<const char*, Entry> targets[] = {
      {"gltf", fuzz::gltf}, {"camera", fuzz::camera}, {"suite", fuzz::suite}};
  for (const auto& [name, entry] : targets)
    for (const fs::path& file : filesIn(corpus / name)) {
      SCOPED_TRACE(file.string());
      std::ifstream in(file, std::ios::binary);
      const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
      EXPECT_NO_THROW(entry(bytes.data(), bytes.size()));
    }
  for (const char* cmd : {"render.txt", "bench.txt", "compare.txt", "devices.txt"}) {
    std::ifstream in(corpus / "cli" / cmd, std::ios::binary);
    const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    std::vector<std::string> args{"manylights"};
    for (const auto a : fuzz::split(text, "\n")) args.emplace_back(a);
    std::vector<char*> argv;
    for (auto& a : args) argv.push_back(a.data());
    EXPECT_EQ(parseCli(int(args.size()), argv.data()), -1) << cmd;
  }
}

}  // namespace
}  // namespace ml
