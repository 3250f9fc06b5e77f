#include "host/run/RunRecords.hpp"

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

// Appends the pass names of `passes` not yet in `names`, in order.
void addPassNames(const PassTimings& passes, std::vector<std::string>& names) {
  for (const auto& [name, ms] : passes.entries()) {
    (void)ms;
    if (std::find(names.begin(), names.end(), name) == names.end()) names.push_back(name);
  }
}

void addHostClockNames(const PassTimings& passes, std::vector<std::string>& names) {
  for (std::size_t i = 0; i < passes.entries().size(); ++i) {
    const std::string& name = passes.entries()[i].first;
    if (passes.clockAt(i) == PassClock::Host && std::find(names.begin(), names.end(), name) == names.end())
      names.push_back(name);
  }
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
  // A missing time (NaN) is not a value: it neither counts nor sorts.
  values.erase(std::remove_if(values.begin(), values.end(), [](double v) { return std::isnan(v); }), values.end());
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

std::vector<std::vector<std::pair<std::string, std::string>>> sweepPoints(
    const std::vector<const ParamSweep::value_type*>& axes) {
  std::vector<std::vector<std::pair<std::string, std::string>>> out;
  std::vector<std::size_t> idx(axes.size(), 0);
  for (;;) {
    auto& point = out.emplace_back();
    for (std::size_t a = 0; a < axes.size(); ++a) point.emplace_back(axes[a]->first, axes[a]->second[idx[a]]);
    std::size_t a = 0;
    for (; a < axes.size(); ++a) {
      if (++idx[a] < axes[a]->second.size()) break;
      idx[a] = 0;
    }
    if (a == axes.size()) return out;
  }
}

namespace {

// Every sweep point of one technique: the product over the sweep's keys it reads.
void expandTechnique(const TechniqueInfo& info, const ParamSweep& sweep, const std::string& flag,
                     std::vector<TechniqueVariant>& out) {
  std::vector<const ParamSweep::value_type*> axes;
  for (const auto& s : sweep)
    if (info.descriptor->param(s.first) && !s.second.empty()) axes.push_back(&s);
  for (auto& labels : sweepPoints(axes)) {
    TechniqueVariant v;
    v.info = &info;
    v.technique = info.name;
    v.pipeline = info.pipeline;
    v.labels = std::move(labels);
    v.params = techniqueParams(info, v.labels, flag);
    v.label = variantLabel(info.name, v.labels);
    out.push_back(std::move(v));
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
      static_cast<RunIdentity&>(s) = r;
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
        addPassNames(r->passes, pass_names);
        addHostClockNames(r->passes, s.host_clock_passes);
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

namespace {

// The record's fields, listed once: JSON writes every field in this order,
// CSV the fields with a column, in the same order (a value's CSV text is
// derived from its JSON value), then one "pass:<name>_ms" column per pass.
template <class R>
struct Field {
  const char* name;
  bool csv;  // has a CSV column (objects other than params and gi_settings do not)
  nlohmann::ordered_json (*get)(const R&);
};
using Json = nlohmann::ordered_json;

// The RunIdentity fields, first in both a record and a summary.
template <class R>
std::vector<Field<R>> runFields() {
  return {
      {"run", true, [](const R& r) { return Json(r.run); }},
      {"technique", true, [](const R& r) { return Json(r.technique); }},
      {"pipeline", true, [](const R& r) { return Json(r.pipeline); }},
      {"params", true, [](const R& r) { return paramsJson(r.params); }},
      {"lights", true, [](const R& r) { return Json(r.lights); }},
      {"light_file", true, [](const R& r) { return Json(r.light_file); }},
      {"light_count", true, [](const R& r) { return Json(r.light_count); }},
      {"width", true, [](const R& r) { return Json(r.width); }},
      {"height", true, [](const R& r) { return Json(r.height); }},
  };
}

// Counts are null without counting, evaluations also without shading, times without timing.
Json counted(const FrameRecord& r, std::uint64_t v) { return r.counted ? Json(v) : Json(); }
Json evaluated(const FrameRecord& r, std::uint64_t v) { return r.shaded ? counted(r, v) : Json(); }
// A time the device could not measure is null, never 0.
Json msOrNull(double ms) { return PassTimings::isMissing(ms) ? Json() : Json(ms); }
Json timedMs(const FrameRecord& r, double v) { return r.timed ? msOrNull(v) : Json(); }
// Per pass, the clock that timed it: "device" (its profiling clock or GL
// timer queries), or "host" (bracketed by finish calls: the device's clock unusable).
Json passClocks(const PassTimings& passes) {
  Json clocks = Json::object();
  for (std::size_t i = 0; i < passes.entries().size(); ++i)
    clocks[passes.entries()[i].first] = passes.clockAt(i) == PassClock::Host ? "host" : "device";
  return clocks;
}

const std::vector<Field<FrameRecord>>& recordFields() {
  static const std::vector<Field<FrameRecord>> fields = [] {
    std::vector<Field<FrameRecord>> f = runFields<FrameRecord>();
    const std::vector<Field<FrameRecord>> rest = {
        {"frame", true, [](const FrameRecord& r) { return Json(r.frame); }},
        {"shaded", false, [](const FrameRecord& r) { return Json(r.shaded); }},
        {"light_evaluations", true, [](const FrameRecord& r) { return evaluated(r, r.light_evaluations); }},
        {"lower_bound", true, [](const FrameRecord& r) { return counted(r, r.lower_bound); }},
        {"covered_pixels", true, [](const FrameRecord& r) { return counted(r, r.covered_pixels); }},
        {"fragment_evaluations", true, [](const FrameRecord& r) { return evaluated(r, r.fragment_evaluations); }},
        {"passes", false,
         [](const FrameRecord& r) {
           Json passes = Json::object();
           if (r.timed)
             for (const auto& [name, ms] : r.passes.entries()) passes[name] = msOrNull(ms);
           return passes;
         }},
        {"pass_clocks", false, [](const FrameRecord& r) { return r.timed ? passClocks(r.passes) : Json::object(); }},
        {"passes_total_ms", true, [](const FrameRecord& r) { return timedMs(r, r.passes_total_ms); }},
        {"host_ms", true, [](const FrameRecord& r) { return timedMs(r, r.host_ms); }},
        {"memory_bytes", true, [](const FrameRecord& r) { return Json(r.memory_bytes); }},
        {"technique_stats", false,
         [](const FrameRecord& r) {
           Json st = Json::object();
           for (const auto& [k, v] : r.technique_stats) st[k] = v;
           return st;
         }},
        {"gi", true, [](const FrameRecord& r) { return Json(r.gi); }},
        {"gi_settings", true, [](const FrameRecord& r) { return paramsJson(r.gi_settings); }},
        {"voxel_bytes", true, [](const FrameRecord& r) { return Json(r.voxel_bytes); }},
        {"gi_rel_rmse", true, [](const FrameRecord& r) { return r.gi_rel_rmse >= 0 ? Json(r.gi_rel_rmse) : Json(); }},
        {"gi_ref_noise", true, [](const FrameRecord& r) { return r.gi_ref_noise >= 0 ? Json(r.gi_ref_noise) : Json(); }},
        {"gi_rel_rmse_corrected", true,
         [](const FrameRecord& r) { return r.gi_rel_rmse_corrected >= 0 ? Json(r.gi_rel_rmse_corrected) : Json(); }},
        {"gi_updates", true, [](const FrameRecord& r) { return r.gi_updates ? Json(r.gi_updates->ran) : Json(); }},
        {"gi_reused", true, [](const FrameRecord& r) { return r.gi_updates ? Json(r.gi_updates->reused) : Json(); }},
    };
    f.insert(f.end(), rest.begin(), rest.end());
    return f;
  }();
  return fields;
}

template <class R>
Json fieldsJson(const std::vector<Field<R>>& fields, const R& r) {
  Json j;
  for (const auto& f : fields) j[f.name] = f.get(r);
  return j;
}

// A CSV cell from a field's JSON value: null empty, params "k=v;k=v", numbers as written by num().
std::string csvCell(const Json& v) {
  if (v.is_null()) return "";
  if (v.is_string()) return csvField(v.get<std::string>());
  if (v.is_object()) {
    std::vector<std::pair<std::string, std::string>> params;
    for (const auto& [k, x] : v.items()) params.emplace_back(k, x.get<std::string>());
    return csvField(paramsText(params));
  }
  if (v.is_number_float()) return num(v.get<double>());
  return v.dump();
}

}  // namespace

nlohmann::ordered_json recordJson(const FrameRecord& r) { return fieldsJson(recordFields(), r); }

nlohmann::ordered_json summaryJson(const RunSummary& s) {
  nlohmann::ordered_json j = fieldsJson(runFields<RunSummary>(), s);
  j["frames"] = s.frames;
  auto opt = [](bool have, const Summary& v) { return have ? toJson(v) : nlohmann::ordered_json(); };
  j["shaded"] = s.shaded;
  j["light_evaluations"] = opt(s.counted && s.shaded, s.light_evaluations);
  j["lower_bound"] = opt(s.counted, s.lower_bound);
  j["covered_pixels"] = opt(s.counted, s.covered_pixels);
  j["passes_total_ms"] = opt(s.timed && s.passes_total_ms.n, s.passes_total_ms);
  j["host_ms"] = opt(s.timed, s.host_ms);
  j["memory_bytes"] = toJson(s.memory_bytes);
  nlohmann::ordered_json passes = nlohmann::ordered_json::object();
  for (const auto& [name, sum] : s.passes) passes[name] = sum.n ? toJson(sum) : nlohmann::ordered_json();
  j["passes"] = passes;
  nlohmann::ordered_json clocks = nlohmann::ordered_json::object();
  for (const auto& [name, sum] : s.passes) {
    const bool host = std::find(s.host_clock_passes.begin(), s.host_clock_passes.end(), name) !=
                      s.host_clock_passes.end();
    clocks[name] = host ? "host" : "device";
  }
  j["pass_clocks"] = clocks;
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
  for (const auto& r : records) addPassNames(r.passes, pass_names);
  // Appending field by field: `"," + std::string` chains trip GCC 12's
  // -Wrestrict false positive (GCC bug 105329) under -O3.
  std::string out;
  for (const auto& f : recordFields())
    if (f.csv) {
      if (!out.empty()) out += ',';
      out += f.name;
    }
  for (const auto& n : pass_names) {
    out += ',';
    out += csvField("pass:" + n + "_ms");
  }
  out += '\n';
  for (const auto& r : records) {
    bool first = true;
    for (const auto& f : recordFields())
      if (f.csv) {
        if (!first) out += ',';
        first = false;
        out += csvCell(f.get(r));
      }
    for (const auto& n : pass_names) {
      out += ',';
      if (r.timed && !PassTimings::isMissing(r.passes.get(n))) out += num(r.passes.get(n));
    }
    out += '\n';
  }
  return out;
}

}  // namespace ml
