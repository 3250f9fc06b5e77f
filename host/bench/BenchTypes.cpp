#include "host/bench/BenchTypes.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>

#include "host/util/Error.hpp"

namespace ml {
namespace {

bool parseIndex(std::string_view s, std::size_t& out) {
  if (s.empty()) return false;
  auto [p, ec] = std::from_chars(s.data(), s.data() + s.size(), out);
  return ec == std::errc() && p == s.data() + s.size();
}

nlohmann::ordered_json paramsJson(const std::vector<std::pair<std::string, std::string>>& params) {
  nlohmann::ordered_json j = nlohmann::ordered_json::object();
  for (const auto& [k, v] : params) j[k] = v;
  return j;
}

std::string csvField(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string q = "\"";
  for (char c : s) q += c == '"' ? std::string("\"\"") : std::string(1, c);
  return q + "\"";
}

std::string num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.6g", v);
  return buf;
}

}  // namespace

double percentile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return 0.0;
  const double pos = q * static_cast<double>(sorted.size() - 1);
  const auto lo = static_cast<std::size_t>(std::floor(pos));
  const std::size_t hi = std::min(lo + 1, sorted.size() - 1);
  return sorted[lo] + (sorted[hi] - sorted[lo]) * (pos - static_cast<double>(lo));
}

FrameRange parseFrameRange(const std::string& text, const std::string& flag) {
  FrameRange r;
  std::vector<std::string> parts;
  std::size_t start = 0;
  for (;;) {
    const auto colon = text.find(':', start);
    parts.push_back(text.substr(start, colon == std::string::npos ? std::string::npos : colon - start));
    if (colon == std::string::npos) break;
    start = colon + 1;
  }
  auto bad = [&] {
    return UserError(flag + ": expected FIRST:LAST:STEP (frame indices, LAST inclusive, parts optional), got '" +
                     text + "'");
  };
  if (text.empty() || parts.size() > 3) throw bad();
  if (!parts[0].empty() && !parseIndex(parts[0], r.first)) throw bad();
  if (parts.size() == 1) {
    if (parts[0].empty()) throw bad();
    r.last = r.first;
    return r;
  }
  if (!parts[1].empty()) {
    std::size_t last = 0;
    if (!parseIndex(parts[1], last)) throw bad();
    if (last < r.first) throw UserError(flag + ": LAST is before FIRST in '" + text + "'");
    r.last = last;
  }
  if (parts.size() == 3 && !parts[2].empty()) {
    if (!parseIndex(parts[2], r.step) || r.step == 0) throw bad();
  }
  return r;
}

std::vector<std::size_t> selectFrames(const FrameRange& range, std::size_t path_frames, const std::string& flag) {
  if (range.first >= path_frames)
    throw UserError(flag + ": first frame " + std::to_string(range.first) + " is past the camera path's " +
                    std::to_string(path_frames) + " frames");
  const std::size_t last = std::min(range.last.value_or(path_frames - 1), path_frames - 1);
  std::vector<std::size_t> out;
  for (std::size_t f = range.first; f <= last; f += range.step) out.push_back(f);
  return out;
}

Summary summarize(std::vector<double> values) {
  Summary s;
  s.n = values.size();
  if (values.empty()) return s;
  std::sort(values.begin(), values.end());
  double sum = 0;
  for (double v : values) sum += v;
  s.mean = sum / static_cast<double>(values.size());
  s.median = percentile(values, 0.5);
  s.p5 = percentile(values, 0.05);
  s.p95 = percentile(values, 0.95);
  s.max = values.back();
  s.min = values.front();
  return s;
}

nlohmann::ordered_json toJson(const Summary& s) {
  nlohmann::ordered_json j;
  j["mean"] = s.mean;
  j["median"] = s.median;
  j["p95"] = s.p95;
  j["max"] = s.max;
  j["min"] = s.min;
  return j;
}

std::string variantLabel(const std::string& technique, const std::vector<std::pair<std::string, std::string>>& labels) {
  std::string label = technique;
  for (std::size_t i = 0; i < labels.size(); ++i) {
    label += i ? ',' : '[';
    label += labels[i].first;
    label += '=';
    label += labels[i].second;
  }
  return labels.empty() ? label : label + "]";
}

