// The folders of host/ and gl/ include each other without a cycle (so a
// technique folder can depend on the interface in host/assign and on gl/
// while the renderer knows only the interface), and host/assign includes
// nothing from gl/. Reads the sources' `#include "folder/..."` lines.
#include "ml_test_paths.h"  // MANYLIGHTS_TEST_DATA_DIR (the source tree's data/)
#include <gtest/gtest.h>

#include "support/RunCommand.hpp"

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <set>
#include <string>

namespace ml {
namespace {

namespace fs = std::filesystem;
using Graph = std::map<std::string, std::set<std::string>>;  // folder -> folders it includes from

// "host/tiled/X.hpp" -> "host/tiled"; "gl/shaders/x" -> "gl"; "" for other headers.
std::string folderOf(const std::string& path) {
  if (path.rfind("gl/", 0) == 0) return "gl";
  if (path.rfind("host/", 0) == 0) {
    const auto slash = path.find('/', 5);
    return slash == std::string::npos ? "" : path.substr(0, slash);
  }
  return "";
}

// The quoted path of an `#include "..."` line, or "" for any other line.
// Parsed by hand: GCC 12's -Wmaybe-uninitialized misfires inside std::regex at
// -O1 (the sanitizer build), and -Werror turns that into a build failure.
std::string quotedInclude(const std::string& line) {
  std::size_t i = line.find_first_not_of(" \t");
  if (i == std::string::npos || line[i] != '#') return "";
  i = line.find_first_not_of(" \t", i + 1);
  if (i == std::string::npos || line.compare(i, 7, "include") != 0) return "";
  i = line.find_first_not_of(" \t", i + 7);
  if (i == std::string::npos || line[i] != '"') return "";
  const std::size_t end = line.find('"', i + 1);
  return end == std::string::npos ? "" : line.substr(i + 1, end - i - 1);
}

Graph includeGraph(const fs::path& root) {
  Graph g;
  for (const char* top : {"host", "gl"})
    for (const auto& e : fs::recursive_directory_iterator(root / top)) {
      const std::string ext = e.path().extension().string();
      if (!e.is_regular_file() || (ext != ".cpp" && ext != ".hpp")) continue;
      const std::string from = folderOf(fs::relative(e.path(), root).generic_string());
      std::ifstream in(e.path());
      for (std::string line; std::getline(in, line);)
        if (const std::string to = folderOf(quotedInclude(line)); !to.empty() && to != from) g[from].insert(to);
    }
  return g;
}

// A cycle as "a -> b -> a", or "" when there is none.
std::string findCycle(const Graph& g) {
  std::map<std::string, int> state;  // 1 on the stack, 2 done
  std::vector<std::string> stack;
  std::string cycle;
  std::function<bool(const std::string&)> visit = [&](const std::string& n) {
    state[n] = 1;
    stack.push_back(n);
    if (auto it = g.find(n); it != g.end())
      for (const auto& m : it->second) {
        if (state[m] == 1) {
          for (auto s = std::find(stack.begin(), stack.end(), m); s != stack.end(); ++s) cycle += *s + " -> ";
          cycle += m;
          return true;
        }
        if (state[m] == 0 && visit(m)) return true;
      }
    stack.pop_back();
    state[n] = 2;
    return false;
  };
  for (const auto& [n, edges] : g)
    if (state[n] == 0 && visit(n)) return cycle;
  return "";
}

TEST(IncludeGraph, FoldersHaveNoCycleAndAssignIncludesNoGl) {
  const Graph g = includeGraph(fs::path(MANYLIGHTS_TEST_DATA_DIR).parent_path());
  ASSERT_TRUE(g.count("host/app")) << "no includes found: wrong source tree?";
  EXPECT_EQ(findCycle(g), "");
  EXPECT_FALSE(g.at("host/assign").count("gl"));
  // The check can fail: a cycle planted in a copy of the graph is found.
  Graph planted = g;
  planted["host/assign"].insert("host/tiled");
  EXPECT_NE(findCycle(planted), "");
}

// The build's layer check (scripts/check_layers.py, run by CMake before any
// layer compiles, against the layers CMakeLists.txt declares): the tree passes.
TEST(LayerCheck, TheSourceTreePassesTheBuildsCheck) {
  const fs::path root = fs::path(MANYLIGHTS_TEST_DATA_DIR).parent_path();
  const test::CommandResult r = test::runShell("python3 " + (root / "scripts/check_layers.py").string() + " " +
                                               MANYLIGHTS_LAYERS_FILE + " " + root.string());
  EXPECT_EQ(r.exit_code, 0) << r.err;
}

// An include that goes up a layer fails the check, naming the file, the line
// and the layer it would need: planted in a scratch tree checked against the
// real declarations (compute sits below vct, and below the run layer).
TEST(LayerCheck, AnIncludeUpALayerFailsTheBuild) {
  const fs::path root = fs::path(MANYLIGHTS_TEST_DATA_DIR).parent_path();
  const fs::path tree = fs::path(test::tempDir()) / "planted-layers";
  fs::remove_all(tree);
  fs::create_directories(tree / "host/compute");
  fs::create_directories(tree / "host/vct");
  std::ofstream(tree / "host/compute/Planted.hpp") << "#pragma once\n#include \"host/cl/ClRuntime.hpp\"\n"
                                                      "#include \"host/vct/VoxelMips.hpp\"\n";
  std::ofstream(tree / "host/vct/Fine.hpp") << "#include \"host/compute/Scan.hpp\"\n";
  const std::string check = "python3 " + (root / "scripts/check_layers.py").string() + " " + MANYLIGHTS_LAYERS_FILE + " ";
  const test::CommandResult r = test::runShell(check + tree.string());
  EXPECT_EQ(r.exit_code, 1) << r.err;
  EXPECT_NE(r.err.find("host/compute/Planted.hpp:3: includes host/vct/VoxelMips.hpp"), std::string::npos) << r.err;
  EXPECT_EQ(r.err.find("Fine.hpp"), std::string::npos) << "a downward include was refused: " << r.err;
  EXPECT_EQ(r.err.find("ClRuntime"), std::string::npos) << r.err;
  // A twin is for tests and benches: production code including one fails too.
  fs::remove(tree / "host/compute/Planted.hpp");
  std::ofstream(tree / "host/vct/UsesTwin.cpp") << "#include \"host/vct/InjectTwin.hpp\"\n";
  const test::CommandResult t = test::runShell(check + tree.string());
  EXPECT_EQ(t.exit_code, 1) << t.err;
  EXPECT_NE(t.err.find("UsesTwin.cpp:1: includes the twin host/vct/InjectTwin.hpp"), std::string::npos) << t.err;
}

}  // namespace
}  // namespace ml
