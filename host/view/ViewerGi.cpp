#include "host/view/ViewerGi.hpp"

#include "host/gi/Registry.hpp"
#include "host/util/Error.hpp"
#include "host/util/GiToneMap.hpp"

namespace ml {
namespace {

// `list` with key set to value (replacing an earlier value of the key).
SettingList with(SettingList list, const std::string& key, const std::string& value) {
  for (auto& kv : list)
    if (kv.first == key) {
      kv.second = value;
      return list;
    }
  list.emplace_back(key, value);
  return list;
}

}  // namespace

ViewerGi::ViewerGi(ClRuntime& cl, const Scene& scene)
    : cl_(cl), scene_(scene), descriptor_(giDescriptors().front()) {
  select(*descriptor_, false);
}

ViewerGi::~ViewerGi() = default;

// The new pass is built before the old one goes: if it fails, nothing changed.
void ViewerGi::rebuild(const ParamValues& params) {
  auto pass = makeGiPass(*descriptor_, cl_, params, scene_);
  pass_ = std::move(pass);
  params_ = params;
}

// Selects `d` with the parameters and view values given for it so far.
void ViewerGi::select(const GiDescriptor& d, bool build) {
  const ParamValues params = giParams(d, given_[d.name]);
  ParamValues view = giViewParams(d, params, {});
  for (const auto& [key, value] : view_given_[d.name]) view.set(key, value);
  if (d.fit_view) d.fit_view(params, view);
  std::unique_ptr<GiPass> pass = build ? makeGiPass(d, cl_, params, scene_) : nullptr;
  descriptor_ = &d;
  params_ = params;
  view_ = view;
  pass_ = std::move(pass);
}

void ViewerGi::setMode(const std::string& mode) {
  if (mode == "none") {
    pass_.reset();
  } else {
    const GiDescriptor& d = findGi(mode, "gi");
    if (&d != descriptor_ || !pass_) select(d, true);
  }
  mode_ = mode;
}

void ViewerGi::setParam(const std::string& key, const std::string& value) {
  const SettingList given = with(given_[descriptor_->name], key, value);
  const ParamValues params = giParams(*descriptor_, given);
  if (pass_)
    rebuild(params);
  else
    params_ = params;
  given_[descriptor_->name] = given;
  if (descriptor_->fit_view) descriptor_->fit_view(params_, view_);
}

void ViewerGi::setView(const std::string& key, const std::string& value) {
  SettingList given;
  for (const auto& [k, v] : view_.entries()) given.emplace_back(k, v);  // the shown view, whole
  given = with(given, key, value);
  view_ = giViewParams(*descriptor_, params_, given);
  view_given_[descriptor_->name] = with(view_given_[descriptor_->name], key, value);
}

std::vector<float> ViewerGi::indirectImage() const {
  if (!pass_) throw UserError("view: the indirect light needs a GI pass");
  return giToneMapped(pass_->indirectRgba());
}

std::vector<float> ViewerGi::viewImage(const Camera& camera, unsigned width, unsigned height) {
  if (!pass_ || descriptor_->view_name.empty()) throw UserError("view: this view needs a GI pass that has one");
  return pass_->view(view_, {camera.view(), camera.projection(float(width) / float(height)), width, height}).display;
}

}  // namespace ml
