// Bad input to `render` and `bench` (issue 18, items 3-7): every case is one
// line on stderr naming the flag, exit code 2, and, where the check belongs
// before any work, nothing on stdout (no start-up lines) before it. Output
// files are checked before the first frame and never left complete-looking by
// an interrupted run; reports carry no machine paths.
#include "ml_test_paths.h"  // MANYLIGHTS_BINARY, MANYLIGHTS_TEST_DATA_DIR (generated)
#include <gtest/gtest.h>

#include <fcntl.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <thread>

#include "suite/suite_support.hpp"
#include "support/RunCommand.hpp"
#include "support/TempDir.hpp"

// GCC names AddressSanitizer builds with __SANITIZE_ADDRESS__, clang with __has_feature.
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define ML_CLANG_ASAN 1
#endif
#endif
#ifndef ML_CLANG_ASAN
#define ML_CLANG_ASAN 0
#endif

namespace ml {
namespace {

namespace fs = std::filesystem;
using test::CommandResult;
using test::lines;
using test::runManylights;
using test::TempDir;

// Exit 2, one stderr line mentioning every string of `mentions`, and (with
// `quiet`) nothing on stdout: the check ran before GL/CL printed anything.
void expectRefused(const CommandResult& r, std::initializer_list<std::string> mentions, bool quiet = true) {
  EXPECT_EQ(r.exit_code, 2) << "stdout: " << r.out << "\nstderr: " << r.err;
  EXPECT_EQ(lines(r.err), 1) << "expected one line: " << r.err;
  for (const auto& m : mentions) EXPECT_NE(r.err.find(m), std::string::npos) << "expected '" << m << "' in: " << r.err;
  if (quiet) {
    EXPECT_EQ(r.out, "") << "expected no output before the error";
  }
}

// Runs the binary under `ulimit -v kib` (an address-space limit).
CommandResult runLimited(const std::string& args, long kib) {
  std::string cmd = "sh -c 'ulimit -v ";
  cmd += std::to_string(kib);
  cmd += " && exec ";
  cmd += MANYLIGHTS_BINARY;
  cmd += " " + args + "'";
  return test::runShell(cmd);
}

TEST(CliInputs, LightCountAboveTheMaximumBeforeGeneration) {
  // Used to exit 3 with std::bad_alloc after trying to allocate 32 GB.
  expectRefused(runManylights("render --size 16x16 --lights 1000000000"), {"--lights", "134217728"});
  expectRefused(runManylights("render --size 16x16 --lights 5000000000"), {"--lights", "134217728"});
  expectRefused(runManylights("bench --techniques deferred --size 16x16 --frames 0 --lights 64,1000000000"),
                {"--lights", "134217728"});
}

TEST(CliInputs, LightCountAboveTheMemoryLimit) {
#if defined(__SANITIZE_ADDRESS__) || ML_CLANG_ASAN
  // ASan reserves terabytes of shadow memory at start-up, which `ulimit -v`
  // forbids; the Release run of the suite covers this case.
  GTEST_SKIP() << "ulimit -v cannot hold an AddressSanitizer process";
#endif
  // 100M lights are under the maximum but need ~48 GiB; under a 2 GiB
  // address-space limit the estimate refuses them before generating any.
  const auto r = runLimited("render --size 16x16 --lights 100000000", 2L * 1024 * 1024);
  expectRefused(r, {"--lights", "memory", "available"});
}

TEST(CliInputs, HashedLightLimitBeforeGeneration) {
  // Hashed shading's 24-bit list entries: checked before the lights are
  // generated and before GL/CL open, not when the structure is built.
  expectRefused(runManylights("render --size 16x16 --technique hashed-deferred --lights 16777216"),
                {"--lights", "hashed-deferred", "16777215"});
  expectRefused(runManylights("bench --techniques deferred,hashed-forward --size 16x16 --frames 0 --lights 16777216"),
                {"--lights", "hashed-forward", "16777215"});
}

TEST(CliInputs, LightRadiusMustBeFinitePositive) {
  for (const char* v : {"0", "-1", "nan", "inf", "x"}) {
    SCOPED_TRACE(v);
    expectRefused(runManylights(std::string("render --size 16x16 --lights 32 --light-radius=") + v),
                  {"--light-radius"});
  }
  expectRefused(runManylights("bench --techniques deferred --size 16x16 --frames 0 --lights 32 --light-radius=-2"),
                {"--light-radius"});
  // A light file carries its own radii: a radius for it would be ignored.
  expectRefused(runManylights("render --size 16x16 --light-radius 2"), {"--light-radius"});
}

TEST(CliInputs, ImageOutputsArePngOrExr) {
  TempDir dir;
  expectRefused(runManylights("render --size 16x16 --lights 8 --out " + dir.file("x.bmp")), {"--out", ".png", ".exr"});
  expectRefused(runManylights("render --size 16x16 --lights 8 --heatmap " + dir.file("h.jpg")), {"--heatmap", ".png"});
  expectRefused(runManylights("render --size 16x16 --lights 8 --out " + dir.file("noext")), {"--out", ".png"});
  EXPECT_FALSE(fs::exists(dir.file("x.bmp")));
}

TEST(CliInputs, UnwritableOutputsBeforeTheFirstFrame) {
  TempDir dir;
  // Below a plain file no folder can be made, whoever runs the test (root too).
  const std::string blocked = dir.write("a-file", "x") + "/sub";
  expectRefused(runManylights("render --size 16x16 --lights 8 --out " + blocked + "/o.png"), {"--out", blocked});
  expectRefused(runManylights("render --size 16x16 --lights 8 --stats-json " + blocked + "/s.json"), {"--stats-json"});
  const std::string bench = "bench --techniques deferred --size 16x16 --frames 0 --lights 8 --progress none ";
  expectRefused(runManylights(bench + "--images " + blocked), {"--images", blocked});  // used to exit 3
  expectRefused(runManylights(bench + "--json " + blocked + "/b.json"), {"--json"});
  expectRefused(runManylights(bench + "--csv " + blocked + "/b.csv"), {"--csv"});
  expectRefused(runManylights(bench + "--plot " + blocked), {"--plot"});
  expectRefused(runManylights(bench + "--json " + dir.file("")), {"--json", "folder"});
}

// /proc and /sys are refused before anything is made there, as written or
// through a link: /proc/self/root/<tmp> is a writable folder when the test
// runs as root, /proc/foo.png is not (its refusal used to name errno only).
TEST(CliInputs, OutputsUnderProcOrSysAreRefused) {
  TempDir dir;
  const std::string via_proc = "/proc/self/root" + fs::weakly_canonical(dir.file("")).string();
  ASSERT_TRUE(fs::is_directory(via_proc)) << via_proc << ": the link the test relies on is missing";
  const std::string render = "render --size 16x16 --lights 8 ";
  expectRefused(runManylights(render + "--out /proc/foo.png"), {"--out", "/proc"});
  expectRefused(runManylights(render + "--out /sys/foo.png"), {"--out", "/sys"});
  expectRefused(runManylights(render + "--out " + via_proc + "/o.png"), {"--out", "/proc"});
  expectRefused(runManylights(render + "--stats-json " + via_proc + "/s.json"), {"--stats-json", "/proc"});
  const std::string bench = "bench --techniques deferred --size 16x16 --frames 0 --lights 8 --progress none ";
  expectRefused(runManylights(bench + "--json " + via_proc + "/b.json"), {"--json", "/proc"});
  expectRefused(runManylights(bench + "--images " + via_proc + "/images"), {"--images", "/proc"});
  for (const char* made : {"o.png", "s.json", "b.json", "images"})
    EXPECT_FALSE(fs::exists(dir.file(made))) << made << " was written through /proc";
  // Links that lead out of /proc are followed: a link to /proc is refused too.
  const std::string link = dir.file("to-proc");
  fs::create_directory_symlink("/proc", link);
  expectRefused(runManylights(render + "--out " + link + "/foo.png"), {"--out", "/proc"});
}

// Outputs that are not files are written in place: the process's stdout by
// its name (/dev/stdout, as a pipe and redirected to a file), /dev/null, and a
// link to a file (written through; the link stays). A rename over
// /dev/stdout used to replace the device name itself when run as root.
TEST(CliInputs, StreamOutputsAreWrittenInPlace) {
  TempDir dir;
  const std::string render = std::string(MANYLIGHTS_BINARY) + " render --size 16x16 --lights 8 --frames 1 ";
  const CommandResult piped = test::runShell("(" + render + "--stats-json /dev/stdout | cat)");
  ASSERT_EQ(piped.exit_code, 0) << piped.err;
  const std::size_t open = piped.out.find("\n{");
  ASSERT_NE(open, std::string::npos) << "no JSON after the report on stdout: " << piped.out;
  EXPECT_TRUE(nlohmann::json::accept(piped.out.substr(open + 1))) << piped.out;
  EXPECT_TRUE(fs::is_symlink("/dev/stdout") || fs::is_character_file("/dev/stdout")) << "/dev/stdout was replaced";
  const std::string redirected = dir.file("out.txt");
  const CommandResult to_file = test::runShell("(" + render + "--stats-json /dev/stdout > " + redirected + ")");
  ASSERT_EQ(to_file.exit_code, 0) << to_file.err;
  std::ifstream in(redirected);
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("lights"), std::string::npos) << "the report before the JSON was lost: " << text;
  EXPECT_NE(text.find("\n{"), std::string::npos) << "no JSON after the report: " << text;
  const CommandResult null = test::runShell(render + "--stats-json /dev/null");
  EXPECT_EQ(null.exit_code, 0) << null.err;
  EXPECT_TRUE(fs::is_character_file("/dev/null")) << "/dev/null was replaced";
  const std::string real = dir.write("real.json", "old"), link = dir.file("link.json");
  fs::create_symlink(real, link);
  ASSERT_EQ(test::runShell(render + "--stats-json " + link).exit_code, 0);
  EXPECT_TRUE(fs::is_symlink(link)) << "the link was replaced by a file";
  std::ifstream json(real);
  EXPECT_TRUE(nlohmann::json::accept(json)) << "the linked file was not written";
}

TEST(CliInputs, EmptyTechniqueListIsRefused) {
  // Used to run every registered technique.
  expectRefused(runManylights("bench --techniques '' --size 16x16 --frames 0 --lights 8"), {"--techniques"});
  expectRefused(runManylights("bench --techniques , --size 16x16 --frames 0 --lights 8"), {"--techniques"});
  expectRefused(runManylights("bench --techniques deferred --lights '' --size 16x16 --frames 0"), {"--lights"});
}

TEST(CliInputs, TechniqueFlagsBeforeStartUp) {
  expectRefused(runManylights("render --size 16x16 --lights 8 --technique hashed-deferred --node-size big"),
                {"--node-size"});
  expectRefused(runManylights("render --size 16x16 --lights 8 --technique tiled-deferred --tile-depth deep"),
                {"--tile-depth"});
  expectRefused(runManylights("render --size 16x16 --lights 8 --technique clustered-deferred --unique magic"),
                {"--unique"});
  expectRefused(runManylights("render --size 16x16 --lights 8 --technique tiled-deferred --tile 257"), {"--tile"});
  expectRefused(runManylights("render --size 16x16 --lights 8 --technique deferred --cluster-view /tmp/c.png"),
                {"--cluster-view"});
}

// A bench killed after its first finished run leaves its results so far in
// <json>.partial, marked incomplete, and no file under the name it was given.
TEST(CliInputs, InterruptedBenchLeavesNoCompleteLookingJson) {
  TempDir dir;
  const std::string json = dir.file("b.json"), csv = dir.file("b.csv");
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const int null = ::open("/dev/null", O_WRONLY);
    ::dup2(null, 1);
    ::dup2(null, 2);
    ::execl(MANYLIGHTS_BINARY, MANYLIGHTS_BINARY, "bench", "--techniques", "tiled-deferred", "--param",
            "tile=8,16,32,64,128,256", "--lights", "64", "--size", "32x24", "--frames", "0", "--progress", "none",
            "--json", json.c_str(), "--csv", csv.c_str(), static_cast<char*>(nullptr));
    ::_exit(127);
  }
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(300);
  bool seen = false;
  while (!seen && std::chrono::steady_clock::now() < deadline) {
    seen = fs::exists(json) || fs::exists(json + ".partial");
    int status = 0;
    if (!seen && ::waitpid(pid, &status, WNOHANG) == pid) FAIL() << "bench ended before writing any results";
    if (!seen) std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  ::kill(pid, SIGKILL);
  ::waitpid(pid, nullptr, 0);
  ASSERT_TRUE(seen) << "no results after 300 s";
  EXPECT_FALSE(fs::exists(json)) << "an interrupted run left a complete-looking " << json;
  EXPECT_FALSE(fs::exists(csv)) << "an interrupted run left a complete-looking " << csv;
  ASSERT_TRUE(fs::exists(json + ".partial"));
  std::ifstream in(json + ".partial");
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["meta"]["complete"], false);
  EXPECT_EQ(j["meta"]["records_planned"], 6);
  EXPECT_LT(j["records"].size(), 6u);
}