namespace {

// Every sweep point of one technique: the product over the sweep's keys it reads.
void expandTechnique(const TechniqueInfo& info, const ParamSweep& sweep, const std::string& flag,
                     std::vector<TechniqueVariant>& out) {
  std::vector<const ParamSweep::value_type*> axes;
  for (const auto& s : sweep)
    if (info.descriptor->param(s.first) && !s.second.empty()) axes.push_back(&s);
  std::vector<std::size_t> idx(axes.size(), 0);
  for (;;) {
    TechniqueVariant v;
    v.info = &info;
    v.technique = info.name;
    v.pipeline = info.pipeline;
    for (std::size_t a = 0; a < axes.size(); ++a) v.labels.emplace_back(axes[a]->first, axes[a]->second[idx[a]]);
    v.params = techniqueParams(info, v.labels, flag);
    v.label = variantLabel(info.name, v.labels);
    out.push_back(std::move(v));
    std::size_t a = 0;
    for (; a < axes.size(); ++a) {
      if (++idx[a] < axes[a]->second.size()) break;
      idx[a] = 0;
    }
    if (a == axes.size()) break;
  }
}

}  // namespace

std::vector<TechniqueVariant> expandVariants(const std::vector<std::string>& names, const ParamSweep& sweep,
                                             const std::string& flag) {
  // Validate every value once up front, so a typo or an out-of-range value
  // fails before any rendering (even for keys no chosen technique reads).
  for (const auto& [key, values] : sweep)
    for (const auto& v : values) checkParam(key, v, flag);
  std::vector<TechniqueVariant> out;
  for (const auto& name : names) expandTechnique(findTechnique(name, "--techniques"), sweep, flag, out);
  return out;
}

std::vector<RunSummary> summarizeRuns(const std::vector<FrameRecord>& records) {
  std::vector<RunSummary> out;
  std::map<std::string, std::vector<const FrameRecord*>> by_run;
  for (const auto& r : records) {
    auto& list = by_run[r.run];
    if (list.empty()) {
      RunSummary s;
      s.run = r.run;
      s.technique = r.technique;
      s.pipeline = r.pipeline;
      s.lights = r.lights;
      s.light_file = r.light_file;
      s.params = r.params;
      s.light_count = r.light_count;
      s.width = r.width;
      s.height = r.height;
      out.push_back(std::move(s));
    }
    list.push_back(&r);
  }
  for (auto& s : out) {
    const auto& list = by_run[s.run];
    s.frames = list.size();
    std::vector<double> le, lb, cov, total, host, mem;
    std::vector<std::string> pass_names;
    for (const FrameRecord* r : list) {
      s.shaded = s.shaded && r->shaded;
      if (r->counted) {
        s.counted = true;
        le.push_back(static_cast<double>(r->light_evaluations));
        lb.push_back(static_cast<double>(r->lower_bound));
        cov.push_back(static_cast<double>(r->covered_pixels));
      }
      if (r->timed) {
        s.timed = true;
        total.push_back(r->passes_total_ms);
        host.push_back(r->host_ms);
        for (const auto& [name, ms] : r->passes.entries()) {
          (void)ms;
          if (std::find(pass_names.begin(), pass_names.end(), name) == pass_names.end()) pass_names.push_back(name);
        }
      }
      mem.push_back(static_cast<double>(r->memory_bytes));
    }
    s.light_evaluations = summarize(le);
    s.lower_bound = summarize(lb);
    s.covered_pixels = summarize(cov);
    s.passes_total_ms = summarize(total);
    s.host_ms = summarize(host);
    s.memory_bytes = summarize(mem);
    for (const auto& name : pass_names) {
      std::vector<double> v;
      for (const FrameRecord* r : list)
        if (r->timed) v.push_back(r->passes.get(name));
      s.passes.emplace_back(name, summarize(v));
    }
  }
  return out;
}

// What identifies a run, shared by its frame records and its summary.
template <class RunFields>
nlohmann::ordered_json runJson(const RunFields& r) {
  nlohmann::ordered_json j;
  j["run"] = r.run;
  j["technique"] = r.technique;
  j["pipeline"] = r.pipeline;
  j["params"] = paramsJson(r.params);
  j["lights"] = r.lights;
  j["light_file"] = r.light_file;
  j["light_count"] = r.light_count;
  j["width"] = r.width;
  j["height"] = r.height;
  return j;
}

