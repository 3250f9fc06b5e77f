#include "host/view/ViewerSession.hpp"

#include "host/run/OutputFiles.hpp"
#include "host/util/Error.hpp"
#include "host/util/ThesisSeed.hpp"

namespace ml {
namespace {

constexpr std::size_t kHistoryFrames = 240;  // the rolling plot's length

}  // namespace

ViewerSession::ViewerSession(RunContext& ctx, ViewerSetup setup)
    : ctx_(ctx), setup_(std::move(setup)), cameras_(setup_.cameras) {
  renderer_ = std::make_unique<FrameRenderer>(*ctx_.cl, setup_.scene, setup_.width, setup_.height);
  lights_ = setup_.lights;
  renderer_->setLights(lights_);
  gi_ = std::make_unique<ViewerGi>(*ctx_.cl, setup_.scene);
  given_ = setup_.params;
  controller_.set(cameras_.frames.front());
  setTechnique(setup_.technique);
}

void ViewerSession::rebuildAssigner() {
  const std::vector<std::pair<std::string, std::string>> given(given_.begin(), given_.end());
  params_ = techniqueParams(*technique_, given, "--param");
  assigner_.reset();  // the old structures go first: two at once may not fit the device
  assigner_ = makeAssigner(*technique_, *ctx_.cl, params_, &setup_.scene);
  stale_ = true;
}

void ViewerSession::setTechnique(const std::string& name) {
  const TechniqueInfo& t = findTechnique(name, "technique");
  if (lights_.size() > t.max_lights)
    throw UserError("technique: '" + name + "' addresses at most " + std::to_string(t.max_lights) + " lights, " +
                    std::to_string(lights_.size()) + " are loaded");
  const TechniqueInfo* before = technique_;
  technique_ = &t;
  if (before) {
    rebuildOrRestore([&] { technique_ = before; });
  } else {
    rebuildAssigner();
  }
  // A debug view belongs to one technique; the shared modes carry over.
  bool offered = false;
  for (const ViewMode& m : viewModes()) offered |= m.name == view_mode_;
  if (!offered) view_mode_ = "shaded";
}

void ViewerSession::setParam(const std::string& key, const std::string& value) {
  checkParam(key, value, "param");
  const auto old = given_.find(key);
  const std::optional<std::string> before = old == given_.end() ? std::nullopt : std::optional(old->second);
  given_[key] = value;
  rebuildOrRestore([&] {
    if (before) given_[key] = *before;
    else given_.erase(key);
  });
}

// A technique may refuse a combination only when it is built (e.g. a device
// limit): the session then goes back to its last working state and rethrows.
void ViewerSession::rebuildOrRestore(const std::function<void()>& restore) {
  try {
    rebuildAssigner();
  } catch (...) {
    restore();
    rebuildAssigner();
    throw;
  }
}

void ViewerSession::setLightCount(std::uint64_t count) {
  if (count == 0 || count > technique_->max_lights)
    throw UserError("lights: expected 1.." + std::to_string(technique_->max_lights) + " for '" + technique_->name +
                    "', got " + std::to_string(count));
  lights_ = setup_.generate_lights(static_cast<std::uint32_t>(count));
  renderer_->setLights(lights_);
  setAnimation(animate_fraction_, animate_speed_);
  stale_ = true;
}

void ViewerSession::setAnimation(double fraction, double speed) {
  // LightAnimator checks both values (UserError naming --animate / --animate-speed).
  auto animator = std::make_unique<LightAnimator>(lights_, fraction, kThesisSeed, speed);
  animate_fraction_ = fraction;
  animate_speed_ = speed;
  animator_ = fraction > 0.0 ? std::move(animator) : nullptr;
}

std::vector<ViewMode> ViewerSession::viewModes() const {
  std::vector<ViewMode> modes = {{"shaded", "shaded"},
                                 {"heatmap", "heat map: lights evaluated"},
                                 {"bound-heatmap", "heat map: lower bound (lights in range)"},
                                 {"ratio-map", "evaluations / lower bound"}};
  for (const DebugViewSpec& v : technique_->descriptor->debug_views) modes.push_back({v.name, v.name + " view"});
  if (gi_->on()) {
    const GiDescriptor& d = gi_->descriptor();
    modes.push_back({"indirect", "indirect light (" + d.name + ")"});
    if (!d.view_name.empty()) modes.push_back({d.view_name, d.view_name + " (" + d.name + ")"});
  }
  return modes;
}

void ViewerSession::setGi(const std::string& mode) {
  gi_->setMode(mode);
  bool offered = false;  // the GI views go with their pass
  for (const ViewMode& m : viewModes()) offered |= m.name == view_mode_;
  if (!offered) view_mode_ = "shaded";
  stale_ = true;
}

void ViewerSession::setGiParam(const std::string& key, const std::string& value) {
  gi_->setParam(key, value);
  stale_ = true;
}

void ViewerSession::setGiView(const std::string& key, const std::string& value) {
  gi_->setView(key, value);
  stale_ = true;
}

void ViewerSession::setViewMode(const std::string& name) {
  std::string names;
  for (const ViewMode& m : viewModes()) {
    if (m.name == name) {
      view_mode_ = name;
      stale_ = true;
      return;
    }
    names += (names.empty() ? "" : "|") + m.name;
  }
  throw UserError("view: '" + name + "' is not a view of '" + technique_->name + "' (choose " + names + ")");
}

void ViewerSession::setHeatmapMax(std::uint32_t max_value) {
  heatmap_max_ = max_value;
  stale_ = true;
}

void ViewerSession::setRatioMax(double max_ratio) {
  if (!(max_ratio > 1.0 && max_ratio <= 1e6))
    throw UserError("ratio_max: expected a ratio above 1 (up to 1e6), got " + std::to_string(max_ratio));
  ratio_max_ = max_ratio;
  stale_ = true;
}

std::optional<HeatmapKind> ViewerSession::heatmapKind() const {
  if (view_mode_ == "heatmap") return HeatmapKind::Evaluated;
  if (view_mode_ == "bound-heatmap") return HeatmapKind::Bound;
  if (view_mode_ == "ratio-map") return HeatmapKind::Ratio;
  return std::nullopt;
}

void ViewerSession::setCameraFrame(std::size_t index) {
  if (index >= cameras_.frames.size())
    throw UserError("camera_frame: " + std::to_string(index) + " is past the camera path's " +
                    std::to_string(cameras_.frames.size()) + " frames");
  path_frame_ = index;
  controller_.set(cameras_.frames[index]);
}

void ViewerSession::setCamera(const Camera& c) { controller_.set(c); }

void ViewerSession::startRecording() {
  recording_ = true;
  recorded_.frames.clear();
}

void ViewerSession::saveRecording(const std::string& path) {
  if (!recording_ || recorded_.frames.empty())
    throw UserError(path + ": no camera path recorded (start recording, then render frames)");
  requireOutputFile("record", path);
  saveCameraJson(path, recorded_);
  recording_ = false;
}

bool ViewerSession::needsCounts() const {
  return counts_requested_ || heatmapKind().has_value();
}

bool ViewerSession::frame() {
  if (playing_ && !cameras_.frames.empty()) setCameraFrame((path_frame_ + 1) % cameras_.frames.size());
  if (!stale_ && !animator_ && controller_.version() == rendered_version_) return false;
  if (animator_) {
    lights_ = animator_->step();
    renderer_->setLights(lights_);
  }
  render();
  return true;
}

void ViewerSession::render() {
  const Camera& camera = controller_.camera();
  if (needsCounts()) {
    last_ = countedRender(*renderer_, *assigner_, {.pipeline = technique_->pipeline}, camera);
    counts_ = last_;
    counts_requested_ = false;
  } else {
    last_ = renderer_->render(camera, *assigner_, {.pipeline = technique_->pipeline, .gi = gi_->pass()});
  }
  if (!PassTimings::isMissing(last_.passes.total())) history_ms_.push_back(last_.passes.total());  // no n/a points
  if (history_ms_.size() > kHistoryFrames) history_ms_.pop_front();
  if (recording_) recorded_.frames.push_back(camera);
  rendered_version_ = controller_.version();
  stale_ = false;
}

std::vector<float> ViewerSession::image() {
  if (stale_ || controller_.version() != rendered_version_) render();
  if (view_mode_ == "shaded") return renderer_->targets().readColor();
  if (view_mode_ == "indirect") return gi_->indirectImage();
  if (gi_->on() && view_mode_ == gi_->descriptor().view_name)
    return gi_->viewImage(controller_.camera(), width(), height());
  if (const auto kind = heatmapKind()) {
    const double top = *kind == HeatmapKind::Ratio ? ratio_max_ : double(heatmap_max_);
    FrameHeatmap map = frameHeatmap(*renderer_, technique_->pipeline, {*kind, top});
    shown_scale_ = map.scale;
    return std::move(map.rgba);
  }
  return frameDebugView(*renderer_, technique_->pipeline, controller_.camera(), *assigner_, view_mode_);
}

void ViewerSession::screenshot(const std::string& path) {
  requireImageFile("screenshot", path);
  writeImageAtomically("screenshot", path, width(), height(), 4, image());
}

}  // namespace ml