// A finished bench: complete JSON, no .partial left, no machine paths.
TEST(CliInputs, FinishedBenchIsCompleteAndRecordsNoMachinePaths) {
  TempDir dir;
  const std::string json = dir.file("b.json");
  const auto r = runManylights("bench --techniques deferred,forward --lights 16 --size 16x16 --frames 0 "
                               "--progress none --json " + json);
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_FALSE(fs::exists(json + ".partial"));
  std::ifstream in(json);
  const auto j = nlohmann::json::parse(in);
  EXPECT_EQ(j["meta"]["complete"], true);
  EXPECT_EQ(j["records"].size(), 2u);
  EXPECT_EQ(j["meta"]["scene"]["source"], "data/default/scene.glb");
  EXPECT_EQ(j["meta"]["command"].get<std::string>().rfind("manylights bench ", 0), 0u) << j["meta"]["command"];
  const std::string data_dir = fs::weakly_canonical(MANYLIGHTS_TEST_DATA_DIR).string();
  EXPECT_EQ(r.out.find(data_dir), std::string::npos) << r.out;
}

TEST(CliInputs, RenderReportsNoMachinePaths) {
  const auto r = runManylights("render --size 16x16 --frames 1 --warmup 0");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.out.find("scene: data/default/scene.glb"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("(data/default/lights.json)"), std::string::npos) << r.out;
}

