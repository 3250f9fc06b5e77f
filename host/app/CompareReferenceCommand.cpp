#include "host/app/CompareReferenceCommand.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <set>

#include "gl/FrameRenderer.hpp"
#include "gl/GlContext.hpp"
#include "host/techniques/Registry.hpp"
#include "host/bench/BenchInputs.hpp"
#include "host/bench/BenchTypes.hpp"
#include "host/bench/Progress.hpp"
#include "host/cl/ClRuntime.hpp"
#include "host/scene/LightSet.hpp"
#include "host/suite/ThesisReference.hpp"
#include "host/util/Error.hpp"
#include "host/bench/OutputFiles.hpp"

namespace ml {
namespace fs = std::filesystem;
namespace {

struct Dist {
  std::size_t n = 0;
  double mean = 0, median = 0, p5 = 0, p95 = 0;
};

Dist distribution(std::vector<double> v) {
  Dist d;
  d.n = v.size();
  if (v.empty()) return d;
  std::sort(v.begin(), v.end());
  double s = 0;
  for (double x : v) s += x;
  d.mean = s / static_cast<double>(v.size());
  d.median = percentile(v, 0.5);
  d.p5 = percentile(v, 0.05);
  d.p95 = percentile(v, 0.95);
  return d;
}

nlohmann::ordered_json distJson(const Dist& d) {
  return {{"n", d.n}, {"mean", d.mean}, {"median", d.median}, {"p5", d.p5}, {"p95", d.p95}};
}

double pearson(const std::vector<double>& a, const std::vector<double>& b) {
  const std::size_t n = std::min(a.size(), b.size());
  if (n < 3) return std::nan("");
  double ma = 0, mb = 0;
  for (std::size_t i = 0; i < n; ++i) {
    ma += a[i];
    mb += b[i];
  }
  ma /= static_cast<double>(n);
  mb /= static_cast<double>(n);
  double sab = 0, saa = 0, sbb = 0;
  for (std::size_t i = 0; i < n; ++i) {
    sab += (a[i] - ma) * (b[i] - mb);
    saa += (a[i] - ma) * (a[i] - ma);
    sbb += (b[i] - mb) * (b[i] - mb);
  }
  return saa > 0 && sbb > 0 ? sab / std::sqrt(saa * sbb) : std::nan("");
}

double mean(const std::vector<double>& v) {
  double s = 0;
  for (double x : v) s += x;
  return v.empty() ? 0.0 : s / static_cast<double>(v.size());
}

std::string thousands(double v) {
  if (!std::isfinite(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.0f", v);
  std::string s = buf, out;
  const bool neg = !s.empty() && s[0] == '-';
  if (neg) s.erase(0, 1);
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (i && (s.size() - i) % 3 == 0) out += ',';
    out += s[i];
  }
  return (neg ? "-" : "") + out;
}

std::string fixed(double v, int digits = 3) {
  if (!std::isfinite(v)) return "-";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", digits, v);
  return buf;
}

struct SeriesRun {
  const ReferenceSeries* ref = nullptr;
  std::string technique;
  std::string label;  // "tiled-deferred[tile=8,tile_depth=none]"
  std::vector<std::pair<std::string, std::string>> param_labels;
  std::string skipped;  // why it did not run
  std::uint32_t light_count = 0;
  // Per compared frame (reference frame numbers):
  std::vector<std::size_t> frames;
  std::vector<double> ours, thesis, thesis_raw, bound, covered;
};



}  // namespace

CLI::App* addCompareReferenceCommand(CLI::App& app, CompareReferenceArgs& a) {
  auto* cmd = app.add_subcommand(
      "compare-reference",
      "Compare our per-frame light evaluations with the thesis's published counts (lc_data.json): per technique and "
      "tile size, ours vs theirs, and the technique ratios side by side");
  cmd->footer(
      "Example:\n"
      "  manylights compare-reference --reference ../shared/data/thesis-suite/reference \\\n"
      "      --suite ../shared/data/thesis-suite/scenes/spaceship-indoor --allow-missing-meshes --frames 3:518:8\n"
      "The thesis's naive (ns) counts are NUM_LIGHTS x covered pixels / 10 (its resolution/ns-old data is exactly\n"
      "10x ns); they are compared after multiplying by --naive-scale. Tiled/clustered counts are compared as published.");
  cmd->add_option("--reference", a.reference, "the thesis's reference data (thesis-suite root, reference/ or "
                                               "reference/light_calculations/)")
      ->required();
  cmd->add_option("--suite", a.suite, "the scene-suite folder the reference was measured on")->required();
  cmd->add_option("--scene-name", a.scene_name, "scene folder name in the reference (default: the suite folder's)");
  cmd->add_option("--techniques", a.techniques, "only these of our techniques (default: every mapped one)");
  cmd->add_option("--tiles", a.tiles, "only these tile sizes, comma list (default: all in the reference)");
  cmd->add_option("--frames", a.frames, "FIRST:LAST:STEP over the reference's frame numbers (default: all)");
  cmd->add_option("--technique-map", a.technique_map, "series -> our technique")->capture_default_str();
  cmd->add_option("--tile-depth", a.tile_depth, "depth culling of our tiled technique (thesis: none)")
      ->capture_default_str();
  cmd->add_option("--naive-scale", a.naive_scale, "multiply the thesis's naive counts by this")->capture_default_str();
  cmd->add_option("--frame-offset", a.frame_offset, "our camera frame = reference frame + offset")
      ->capture_default_str();
  cmd->add_option("--coverage-tolerance", a.coverage_tolerance,
                  "frames whose covered pixels are within this fraction of the thesis's are also reported apart")
      ->capture_default_str();
  cmd->add_option("--fovy", a.fovy, "vertical field of view in degrees (default: the reference config's)");
  cmd->add_option("--json", a.json, "write per-frame values and summaries as JSON");
  cmd->add_option("--csv", a.csv, "write per-frame values as CSV");
  cmd->add_option("--markdown", a.markdown, "write the two tables as Markdown");
  cmd->add_option("--geometry", a.geometry, "suite geometry file under geometry/");
  cmd->add_flag("--allow-missing-meshes", a.allow_missing_meshes, "skip objects whose OBJ mesh is missing");
  cmd->add_option("--device", a.device, "OpenCL device: gpu, cpu or an index from `manylights devices`");
  cmd->add_option("--progress", a.progress, "progress on stderr: auto|bar|lines|none")->capture_default_str();
  return cmd;
}

int runCompareReference(const CompareReferenceArgs& a) {
  // Validate the cheap things first.
  std::map<std::string, std::string> tmap;
  for (const auto& item : splitList(a.technique_map)) {
    const auto eq = item.find('=');
    const std::string kind = eq == std::string::npos ? "" : item.substr(0, eq);
    if (kind != "ns" && kind != "ts" && kind != "cs")
      throw UserError("--technique-map: expected ns=NAME,ts=NAME,cs=NAME, got '" + item + "'");
    tmap[kind] = item.substr(eq + 1);
  }
  std::set<std::string> only_tech;
  for (const auto& t : splitList(a.techniques)) only_tech.insert(t);
  std::set<unsigned> only_tiles;
  for (const auto& t : splitList(a.tiles)) {
    checkParam("tile", t, "--tiles");
    only_tiles.insert(static_cast<unsigned>(std::stoul(t)));
  }
  checkParam("tile_depth", a.tile_depth, "--tile-depth");
  if (!(a.naive_scale > 0)) throw UserError("--naive-scale: must be positive");
  if (a.fovy != 0 && !(a.fovy > 0 && a.fovy < 180)) throw UserError("--fovy: must be in (0, 180) degrees");
  const FrameRange range = a.frames.empty() ? FrameRange{} : parseFrameRange(a.frames, "--frames");
  const Progress::Mode progress_mode = Progress::parseMode(a.progress, "--progress");
  requireOutputFile("--json", a.json);
  requireOutputFile("--csv", a.csv);
  requireOutputFile("--markdown", a.markdown);
  const DeviceChoice device = DeviceChoice::resolve(a.device);

  BenchSceneArgs sa;
  sa.suite = a.suite;
  sa.geometry = a.geometry;
  sa.allow_missing_meshes = a.allow_missing_meshes;
  if (!fs::is_directory(a.suite)) throw UserError("--suite: '" + a.suite + "' is not a folder");
  const std::string scene_name =
      a.scene_name.empty() ? fs::path(a.suite).lexically_normal().filename().string() : a.scene_name;
  const ThesisReference ref = loadThesisReference(a.reference, scene_name);

  // Which series run with which technique.
  std::vector<SeriesRun> runs;
  for (const auto& s : ref.series) {
    SeriesRun r;
    r.ref = &s;
    r.technique = tmap.count(s.kind) ? tmap[s.kind] : "";
    if (s.tile && !only_tiles.empty() && !only_tiles.count(s.tile)) continue;
    if (!only_tech.empty() && !only_tech.count(r.technique)) continue;
    const bool registered = std::any_of(techniques().begin(), techniques().end(),
                                        [&](const TechniqueInfo& t) { return t.name == r.technique; });
    if (r.technique.empty()) r.skipped = "no technique mapped";
    else if (!registered) r.skipped = "technique '" + r.technique + "' is not registered in this build";
    if (s.kind == "ts") r.param_labels = {{"tile", std::to_string(s.tile)}, {"tile_depth", a.tile_depth}};
    else if (s.kind == "cs") r.param_labels = {{"cluster_tile", std::to_string(s.tile)}};
    // Labelled like bench's variants: "tiled-deferred[tile=8,tile_depth=none]".
    r.label = variantLabel(r.technique, r.param_labels);
    runs.push_back(std::move(r));
  }
  if (runs.empty()) throw UserError("--techniques/--tiles: nothing in the reference matches the selection");

  const BenchScene scene = loadBenchScene(sa);
  const std::size_t path_frames = scene.cameras.frames.size();
  // Frames per series: the reference's frames in --frames whose camera frame exists.
  std::size_t total_steps = 0;
  for (auto& r : runs) {
    if (!r.skipped.empty()) continue;
    for (const auto& [f, c] : r.ref->counts) {
      (void)c;
      if (f < range.first || (range.last && f > *range.last) || (f - range.first) % range.step != 0) continue;
      const long cam = static_cast<long>(f) + a.frame_offset;
      if (cam < 0 || static_cast<std::size_t>(cam) >= path_frames) continue;
      r.frames.push_back(f);
    }
    if (r.frames.empty()) r.skipped = "no reference frame in --frames within the camera path";
    total_steps += r.frames.size();
  }

  std::printf("thesis reference: %s (scene %s, %s)\n", ref.frames_dir.c_str(), ref.scene.c_str(), ref.pipeline.c_str());
  for (const auto& n : ref.notes) std::printf("note: %s\n", n.c_str());
  for (const auto& r : runs)
    if (!r.skipped.empty()) std::printf("note: skipped %s: %s\n", r.ref->id.c_str(), r.skipped.c_str());
  std::printf("scene: %s (%zu triangles, %zu camera frames)%s\n", scene.source.c_str(), scene.scene.triangleCount(),
              path_frames, scene.missing_meshes.empty() ? "" : ", with missing meshes skipped");
  std::printf("thesis naive counts x %g (NUM_LIGHTS x covered pixels / 10 as published); frame offset %d\n",
              a.naive_scale, a.frame_offset);
  std::fflush(stdout);

  std::unique_ptr<GlContext> gl;
  std::unique_ptr<ClRuntime> cl;
  if (total_steps > 0) {
    gl = createHeadlessContext();
    const GlShareHandles share = gl->shareHandles();
    cl = ClRuntime::create(device, &share);
    std::printf("%s\n%s\n", cl->describe().c_str(), gl->describe().c_str());
    std::fflush(stdout);
  }

  // Render: one renderer per viewport, lights per light file.
  Progress progress(total_steps, progress_mode);
  std::size_t done = 0;
  std::map<std::pair<unsigned, unsigned>, std::unique_ptr<FrameRenderer>> renderers;
  std::map<std::string, std::vector<gpu::PointLight>> light_cache;
  for (auto& r : runs) {
    if (!r.skipped.empty()) continue;
    const ReferenceSeries& s = *r.ref;
    std::string light_path = s.light_file.empty() ? scene.default_lights : (fs::path(a.suite) / "lights" / s.light_file).string();
    if (!fs::is_regular_file(light_path)) {
      r.skipped = "its light set '" + s.light_file + "' is not in " + a.suite + "/lights";
      r.frames.clear();
      std::printf("note: skipped %s: %s\n", s.id.c_str(), r.skipped.c_str());
      continue;
    }
    if (!light_cache.count(light_path)) light_cache[light_path] = loadLightsJson(light_path);
    const auto& lights = light_cache[light_path];
    r.light_count = static_cast<std::uint32_t>(lights.size());
    auto& renderer = renderers[{s.width, s.height}];
    if (!renderer) renderer = std::make_unique<FrameRenderer>(*cl, scene.scene, s.width, s.height);
    renderer->setLights(lights);
    const TechniqueInfo& tech = findTechnique(r.technique, "--technique-map");
    auto assigner = makeAssigner(tech, *cl, techniqueParams(tech, r.param_labels, "--technique-map"), &scene.scene);
    FrameOptions opts;
    opts.pipeline = tech.pipeline;
    opts.count_lights = true;
    for (std::size_t f : r.frames) {
      progress.update(done, s.id + " " + r.label + " frame " + std::to_string(f));
      Camera cam = scene.cameras.frames[static_cast<std::size_t>(static_cast<long>(f) + a.frame_offset)];
      cam.fovy_degrees = a.fovy > 0 ? a.fovy : s.fovy;
      cam.near_plane = s.near_plane;
      cam.far_plane = s.far_plane;
      const FrameResult res = renderer->render(cam, *assigner, opts);
      const double raw = s.counts.at(f);
      r.ours.push_back(static_cast<double>(res.light_evaluations));
      r.thesis_raw.push_back(raw);
      r.thesis.push_back(s.kind == "ns" ? raw * a.naive_scale : raw);
      r.bound.push_back(static_cast<double>(res.lower_bound));
      r.covered.push_back(static_cast<double>(res.covered_pixels));
      ++done;
    }
  }
  if (total_steps > 0) progress.finish();

  // Per-frame lookups. Our naive count is exactly lights x covered pixels
  // (every light for every covered pixel), so it is known from any run of the
  // same frame even when our naive series did not run.
  const ReferenceSeries* ns_ref = nullptr;
  for (const auto& s : ref.series)
    if (s.kind == "ns") ns_ref = &s;
  std::map<std::size_t, double> our_naive, our_cov, their_cov;
  std::map<std::string, std::map<std::size_t, double>> ours_by, thesis_by;  // id -> frame -> value
  for (const auto& r : runs)
    for (std::size_t i = 0; i < r.frames.size(); ++i) {
      const std::size_t f = r.frames[i];
      our_naive[f] = r.covered[i] * r.light_count;
      our_cov[f] = r.covered[i];
      ours_by[r.ref->id][f] = r.ours[i];
      if (ns_ref && ns_ref->counts.count(f) && r.light_count)
        their_cov[f] = ns_ref->counts.at(f) * a.naive_scale / r.light_count;
    }
  for (const auto& s : ref.series)
    for (const auto& [f, c] : s.counts) thesis_by[s.id][f] = s.kind == "ns" ? c * a.naive_scale : c;
  // Frames whose covered pixels match the thesis's (within the tolerance): the
  // ones a missing mesh or a different lens does not distort.
  std::set<std::size_t> matched;
  for (const auto& [f, c] : their_cov)
    if (c > 0 && std::abs(our_cov[f] / c - 1.0) <= a.coverage_tolerance) matched.insert(f);

  struct Stats {
    Dist all, match;
  };
  auto ratioStats = [&](const std::map<std::size_t, double>& num, const std::map<std::size_t, double>& den) {
    std::vector<double> all, match;
    for (const auto& [f, v] : num) {
      auto d = den.find(f);
      if (d == den.end() || !(d->second > 0)) continue;
      all.push_back(v / d->second);
      if (matched.count(f)) match.push_back(v / d->second);
    }
    return Stats{distribution(all), distribution(match)};
  };
  // Restricts `m` to the frames of `keys`, so the thesis side of a ratio uses
  // exactly the frames our side has.
  auto onFramesOf = [](const std::map<std::size_t, double>& m, const std::map<std::size_t, double>& keys) {
    std::map<std::size_t, double> out;
    for (const auto& [f, v] : m)
      if (keys.count(f)) out[f] = v;
    return out;
  };

  struct RatioOut {
    std::string name;
    unsigned tile;
    Stats ours, thesis;
  };
  std::vector<RatioOut> ratios;
  std::set<unsigned> tiles;
  for (const auto& s : ref.series)
    if (s.tile) tiles.insert(s.tile);
  auto addRatio = [&](const std::string& name, unsigned tile, const std::string& num, const std::string& den) {
    if (!ours_by.count(num) || ours_by[num].empty()) return;
    const auto& den_ours = den == "ns" ? our_naive : ours_by[den];
    if (den != "ns" && den_ours.empty()) return;
    if (!thesis_by.count(num) || !thesis_by.count(den)) return;
    RatioOut r{name, tile, ratioStats(ours_by[num], den_ours),
               ratioStats(onFramesOf(thesis_by[num], ours_by[num]), onFramesOf(thesis_by[den], ours_by[num]))};
    if (r.ours.all.n) ratios.push_back(r);
  };
  for (unsigned t : tiles) {
    const std::string ts = "ts/" + std::to_string(t), cs = "cs/" + std::to_string(t);
    if (ns_ref) addRatio("tiled/naive", t, ts, "ns");
    addRatio("clustered/tiled", t, cs, ts);
    if (ns_ref) addRatio("clustered/naive", t, cs, "ns");
  }

  auto dtxt = [](const Dist& d) {
    return d.n ? fixed(d.mean) + " (" + fixed(d.median) + "; " + fixed(d.p5) + "-" + fixed(d.p95) + ")"
               : std::string("-");
  };

  // Table 1: per series.
  std::printf("\nlight evaluations per frame, ours vs thesis (%s); ratio = ours/thesis per frame, mean (median; "
              "p5-p95)\n",
              ref.scene.c_str());
  std::printf("%zu of the compared frames have the thesis's covered pixels within %.1f%% (\"matched\")\n",
              matched.size(), 100.0 * a.coverage_tolerance);
  std::printf("%-6s %-38s %6s %12s %12s %12s  %-28s %5s  %-28s\n", "series", "our technique", "frames", "ours mean",
              "thesis mean", "bound mean", "ratio, all frames", "corr", "ratio, matched frames");
  std::string md =
      "| thesis series | our technique | frames | ours mean | thesis mean | exact lower bound mean | ours/thesis, all "
      "frames: mean (median; p5-p95) | corr | ours/thesis, matched frames |\n"
      "|---|---|---:|---:|---:|---:|---|---:|---|\n";
  nlohmann::ordered_json jseries = nlohmann::ordered_json::array();
  std::string csv = "series,technique,frame,ours,thesis,thesis_raw,ratio,lower_bound,covered_pixels,matched\n";
  for (const auto& r : runs) {
    nlohmann::ordered_json j;
    j["series"] = r.ref->id;
    j["technique"] = r.technique;
    j["label"] = r.label;
    j["width"] = r.ref->width;
    j["height"] = r.ref->height;
    j["light_file"] = r.ref->light_file;
    std::vector<double> every;
    for (const auto& [f, c] : r.ref->counts) every.push_back(r.ref->kind == "ns" ? c * a.naive_scale : c);
    j["thesis_mean_all_frames"] = mean(every);
    if (!r.skipped.empty() || r.frames.empty()) {
      j["skipped"] = r.skipped;
      jseries.push_back(j);
      std::printf("%-6s %-38s skipped: %s\n", r.ref->id.c_str(), r.technique.c_str(), r.skipped.c_str());
      md += "| " + r.ref->id + " | " + r.technique + " | - | - | " + thousands(mean(every)) +
            " (all frames) | - | skipped: " + r.skipped + " | | |\n";
      continue;
    }
    std::map<std::size_t, double> o, t;
    for (std::size_t i = 0; i < r.frames.size(); ++i) {
      o[r.frames[i]] = r.ours[i];
      t[r.frames[i]] = r.thesis[i];
      csv += r.ref->id + "," + r.technique + "," + std::to_string(r.frames[i]) + "," + fixed(r.ours[i], 0) + "," +
             fixed(r.thesis[i], 0) + "," + fixed(r.thesis_raw[i], 0) + "," +
             (r.thesis[i] > 0 ? fixed(r.ours[i] / r.thesis[i], 6) : "") + "," + fixed(r.bound[i], 0) + "," +
             fixed(r.covered[i], 0) + "," + (matched.count(r.frames[i]) ? "1" : "0") + "\n";
    }
    const Stats st = ratioStats(o, t);
    const double corr = pearson(r.ours, r.thesis);
    const double bound_mean = mean(r.bound);
    std::printf("%-6s %-38s %6zu %12s %12s %12s  %-28s %5s  %-28s\n", r.ref->id.c_str(), r.label.c_str(),
                r.frames.size(), thousands(mean(r.ours)).c_str(), thousands(mean(r.thesis)).c_str(),
                thousands(bound_mean).c_str(), dtxt(st.all).c_str(), fixed(corr, 2).c_str(),
                (st.match.n ? std::to_string(st.match.n) + ": " + dtxt(st.match) : std::string("-")).c_str());
    md += "| " + r.ref->id + " | `" + r.label + "` | " + std::to_string(r.frames.size()) + " | " +
          thousands(mean(r.ours)) + " | " + thousands(mean(r.thesis)) + " | " + thousands(bound_mean) + " | " +
          dtxt(st.all) + " | " + fixed(corr, 2) + " | " +
          (st.match.n ? std::to_string(st.match.n) + " frames: " + dtxt(st.match) : std::string("-")) + " |\n";
    j["frames"] = r.frames;
    j["ours"] = r.ours;
    j["thesis"] = r.thesis;
    j["thesis_raw"] = r.thesis_raw;
    j["lower_bound"] = r.bound;
    j["covered_pixels"] = r.covered;
    j["light_count"] = r.light_count;
    j["ours_mean"] = mean(r.ours);
    j["thesis_mean"] = mean(r.thesis);
    j["lower_bound_mean"] = bound_mean;
    j["ratio"] = distJson(st.all);
    j["ratio_matched"] = distJson(st.match);
    j["correlation"] = std::isfinite(corr) ? nlohmann::ordered_json(corr) : nlohmann::ordered_json();
    jseries.push_back(j);
  }

  std::vector<double> oc, tc;
  for (const auto& [f, c] : their_cov) {
    oc.push_back(our_cov[f]);
    tc.push_back(c);
  }
  if (!oc.empty())
    std::printf("\ncovered pixels per frame: ours %s, thesis %s (naive x %g / lights)\n", thousands(mean(oc)).c_str(),
                thousands(mean(tc)).c_str(), a.naive_scale);

  // Table 2: technique ratios.
  std::printf("\ntechnique ratios per frame, mean (median; p5-p95); all frames | matched frames\n");
  std::printf("%-16s %4s  %-28s %-28s | %-28s %-28s\n", "ratio", "tile", "ours", "thesis", "ours (matched)",
              "thesis (matched)");
  std::string md2 =
      "| ratio | tile | ours, all frames | thesis, same frames | ours, matched frames | thesis, matched frames |\n"
      "|---|---:|---|---|---|---|\n";
  nlohmann::ordered_json jratios = nlohmann::ordered_json::array();
  for (const auto& row : ratios) {
    std::printf("%-16s %4u  %-28s %-28s | %-28s %-28s\n", row.name.c_str(), row.tile, dtxt(row.ours.all).c_str(),
                dtxt(row.thesis.all).c_str(), dtxt(row.ours.match).c_str(), dtxt(row.thesis.match).c_str());
    md2 += "| " + row.name + " | " + std::to_string(row.tile) + " | " + dtxt(row.ours.all) + " | " +
           dtxt(row.thesis.all) + " | " + dtxt(row.ours.match) + " | " + dtxt(row.thesis.match) + " |\n";
    jratios.push_back({{"ratio", row.name},
                       {"tile", row.tile},
                       {"ours", distJson(row.ours.all)},
                       {"thesis", distJson(row.thesis.all)},
                       {"ours_matched", distJson(row.ours.match)},
                       {"thesis_matched", distJson(row.thesis.match)}});
  }
  if (ratios.empty()) std::printf("(none: needs our runs of two series with the same tile size, or of one and naive)\n");

  if (!a.json.empty()) {
    nlohmann::ordered_json j;
    j["schema"] = "manylights-compare-reference/1";
    j["reference"] = ref.frames_dir;
    j["scene"] = ref.scene;
    j["suite"] = a.suite;
    j["naive_scale"] = a.naive_scale;
    j["frame_offset"] = a.frame_offset;
    j["fovy"] = a.fovy > 0 ? a.fovy : (ref.series.empty() ? 45.0f : ref.series.front().fovy);
    j["coverage_tolerance"] = a.coverage_tolerance;
    j["matched_frames"] = std::vector<std::size_t>(matched.begin(), matched.end());
    j["missing_meshes"] = scene.missing_meshes;
    j["notes"] = ref.notes;
    if (!oc.empty()) j["covered_pixels"] = {{"ours", mean(oc)}, {"thesis", mean(tc)}};
    j["series"] = jseries;
    j["ratios"] = jratios;
    writeFileAtomically("--json", a.json, j.dump(1) + "\n");
    std::printf("\nwrote %s\n", a.json.c_str());
  }
  if (!a.csv.empty()) {
    writeFileAtomically("--csv", a.csv, csv);
    std::printf("wrote %s\n", a.csv.c_str());
  }
  if (!a.markdown.empty()) {
    std::string text = md + "\n" + md2;
    if (!oc.empty())
      text += "\nCovered pixels per frame: ours " + thousands(mean(oc)) + ", thesis " + thousands(mean(tc)) +
              " (naive x " + fixed(a.naive_scale, 0) + " / lights); " + std::to_string(matched.size()) + " of " +
              std::to_string(oc.size()) + " frames match within " + fixed(100.0 * a.coverage_tolerance, 1) + "%.\n";
    writeFileAtomically("--markdown", a.markdown, text);
    std::printf("wrote %s\n", a.markdown.c_str());
  }
  return 0;
}

}  // namespace ml
