// The benchmark's data model without rendering: frame ranges, summaries,
// parameter sweeps per technique, and the JSON/CSV schema of records.
#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>

#include "host/run/RunRecords.hpp"
#include "host/util/Error.hpp"

namespace ml {
namespace {

std::vector<std::size_t> frames(const std::string& spec, std::size_t n) {
  return selectFrames(parseFrameRange(spec, "--frames"), n, "--frames");
}

TEST(BenchTypes, FrameRanges) {
  EXPECT_EQ(frames("3:10:3", 100), (std::vector<std::size_t>{3, 6, 9}));
  EXPECT_EQ(frames("3:9:3", 100), (std::vector<std::size_t>{3, 6, 9}));  // LAST inclusive
  EXPECT_EQ(frames("7", 100), (std::vector<std::size_t>{7}));
  EXPECT_EQ(frames("::4", 10), (std::vector<std::size_t>{0, 4, 8}));
  EXPECT_EQ(frames("5:", 8), (std::vector<std::size_t>{5, 6, 7}));
  EXPECT_EQ(frames(":2", 8), (std::vector<std::size_t>{0, 1, 2}));
  EXPECT_EQ(frames("3:518:64", 519).size(), 9u);  // 3, 67, ..., 515
  EXPECT_EQ(frames("0:1000", 4).back(), 3u);     // clamped to the path
  EXPECT_EQ(selectFrames(FrameRange{}, 3, "--frames").size(), 3u);
  for (const char* bad : {"", "a", "1:2:0", "5:2", "1:2:3:4", "-1:5", "1:x"})
    EXPECT_THROW(parseFrameRange(bad, "--frames"), UserError) << bad;
  try {
    frames("9", 5);
    FAIL();
  } catch (const UserError& e) {
    EXPECT_NE(std::string(e.what()).find("--frames"), std::string::npos);
  }
}

TEST(BenchTypes, SummaryMatchesNumpy) {
  std::vector<double> v;
  for (int i = 20; i >= 1; --i) v.push_back(i);
  const Summary s = summarize(v);
  EXPECT_EQ(s.n, 20u);
  EXPECT_DOUBLE_EQ(s.mean, 10.5);
  EXPECT_DOUBLE_EQ(s.median, 10.5);
  EXPECT_NEAR(s.p95, 19.05, 1e-12);  // numpy.percentile(range(1, 21), 95)
  EXPECT_DOUBLE_EQ(s.max, 20);
  EXPECT_DOUBLE_EQ(s.min, 1);
  EXPECT_EQ(summarize({}).n, 0u);
  EXPECT_DOUBLE_EQ(summarize({4}).p95, 4);
}

std::vector<std::string> keysOf(const std::string& technique) {
  std::vector<std::string> keys;
  for (const auto& p : findTechnique(technique).descriptor->params) keys.push_back(p.key);
  return keys;
}

TEST(BenchTypes, SweepsOnlyTheKeysATechniqueReads) {
  std::vector<std::string> names;
  for (const auto& t : techniques()) names.push_back(t.name);
  const ParamSweep sweep = {{"tile", {"8", "16", "32"}}, {"cluster_tile", {"16", "64"}}, {"node_size", {"0.5r", "2"}}};
  const auto vars = expandVariants(names, sweep, "--param");
  for (const auto& name : names) {
    const auto n = std::count_if(vars.begin(), vars.end(), [&](const TechniqueVariant& v) { return v.technique == name; });
    std::size_t expected = 1;
    for (const auto& key : keysOf(name))
      for (const auto& s : sweep)
        if (s.first == key) expected *= s.second.size();
    EXPECT_EQ(static_cast<std::size_t>(n), expected) << name;
  }
  // The brute-force techniques read no parameter: one variant, plain label.
  const auto brute = expandVariants({"deferred"}, sweep, "--param");
  ASSERT_EQ(brute.size(), 1u);
  EXPECT_EQ(brute[0].label, "deferred");
  EXPECT_EQ(keysOf("tiled-deferred"), (std::vector<std::string>{"tile", "tile_depth", "kernel_shape"}));
  EXPECT_EQ(keysOf("clustered-forward").front(), "cluster_tile");
  EXPECT_EQ(keysOf("hashed-deferred").front(), "node_size");
}

TEST(BenchTypes, ParamValuesAreChecked) {
  const auto tiled = expandVariants({"tiled-deferred"}, {{"tile", {"8"}}, {"tile_depth", {"none"}},
                                                          {"kernel_shape", {"gpu"}}}, "--param");
  ASSERT_EQ(tiled.size(), 1u);
  EXPECT_EQ(tiled[0].params.count("tile"), 8u);
  EXPECT_EQ(tiled[0].params.text("tile_depth"), "none");
  EXPECT_EQ(tiled[0].params.text("kernel_shape"), "gpu");
  EXPECT_EQ(tiled[0].label, "tiled-deferred[tile=8,tile_depth=none,kernel_shape=gpu]");
  const auto hashed = expandVariants({"hashed-forward"}, {{"node_size", {"0.25r"}}, {"geometry_mask", {"on"}}}, "--param");
  ASSERT_EQ(hashed.size(), 1u);
  EXPECT_EQ(hashed[0].params.text("node_size"), "0.25r");
  EXPECT_TRUE(hashed[0].params.on("geometry_mask"));
  EXPECT_TRUE(hashed[0].params.on("octant_masks"));  // the default
  const auto clustered = expandVariants({"clustered-deferred"}, {{"cluster_tile", {"64", "auto"}}}, "--param");
  ASSERT_EQ(clustered.size(), 2u);
  EXPECT_EQ(clustered[0].params.count("cluster_tile"), 64u);
  EXPECT_EQ(clustered[1].params.count("cluster_tile"), 0u);
  for (auto [k, v] : std::vector<std::pair<std::string, std::string>>{
           {"tile", "-1"}, {"tile", "x"}, {"tile", "257"}, {"cluster_tile", "1025"}, {"tile_depth", "deep"},
           {"node_size", "-1"}, {"node_size", "r"}, {"unique", "magic"}, {"kernel_shape", "warp"},
           {"start_depth", "17"}, {"nonsense", "1"}}) {
    try {
      checkParam(k, v, "--param");
      FAIL() << k << "=" << v;
    } catch (const UserError& e) {
      EXPECT_NE(std::string(e.what()).find("--param"), std::string::npos);
      EXPECT_NE(std::string(e.what()).find(k), std::string::npos);
    }
  }
  EXPECT_THROW(expandVariants({"no-such-technique"}, {}, "--param"), UserError);
}

FrameRecord record(const std::string& run, std::size_t frame, std::uint64_t evals, double ms) {
  FrameRecord r;
  r.run = run;
  r.technique = "deferred";
  r.pipeline = "deferred";
  r.lights = "10#1x_1y_1z";
  r.light_count = 10;
  r.width = 32;
  r.height = 16;
  r.frame = frame;
  r.counted = true;
  r.light_evaluations = evals;
  r.lower_bound = evals / 4;
  r.covered_pixels = 512;
  r.timed = true;
  r.passes.add("gbuffer", ms);
  r.passes.add("deferred-shading", 2 * ms);
  r.passes_total_ms = 3 * ms;
  r.host_ms = 4 * ms;
  r.memory_bytes = 100;
  return r;
}

TEST(BenchTypes, JsonAndCsvSchema) {
  std::vector<FrameRecord> recs = {record("a", 0, 400, 1), record("a", 5, 800, 3), record("b,\"x\"", 0, 40, 1)};
  recs[2].timed = false;
  const auto sums = summarizeRuns(recs);
  ASSERT_EQ(sums.size(), 2u);
  EXPECT_EQ(sums[0].frames, 2u);
  EXPECT_DOUBLE_EQ(sums[0].light_evaluations.mean, 600);
  EXPECT_DOUBLE_EQ(sums[0].passes_total_ms.max, 9);
  EXPECT_FALSE(sums[1].timed);

  const auto j = benchJson({{"command", "test"}}, recs, sums);
  EXPECT_EQ(j["schema"], "manylights-bench/1");
  ASSERT_EQ(j["records"].size(), 3u);
  const auto& r0 = j["records"][0];
  for (const char* key : {"technique", "frame", "light_evaluations", "lower_bound", "passes", "memory_bytes", "params",
                          "lights", "light_count", "width", "height", "covered_pixels", "host_ms"})
    EXPECT_TRUE(r0.contains(key)) << key;
  EXPECT_EQ(r0["passes"]["deferred-shading"], 2.0);
  EXPECT_TRUE(j["records"][2]["passes_total_ms"].is_null());
  const auto& s0 = j["summaries"][0];
  for (const char* key : {"mean", "median", "p95", "max"}) EXPECT_TRUE(s0["light_evaluations"].contains(key)) << key;
  EXPECT_TRUE(s0["passes"].contains("gbuffer"));

  const std::string csv = benchCsv(recs);
  std::istringstream in(csv);
  std::string header, line;
  std::getline(in, header);
  EXPECT_EQ(header.rfind("run,technique,pipeline,params,lights,light_file,light_count,width,height,frame,"
                         "light_evaluations,lower_bound,",
                         0),
            0u);
  EXPECT_NE(header.find("pass:gbuffer_ms"), std::string::npos);
  EXPECT_NE(header.find("pass:deferred-shading_ms"), std::string::npos);
  int rows = 0;
  while (std::getline(in, line)) ++rows;
  EXPECT_EQ(rows, 3);
  EXPECT_NE(csv.find("\"b,\"\"x\"\"\""), std::string::npos);  // quoted field
}

// JSON and CSV come from one field table: every CSV column before the pass
// columns is a record key, in the JSON's key order, with the same value.
TEST(BenchTypes, CsvColumnsFollowTheJsonFields) {
  FrameRecord r = record("run,1", 2, 345, 7);
  r.params = {{"tile", "16"}, {"tile_depth", "none"}};
  r.light_file = "lights/a.json";
  const auto j = recordJson(r);
  std::istringstream in(benchCsv({r}));
  std::string header, row;
  std::getline(in, header);
  std::getline(in, row);
  auto cells = [](const std::string& line) {  // splits on commas outside quotes
    std::vector<std::string> out(1);
    bool quoted = false;
    for (char c : line) {
      if (c == '"') quoted = !quoted;
      if (c == ',' && !quoted) out.emplace_back();
      else out.back() += c;
    }
    return out;
  };
  const auto names = cells(header), values = cells(row);
  ASSERT_EQ(names.size(), values.size());
  std::vector<std::string> json_keys;
  for (const auto& [k, v] : j.items())
    if (!v.is_object() || k == "params" || k == "gi_settings") json_keys.push_back(k);
  json_keys.erase(std::remove(json_keys.begin(), json_keys.end(), "shaded"), json_keys.end());
  std::size_t i = 0;
  for (; i < names.size() && names[i].rfind("pass:", 0) != 0; ++i) {
    ASSERT_LT(i, json_keys.size());
    EXPECT_EQ(names[i], json_keys[i]) << "column " << i;
  }
  EXPECT_EQ(i, json_keys.size()) << "every scalar field has a column";
  EXPECT_EQ(values[0], "\"run,1\"");
  EXPECT_EQ(values[3], "tile=16;tile_depth=none");
  const auto col = [&](const std::string& name) {
    return values[std::find(names.begin(), names.end(), name) - names.begin()];
  };
  EXPECT_EQ(col("light_evaluations"), std::to_string(j["light_evaluations"].get<std::uint64_t>()));
  EXPECT_EQ(col("memory_bytes"), std::to_string(j["memory_bytes"].get<std::size_t>()));
  EXPECT_EQ(std::stod(col("host_ms")), j["host_ms"].get<double>());
}

}  // namespace
}  // namespace ml