// render, view, bench and compare-reference take the scene, suite, device and
// progress flags from one adder: the same names and help on every command.
TEST(CliInputs, SharedInputFlagsOnEveryCommand) {
  const std::vector<std::pair<std::string, std::vector<std::string>>> expected = {
      {"render", {"--scene,--suite", "--camera", "--lights", "--light-volumes", "--seed", "--geometry",
                  "--allow-missing-meshes", "--device"}},
      {"view", {"--scene,--suite", "--camera", "--lights", "--light-volumes", "--seed", "--geometry",
                "--allow-missing-meshes", "--device"}},
      {"bench", {"--scene,--suite", "--camera", "--light-volumes", "--seed", "--geometry", "--allow-missing-meshes",
                 "--device", "--progress"}},
      {"compare-reference", {"--geometry", "--allow-missing-meshes", "--device", "--progress"}},
  };
  std::string device_help;
  for (const auto& [cmd, flags] : expected) {
    const auto r = runManylights(cmd + " --help");
    ASSERT_EQ(r.exit_code, 0) << cmd << r.err;
    for (const auto& f : flags) EXPECT_NE(r.out.find("  " + f + " "), std::string::npos) << cmd << " " << f;
    const auto at = r.out.find("  --device ");
    ASSERT_NE(at, std::string::npos) << cmd;
    const std::string line = r.out.substr(at, r.out.find('\n', at) - at);
    if (device_help.empty()) device_help = line;
    EXPECT_EQ(line, device_help) << cmd;
  }
}