nlohmann::ordered_json recordJson(const FrameRecord& r) {
  nlohmann::ordered_json j = runJson(r);
  j["frame"] = r.frame;
  auto count = [&](std::uint64_t v) { return r.counted ? nlohmann::ordered_json(v) : nlohmann::ordered_json(); };
  auto evals = [&](std::uint64_t v) { return r.shaded ? count(v) : nlohmann::ordered_json(); };
  j["shaded"] = r.shaded;
  j["light_evaluations"] = evals(r.light_evaluations);
  j["lower_bound"] = count(r.lower_bound);
  j["covered_pixels"] = count(r.covered_pixels);
  j["fragment_evaluations"] = evals(r.fragment_evaluations);
  nlohmann::ordered_json passes = nlohmann::ordered_json::object();
  if (r.timed)
    for (const auto& [name, ms] : r.passes.entries()) passes[name] = ms;
  j["passes"] = passes;
  j["passes_total_ms"] = r.timed ? nlohmann::ordered_json(r.passes_total_ms) : nlohmann::ordered_json();
  j["host_ms"] = r.timed ? nlohmann::ordered_json(r.host_ms) : nlohmann::ordered_json();
  j["memory_bytes"] = r.memory_bytes;
  nlohmann::ordered_json st = nlohmann::ordered_json::object();
  for (const auto& [k, v] : r.technique_stats) st[k] = v;
  j["technique_stats"] = st;
  return j;
}

nlohmann::ordered_json summaryJson(const RunSummary& s) {
  nlohmann::ordered_json j = runJson(s);
  j["frames"] = s.frames;
  auto opt = [](bool have, const Summary& v) { return have ? toJson(v) : nlohmann::ordered_json(); };
  j["shaded"] = s.shaded;
  j["light_evaluations"] = opt(s.counted && s.shaded, s.light_evaluations);
  j["lower_bound"] = opt(s.counted, s.lower_bound);
  j["covered_pixels"] = opt(s.counted, s.covered_pixels);
  j["passes_total_ms"] = opt(s.timed, s.passes_total_ms);
  j["host_ms"] = opt(s.timed, s.host_ms);
  j["memory_bytes"] = toJson(s.memory_bytes);
  nlohmann::ordered_json passes = nlohmann::ordered_json::object();
  for (const auto& [name, sum] : s.passes) passes[name] = toJson(sum);
  j["passes"] = passes;
  return j;
}

nlohmann::ordered_json benchJson(const nlohmann::ordered_json& meta, const std::vector<FrameRecord>& records,
                                 const std::vector<RunSummary>& summaries) {
  nlohmann::ordered_json j;
  j["schema"] = "manylights-bench/1";
  j["meta"] = meta;
  nlohmann::ordered_json recs = nlohmann::ordered_json::array();
  for (const auto& r : records) recs.push_back(recordJson(r));
  j["records"] = recs;
  nlohmann::ordered_json sums = nlohmann::ordered_json::array();
  for (const auto& s : summaries) sums.push_back(summaryJson(s));
  j["summaries"] = sums;
  return j;
}

std::string paramsText(const std::vector<std::pair<std::string, std::string>>& params) {
  std::string s;
  for (const auto& [k, v] : params) s += (s.empty() ? "" : ";") + k + "=" + v;
  return s;
}

std::string benchCsv(const std::vector<FrameRecord>& records) {
  std::vector<std::string> pass_names;
  for (const auto& r : records)
    for (const auto& [name, ms] : r.passes.entries()) {
      (void)ms;
      if (std::find(pass_names.begin(), pass_names.end(), name) == pass_names.end()) pass_names.push_back(name);
    }
  std::string out =
      "run,technique,pipeline,params,lights,light_file,light_count,width,height,frame,light_evaluations,lower_bound,"
      "covered_pixels,fragment_evaluations,memory_bytes,passes_total_ms,host_ms";
  // Appending field by field: `"," + std::string` chains trip GCC 12's
  // -Wrestrict false positive (GCC bug 105329) under -O3.
  for (const auto& n : pass_names) {
    out += ',';
    out += csvField("pass:" + n + "_ms");
  }
  out += '\n';
  for (const auto& r : records) {
    auto count = [&](std::uint64_t v) { return r.counted ? std::to_string(v) : std::string(); };
    auto evals = [&](std::uint64_t v) { return r.shaded ? count(v) : std::string(); };
    const std::vector<std::string> fields = {
        csvField(r.run), csvField(r.technique), r.pipeline, csvField(paramsText(r.params)), csvField(r.lights),
        csvField(r.light_file), std::to_string(r.light_count), std::to_string(r.width), std::to_string(r.height),
        std::to_string(r.frame), evals(r.light_evaluations), count(r.lower_bound), count(r.covered_pixels),
        evals(r.fragment_evaluations), std::to_string(r.memory_bytes), r.timed ? num(r.passes_total_ms) : std::string(),
        r.timed ? num(r.host_ms) : std::string()};
    for (std::size_t i = 0; i < fields.size(); ++i) {
      if (i) out += ',';
      out += fields[i];
    }
    for (const auto& n : pass_names) {
      out += ',';
      if (r.timed) out += num(r.passes.get(n));
    }
    out += '\n';
  }
  return out;
}

}  // namespace ml
