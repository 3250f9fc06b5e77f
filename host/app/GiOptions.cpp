#include "host/app/GiOptions.hpp"

#include <cstdio>
#include <filesystem>
#include <set>

#include "host/run/OutputFiles.hpp"
#include "host/gi/Registry.hpp"
#include "host/util/Error.hpp"
#include "host/util/GiToneMap.hpp"

namespace ml {

namespace {

// A switch given a value (--KEY=off): the spec's words only. CLI11 turns the
// value into a count before the flag's function sees it and aborts on words
// it does not know, so they are refused here first (CLI11 names the flag).
CLI::Validator switchValue(const ParamSpec& spec) {
  return CLI::Validator(
      [spec](std::string& text) -> std::string {
        if (text == "true") return "";  // CLI11's value for the bare flag
        const std::string why = spec.problem(text);
        return why.empty() ? why : why + ", got '" + text + "'";
      },
      "");
}

std::string specHelp(const GiDescriptor& d, const ParamSpec& p) {
  return "--gi " + d.name + ": " + p.help + " (" + p.allowed() + "; default " + p.default_value + ")";
}

// One flag per key (passes sharing a key describe it alike: host/gi/Registry),
// recorded in `into` in the order given; checked by checkGiFlags.
void addSpecFlag(CLI::App& cmd, const GiDescriptor& d, const ParamSpec& p, SettingList& into) {
  const std::string key = p.key, flag = p.renderFlag();
  if (p.type == ParamType::Switch)
    cmd.add_flag_function(flag, [&into, key](std::int64_t on) { into.emplace_back(key, on > 0 ? "on" : "off"); },
                          specHelp(d, p))
        ->check(switchValue(p));
  else
    cmd.add_option_function<std::string>(flag, [&into, key](const std::string& v) { into.emplace_back(key, v); },
                                         specHelp(d, p));
}

void addPassFlags(CLI::App& cmd, GiArgs& a) {
  std::set<std::string> added;
  for (const GiDescriptor* d : giDescriptors()) {
    for (const ParamSpec& p : d->params)
      if (added.insert(p.key).second) addSpecFlag(cmd, *d, p, a.given);
    for (const ParamSpec& p : d->view_params)
      if (added.insert(p.key).second) addSpecFlag(cmd, *d, p, a.view);
  }
  cmd.add_option_function<std::vector<std::string>>(
         "--gi-param",
         [&a](const std::vector<std::string>& list) {
           for (const std::string& kv : list) {
             const auto eq = kv.find('=');
             if (eq == std::string::npos || eq == 0)
               throw CLI::ValidationError("--gi-param: expected KEY=VALUE, got '" + kv + "'");
             a.given.emplace_back(kv.substr(0, eq), kv.substr(eq + 1));
           }
         },
         "a GI pass parameter by key, as its --KEY flag (repeatable)")
      ->take_all();
}

std::string giModesHelp() {
  std::string s = "global illumination: none, reference (ray-traced diffuse indirect light, --gi-bounces, written as "
                  "<out>_gi_reference.exr/.png)";
  for (const GiDescriptor* d : giDescriptors())
    s += ", " + d->name + " (" + d->summary + ", its indirect image as <out>_gi_" + d->name + ".exr/.png)";
  return s;
}

}  // namespace

void addGiFlags(CLI::App& cmd, GiArgs& a) {
  cmd.add_option("--gi", a.mode, giModesHelp())->capture_default_str();
  cmd.add_option("--gi-samples", a.samples, "--gi reference: hemisphere samples per pixel (1.." +
                                                std::to_string(kMaxGiSamples) + ")")
      ->capture_default_str();
  cmd.add_option("--gi-shadows", a.shadows,
                 "--gi reference: visibility of the lights from the bounce points (none|ray; default: none, or the "
                 "transport the GI pass models with --gi-reference)");
  cmd.add_option("--gi-seed", a.seed, "--gi reference: seed of the hemisphere samples")->capture_default_str();
  cmd.add_option("--gi-bounces", a.bounces,
                 "bounces of the indirect light (1.." + std::to_string(kMaxIndirectBounces) +
                     "): of --gi reference, and of a GI pass up to what it models (its --gi-reference traces as many)")
      ->capture_default_str();
  addPassFlags(cmd, a);
  cmd.add_flag("--gi-reference", a.with_reference,
               "with a GI pass: also trace the Embree reference (--gi-samples, --gi-seed) and report gi_rel_rmse");
}

const GiDescriptor* giPassOf(const GiArgs& a) {
  if (a.mode == "none" || a.mode == "reference") return nullptr;
  return &findGi(a.mode, "--gi");
}

namespace {

// The given values of `d`'s keys (the flags of every pass share one list).
SettingList givenFor(const GiDescriptor& d, const SettingList& given) {
  SettingList s;
  for (const auto& kv : given)
    if (d.param(kv.first)) s.push_back(kv);
  return s;
}

bool isGiPass(const std::string& name) {
  for (const GiDescriptor* d : giDescriptors())
    if (d->name == name) return true;
  return false;
}

std::string allGiKeys() {
  std::string keys;
  for (const GiDescriptor* d : giDescriptors())
    for (const ParamSpec& p : d->params) keys += (keys.empty() ? "" : "|") + p.key;
  return keys;
}

std::string referencePasses() {
  std::string s;
  for (const GiDescriptor* d : giDescriptors())
    if (d->reference_shadows) s += (s.empty() ? "" : "|") + d->name;
  return s;
}

// Every given value is checked against the pass that reads it, with or
// without --gi naming that pass (as a technique's flags are).
void checkGiParams(const GiArgs& a) {
  for (const auto& [key, value] : a.given)
    if (!giParamOwner(key)) throw UserError("--gi-param: unknown GI parameter '" + key + "' (" + allGiKeys() + ")");
  for (const GiDescriptor* d : giDescriptors())
    if (const SettingList mine = givenFor(*d, a.given); !mine.empty()) (void)giParams(*d, mine);
}

void checkGiViews(const GiArgs& a, const GiDescriptor* pass, const std::string& out) {
  if (a.view.empty()) return;
  for (const auto& [key, value] : a.view) {
    const GiDescriptor* owner = giViewParamOwner(key);
    if (owner != pass) {
      const std::string flag = owner->viewParam(key)->renderFlag();
      checkParamValue(*owner->viewParam(key), value, flag);
      throw UserError(flag + ": only with --gi " + owner->name);
    }
  }
  (void)giViewParams(*pass, giParams(*pass, givenFor(*pass, a.given)), a.view);
  if (out.empty())
    throw UserError(pass->view_params.front().renderFlag() + ": needs --out (the images are <out>_gi_" + pass->name +
                    "_*.exr/.png)");
}

void checkGiFiles(const GiArgs& a, const GiDescriptor* pass, const std::string& out) {
  if (a.mode == "none" || out.empty()) return;
  const bool reference = a.mode == "reference" || a.with_reference;
  for (const char* ext : {".exr", ".png"}) {
    if (reference) requireImageFile("--out", giOutputPath(out, "reference", ext));
    if (pass) requireImageFile("--out", giOutputPath(out, pass->name, ext));
  }
  if (pass)
    for (const std::string& suffix : pass->extra_images)
      requireImageFile("--out", giOutputPath(out, pass->name + "_" + suffix, ".png"));
}

}  // namespace

std::string giShadows(const GiArgs& a) {
  if (!a.shadows.empty()) return a.shadows;
  const GiDescriptor* d = giPassOf(a);
  if (!d || !d->reference_shadows) return "none";
  return d->reference_shadows(giParams(*d, givenFor(*d, a.given)));
}

void checkGiFlags(const GiArgs& a, const std::string& out) {
  if (a.mode != "none" && a.mode != "reference" && !isGiPass(a.mode))
    throw UserError("--gi: expected none|reference|" + giNames() + ", got '" + a.mode + "'");
  if (a.samples == 0 || a.samples > kMaxGiSamples)
    throw UserError("--gi-samples: expected 1.." + std::to_string(kMaxGiSamples) + ", got " + std::to_string(a.samples));
  if (!a.shadows.empty() && a.shadows != "none" && a.shadows != "ray")
    throw UserError("--gi-shadows: expected none|ray, got '" + a.shadows + "'");
  if (a.bounces < 1 || a.bounces > kMaxIndirectBounces)
    throw UserError("--gi-bounces: expected 1.." + std::to_string(kMaxIndirectBounces) + ", got " +
                    std::to_string(a.bounces));
  checkGiParams(a);
  const GiDescriptor* pass = giPassOf(a);
  if (a.with_reference && !(pass && pass->reference_shadows))
    throw UserError("--gi-reference: only with --gi " + referencePasses());
  if (pass && a.bounces > pass->max_bounces)
    throw UserError("--gi-bounces " + std::to_string(a.bounces) + ": --gi " + pass->name + " models 1.." +
                    std::to_string(pass->max_bounces) + " (more: --gi reference)");
  if (a.with_reference) {
    const std::string models = pass->reference_shadows(giParams(*pass, givenFor(*pass, a.given)));
    if (giShadows(a) != models)
      throw UserError("--gi-shadows: the reference must model the transport of --gi " + pass->name +
                      " as set (--gi-shadows " + models + ")");
  }
  checkGiViews(a, pass, out);
  checkGiFiles(a, pass, out);
}

ParamValues giPassParams(const GiArgs& a) {
  const GiDescriptor& d = *giPassOf(a);
  return giParams(d, givenFor(d, a.given));
}

std::unique_ptr<GiPass> makeFrameGiPass(const GiArgs& a, ClRuntime& cl, const Scene& scene) {
  const GiDescriptor* d = giPassOf(a);
  if (!d) return nullptr;
  return makeGiPass(*d, cl, giPassParams(a), scene, a.bounces);
}

std::string giOutputPath(const std::string& out, const std::string& kind, const std::string& ext) {
  std::filesystem::path p(out);
  p.replace_extension();
  return p.string() + "_gi_" + kind + ext;
}

}  // namespace ml