// `render` takes the thesis suite as `bench` does: the published copy lacks a
// mesh, and the loader's error names --allow-missing-meshes, which render
// used to refuse as an unknown flag, so the suite could not be rendered.
TEST(CliInputs, RenderTakesASuiteWithAMissingMesh) {
  TempDir dir;
  const std::string suite = test::writeSmallSuite(dir.file("suites"), "with-missing", true);
  expectRefused(runManylights("render --scene " + suite + " --size 16x16 --frames 1 --warmup 0"),
                {"Gone.obj", "--allow-missing-meshes"});
  const auto ok =
      runManylights("render --scene " + suite + " --allow-missing-meshes --size 16x16 --frames 1 --warmup 0");
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  EXPECT_NE((ok.out + ok.err).find("Gone"), std::string::npos) << "expected a warning naming the missing mesh";
}

// `render` resolves its scene like `bench`: a folder in the project's format
// brings its camera path and lights (data/default/ is the default scene).
TEST(CliInputs, RenderTakesASceneFolder) {
  const std::string folder = (fs::path(MANYLIGHTS_TEST_DATA_DIR) / "default").string();
  const auto by_folder = runManylights("render --scene " + folder + " --size 16x16 --frames 1 --warmup 0 --counts");
  const auto by_default = runManylights("render --size 16x16 --frames 1 --warmup 0 --counts");
  ASSERT_EQ(by_folder.exit_code, 0) << by_folder.err;
  ASSERT_EQ(by_default.exit_code, 0) << by_default.err;
  auto counts = [](const std::string& out) { return out.substr(out.find("light evaluations")); };
  EXPECT_EQ(counts(by_folder.out), counts(by_default.out));
  EXPECT_NE(by_folder.out.find("lights: 1024 ("), std::string::npos) << by_folder.out;
  expectRefused(runManylights("render --scene " + folder + "/no-such-folder-or.obj"),
                {"--scene", "no-such-folder-or.obj"});
}

