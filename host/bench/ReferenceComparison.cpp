#include "host/bench/ReferenceComparison.hpp"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "host/run/RunRecords.hpp"
#include "host/run/OutputFiles.hpp"

namespace ml {
namespace {

using FrameMap = std::map<std::size_t, double>;  // reference frame -> value
using Json = nlohmann::ordered_json;

Json distJson(const Summary& d) {
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

// In the values' order (summarize() sums them sorted), as the reports always had it.
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

// "mean (median; p5-p95)", or "-" without values.
std::string distText(const Summary& d) {
  return d.n ? fixed(d.mean) + " (" + fixed(d.median) + "; " + fixed(d.p5) + "-" + fixed(d.p95) + ")"
             : std::string("-");
}

// Every frame's values by series id, ours and the thesis's.
struct FrameJoin {
  const ReferenceSeries* ns_ref = nullptr;
  // Our naive count is exactly lights x covered pixels (every light for
  // every covered pixel), so it is known from any run of the same frame even
  // when our naive series did not run.
  FrameMap our_naive, our_cov, their_cov;
  std::map<std::string, FrameMap> ours_by, thesis_by;
  std::set<std::size_t> matched;  // covered pixels within the tolerance of the thesis's
};

FrameJoin joinFrames(const ThesisReference& ref, const std::vector<SeriesRun>& runs, const ComparisonSettings& s) {
  FrameJoin j;
  for (const auto& series : ref.series)
    if (series.kind == "ns") j.ns_ref = &series;
  for (const auto& r : runs)
    for (std::size_t i = 0; i < r.frames.size(); ++i) {
      const std::size_t f = r.frames[i];
      j.our_naive[f] = r.covered[i] * r.light_count;
      j.our_cov[f] = r.covered[i];
      j.ours_by[r.ref->id][f] = r.ours[i];
      if (j.ns_ref && j.ns_ref->counts.count(f) && r.light_count)
        j.their_cov[f] = j.ns_ref->counts.at(f) * s.naive_scale / r.light_count;
    }
  for (const auto& series : ref.series)
    for (const auto& [f, c] : series.counts) j.thesis_by[series.id][f] = series.kind == "ns" ? c * s.naive_scale : c;
  for (const auto& [f, c] : j.their_cov)
    if (c > 0 && std::abs(j.our_cov[f] / c - 1.0) <= s.coverage_tolerance) j.matched.insert(f);
  return j;
}

struct Stats {
  Summary all, match;
};

Stats ratioStats(const FrameMap& num, const FrameMap& den, const std::set<std::size_t>& matched) {
  std::vector<double> all, match;
  for (const auto& [f, v] : num) {
    auto d = den.find(f);
    if (d == den.end() || !(d->second > 0)) continue;
    all.push_back(v / d->second);
    if (matched.count(f)) match.push_back(v / d->second);
  }
  return Stats{summarize(all), summarize(match)};
}

// `m` on the frames of `keys`, so the thesis side of a ratio uses exactly the
// frames our side has.
FrameMap onFramesOf(const FrameMap& m, const FrameMap& keys) {
  FrameMap out;
  for (const auto& [f, v] : m)
    if (keys.count(f)) out[f] = v;
  return out;
}

struct RatioRow {
  std::string name;
  unsigned tile;
  Stats ours, thesis;
};

std::vector<RatioRow> techniqueRatios(const ThesisReference& ref, FrameJoin& j) {
  std::vector<RatioRow> rows;
  auto add = [&](const std::string& name, unsigned tile, const std::string& num, const std::string& den) {
    if (!j.ours_by.count(num) || j.ours_by[num].empty()) return;
    const FrameMap& den_ours = den == "ns" ? j.our_naive : j.ours_by[den];
    if (den != "ns" && den_ours.empty()) return;
    if (!j.thesis_by.count(num) || !j.thesis_by.count(den)) return;
    const FrameMap& ours_num = j.ours_by[num];
    RatioRow r{name, tile, ratioStats(ours_num, den_ours, j.matched),
               ratioStats(onFramesOf(j.thesis_by[num], ours_num), onFramesOf(j.thesis_by[den], ours_num), j.matched)};
    if (r.ours.all.n) rows.push_back(r);
  };
  std::set<unsigned> tiles;
  for (const auto& s : ref.series)
    if (s.tile) tiles.insert(s.tile);
  for (unsigned t : tiles) {
    const std::string ts = "ts/" + std::to_string(t), cs = "cs/" + std::to_string(t);
    if (j.ns_ref) add("tiled/naive", t, ts, "ns");
    add("clustered/tiled", t, cs, ts);
    if (j.ns_ref) add("clustered/naive", t, cs, "ns");
  }
  return rows;
}

// What the tables become besides stdout.
struct Report {
  std::string md_series =
      "| thesis series | our technique | frames | ours mean | thesis mean | exact lower bound mean | ours/thesis, all "
      "frames: mean (median; p5-p95) | corr | ours/thesis, matched frames |\n"
      "|---|---|---:|---:|---:|---:|---|---:|---|\n";
  std::string md_ratios =
      "| ratio | tile | ours, all frames | thesis, same frames | ours, matched frames | thesis, matched frames |\n"
      "|---|---:|---|---|---|---|\n";
  std::string csv = "series,technique,frame,ours,thesis,thesis_raw,ratio,lower_bound,covered_pixels,matched\n";
  Json series = Json::array(), ratios = Json::array();
};

Json seriesHead(const SeriesRun& r, const ComparisonSettings& s) {
  Json j;
  j["series"] = r.ref->id;
  j["technique"] = r.technique;
  j["label"] = r.label;
  j["width"] = r.ref->width;
  j["height"] = r.ref->height;
  j["light_file"] = r.ref->light_file;
  std::vector<double> every;
  for (const auto& [f, c] : r.ref->counts) every.push_back(r.ref->kind == "ns" ? c * s.naive_scale : c);
  j["thesis_mean_all_frames"] = mean(every);
  return j;
}

void skippedRow(const SeriesRun& r, Json j, Report& rep) {
  j["skipped"] = r.skipped;
  std::printf("%-6s %-38s skipped: %s\n", r.ref->id.c_str(), r.technique.c_str(), r.skipped.c_str());
  rep.md_series += "| " + r.ref->id + " | " + r.technique + " | - | - | " +
                   thousands(j["thesis_mean_all_frames"].get<double>()) + " (all frames) | - | skipped: " + r.skipped +
                   " | | |\n";
  rep.series.push_back(std::move(j));
}

void csvRows(const SeriesRun& r, const FrameJoin& join, Report& rep) {
  for (std::size_t i = 0; i < r.frames.size(); ++i)
    rep.csv += r.ref->id + "," + r.technique + "," + std::to_string(r.frames[i]) + "," + fixed(r.ours[i], 0) + "," +
               fixed(r.thesis[i], 0) + "," + fixed(r.thesis_raw[i], 0) + "," +
               (r.thesis[i] > 0 ? fixed(r.ours[i] / r.thesis[i], 6) : "") + "," + fixed(r.bound[i], 0) + "," +
               fixed(r.covered[i], 0) + "," + (join.matched.count(r.frames[i]) ? "1" : "0") + "\n";
}

void seriesRow(const SeriesRun& r, Json j, const FrameJoin& join, Report& rep) {
  FrameMap o, t;
  for (std::size_t i = 0; i < r.frames.size(); ++i) {
    o[r.frames[i]] = r.ours[i];
    t[r.frames[i]] = r.thesis[i];
  }
  csvRows(r, join, rep);
  const Stats st = ratioStats(o, t, join.matched);
  const double corr = pearson(r.ours, r.thesis);
  const double bound_mean = mean(r.bound);
  const std::string matched_text = st.match.n ? std::to_string(st.match.n) + ": " + distText(st.match) : "-";
  std::printf("%-6s %-38s %6zu %12s %12s %12s  %-28s %5s  %-28s\n", r.ref->id.c_str(), r.label.c_str(),
              r.frames.size(), thousands(mean(r.ours)).c_str(), thousands(mean(r.thesis)).c_str(),
              thousands(bound_mean).c_str(), distText(st.all).c_str(), fixed(corr, 2).c_str(), matched_text.c_str());
  rep.md_series += "| " + r.ref->id + " | `" + r.label + "` | " + std::to_string(r.frames.size()) + " | " +
                   thousands(mean(r.ours)) + " | " + thousands(mean(r.thesis)) + " | " + thousands(bound_mean) +
                   " | " + distText(st.all) + " | " + fixed(corr, 2) + " | " +
                   (st.match.n ? std::to_string(st.match.n) + " frames: " + distText(st.match) : std::string("-")) +
                   " |\n";
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
  j["correlation"] = std::isfinite(corr) ? Json(corr) : Json();
  rep.series.push_back(std::move(j));
}

void seriesTable(const ThesisReference& ref, const std::vector<SeriesRun>& runs, const FrameJoin& join,
                 const ComparisonSettings& s, Report& rep) {
  std::printf("\nlight evaluations per frame, ours vs thesis (%s); ratio = ours/thesis per frame, mean (median; "
              "p5-p95)\n",
              ref.scene.c_str());
  std::printf("%zu of the compared frames have the thesis's covered pixels within %.1f%% (\"matched\")\n",
              join.matched.size(), 100.0 * s.coverage_tolerance);
  std::printf("%-6s %-38s %6s %12s %12s %12s  %-28s %5s  %-28s\n", "series", "our technique", "frames", "ours mean",
              "thesis mean", "bound mean", "ratio, all frames", "corr", "ratio, matched frames");
  for (const auto& r : runs) {
    if (!r.skipped.empty() || r.frames.empty()) skippedRow(r, seriesHead(r, s), rep);
    else seriesRow(r, seriesHead(r, s), join, rep);
  }
}

void ratioTable(const std::vector<RatioRow>& ratios, Report& rep) {
  std::printf("\ntechnique ratios per frame, mean (median; p5-p95); all frames | matched frames\n");
  std::printf("%-16s %4s  %-28s %-28s | %-28s %-28s\n", "ratio", "tile", "ours", "thesis", "ours (matched)",
              "thesis (matched)");
  for (const auto& row : ratios) {
    std::printf("%-16s %4u  %-28s %-28s | %-28s %-28s\n", row.name.c_str(), row.tile, distText(row.ours.all).c_str(),
                distText(row.thesis.all).c_str(), distText(row.ours.match).c_str(),
                distText(row.thesis.match).c_str());
    rep.md_ratios += "| " + row.name + " | " + std::to_string(row.tile) + " | " + distText(row.ours.all) + " | " +
                     distText(row.thesis.all) + " | " + distText(row.ours.match) + " | " +
                     distText(row.thesis.match) + " |\n";
    rep.ratios.push_back({{"ratio", row.name},
                          {"tile", row.tile},
                          {"ours", distJson(row.ours.all)},
                          {"thesis", distJson(row.thesis.all)},
                          {"ours_matched", distJson(row.ours.match)},
                          {"thesis_matched", distJson(row.thesis.match)}});
  }
  if (ratios.empty()) std::printf("(none: needs our runs of two series with the same tile size, or of one and naive)\n");
}

// Mean covered pixels per frame over the frames the thesis implies them for.
struct Coverage {
  std::vector<double> ours, thesis;
};

Coverage coverage(const FrameJoin& join) {
  Coverage c;
  for (const auto& [f, v] : join.their_cov) {
    c.ours.push_back(join.our_cov.at(f));
    c.thesis.push_back(v);
  }
  return c;
}

void writeJson(const ThesisReference& ref, const ComparisonSettings& s, const FrameJoin& join, const Coverage& cov,
               Report& rep, const std::string& path) {
  Json j;
  j["schema"] = "manylights-compare-reference/1";
  j["reference"] = ref.frames_dir;
  j["scene"] = ref.scene;
  j["suite"] = s.suite;
  j["naive_scale"] = s.naive_scale;
  j["frame_offset"] = s.frame_offset;
  j["fovy"] = s.fovy > 0 ? s.fovy : (ref.series.empty() ? 45.0f : ref.series.front().fovy);
  j["coverage_tolerance"] = s.coverage_tolerance;
  j["matched_frames"] = std::vector<std::size_t>(join.matched.begin(), join.matched.end());
  j["missing_meshes"] = s.missing_meshes;
  j["notes"] = ref.notes;
  if (!cov.ours.empty()) j["covered_pixels"] = {{"ours", mean(cov.ours)}, {"thesis", mean(cov.thesis)}};
  j["series"] = std::move(rep.series);
  j["ratios"] = std::move(rep.ratios);
  writeFileAtomically("--json", path, j.dump(1) + "\n");
  std::printf("\nwrote %s\n", path.c_str());
}

void writeMarkdown(const ComparisonSettings& s, const FrameJoin& join, const Coverage& cov, const Report& rep,
                   const std::string& path) {
  std::string text = rep.md_series + "\n" + rep.md_ratios;
  if (!cov.ours.empty())
    text += "\nCovered pixels per frame: ours " + thousands(mean(cov.ours)) + ", thesis " + thousands(mean(cov.thesis)) +
            " (naive x " + fixed(s.naive_scale, 0) + " / lights); " + std::to_string(join.matched.size()) + " of " +
            std::to_string(cov.ours.size()) + " frames match within " + fixed(100.0 * s.coverage_tolerance, 1) +
            "%.\n";
  writeFileAtomically("--markdown", path, text);
  std::printf("wrote %s\n", path.c_str());
}

}  // namespace

void reportComparison(const ThesisReference& ref, const std::vector<SeriesRun>& runs, const ComparisonSettings& s,
                      const ComparisonOutputs& out) {
  FrameJoin join = joinFrames(ref, runs, s);
  const std::vector<RatioRow> ratios = techniqueRatios(ref, join);
  Report rep;
  seriesTable(ref, runs, join, s, rep);
  const Coverage cov = coverage(join);
  if (!cov.ours.empty())
    std::printf("\ncovered pixels per frame: ours %s, thesis %s (naive x %g / lights)\n",
                thousands(mean(cov.ours)).c_str(), thousands(mean(cov.thesis)).c_str(), s.naive_scale);
  ratioTable(ratios, rep);
  if (!out.json.empty()) writeJson(ref, s, join, cov, rep, out.json);
  if (!out.csv.empty()) {
    writeFileAtomically("--csv", out.csv, rep.csv);
    std::printf("wrote %s\n", out.csv.c_str());
  }
  if (!out.markdown.empty()) writeMarkdown(s, join, cov, rep, out.markdown);
}

}  // namespace ml