std::string base64(const std::string& in) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < in.size(); i += 3) {
    unsigned v = static_cast<unsigned char>(in[i]) << 16;
    if (i + 1 < in.size()) v |= static_cast<unsigned char>(in[i + 1]) << 8;
    if (i + 2 < in.size()) v |= static_cast<unsigned char>(in[i + 2]);
    out += table[v >> 18];
    out += table[(v >> 12) & 63];
    out += i + 1 < in.size() ? table[(v >> 6) & 63] : '=';
    out += i + 2 < in.size() ? table[v & 63] : '=';
  }
  return out;
}

TEST(CliInputs, GltfWarningsGoToStderr) {
  // One triangle, and the same points as a LINES primitive (skipped with a warning).
  const float pos[9] = {0, 0, 0, 1, 0, 0, 0, 1, 0};
  std::string bytes(sizeof pos, '\0');
  std::memcpy(bytes.data(), pos, sizeof pos);
  nlohmann::json doc = {
      {"asset", {{"version", "2.0"}}},
      {"buffers", {{{"byteLength", bytes.size()}, {"uri", "data:application/octet-stream;base64," + base64(bytes)}}}},
      {"bufferViews", {{{"buffer", 0}, {"byteLength", bytes.size()}}}},
      {"accessors",
       {{{"bufferView", 0}, {"componentType", 5126}, {"count", 3}, {"type", "VEC3"}, {"min", {0, 0, 0}},
         {"max", {1, 1, 0}}}}},
      {"meshes", {{{"primitives", {{{"attributes", {{"POSITION", 0}}}}, {{"attributes", {{"POSITION", 0}}}, {"mode", 1}}}}}}},
      {"nodes", {{{"mesh", 0}}}},
      {"scenes", {{{"nodes", {0}}}}},
      {"scene", 0}};
  TempDir dir;
  const std::string scene = dir.write("lines.gltf", doc.dump());
  const auto r = runManylights("render --scene " + scene + " --lights 4 --size 16x16 --frames 1 --warmup 0");
  ASSERT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find("skipped"), std::string::npos) << "stderr: " << r.err;
  EXPECT_EQ(r.out.find("skipped"), std::string::npos) << "stdout: " << r.out;
}

}  // namespace
}  // namespace ml
