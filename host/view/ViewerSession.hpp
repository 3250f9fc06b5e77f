#pragma once
// What the viewer shows and the actions that change it, shared by the ImGui
// panel and the scripted mode (so a script drives exactly what a user does):
// the technique and its parameters (from the registry's descriptors, never
// named here), the light set (regenerate N, animate), the view mode, the
// camera (fly/orbit, the scene's path, recording), screenshots. Frames go
// through the run layer's renderer and assigners, as in `render`.
// A change marks the frame stale; frame() renders when stale or animated.
// Bad values from a script are UserErrors; the panel shows them instead.
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "gl/FrameRenderer.hpp"
#include "host/run/RunLayer.hpp"
#include "host/scene/Camera.hpp"
#include "host/scene/LightAnimator.hpp"
#include "host/techniques/Registry.hpp"
#include "host/view/CameraController.hpp"
#include "host/view/ViewerGi.hpp"

namespace ml {

struct ViewerSetup {
  Scene scene;
  std::vector<gpu::PointLight> lights;
  CameraPath cameras;
  std::string lights_label;
  // N lights as `render --lights N` generates them (same volumes, seed, radius).
  std::function<std::vector<gpu::PointLight>(std::uint32_t)> generate_lights;
  std::string technique;
  std::map<std::string, std::string> params;  // given flags, by key
  unsigned width = 0, height = 0;
};

// A view mode: the shaded image, a heat map of the counted frame (lights
// evaluated, lights in range = the exact lower bound, or their ratio), a
// debug view of the technique (DebugViewSpec name, e.g. "cluster"), or, with
// a GI pass on, "indirect" (the indirect light) and the pass's own view
// (its descriptor's view_name, e.g. "voxels"; ViewerGi).
struct ViewMode {
  std::string name;   // "shaded", "heatmap", "bound-heatmap", "ratio-map", or a debug view's name
  std::string label;  // for the panel
};

class ViewerSession {
 public:
  ViewerSession(RunContext& ctx, ViewerSetup setup);

  // Renders when something changed or lights animate; true if it rendered.
  bool frame();
  // The image of the current view mode, RGBA bottom-up (renders first if stale).
  std::vector<float> image();
  void screenshot(const std::string& path);

  void setTechnique(const std::string& name);
  void setParam(const std::string& key, const std::string& value);  // UserError if not accepted
  void setLightCount(std::uint64_t count);
  void setAnimation(double fraction, double speed);
  void setViewMode(const std::string& name);
  // Global illumination (ViewerGi): none or a GI pass, its parameters and
  // view parameters by key (host/gi/Registry.hpp).
  void setGi(const std::string& mode);
  void setGiParam(const std::string& key, const std::string& value);
  void setGiView(const std::string& key, const std::string& value);
  const ViewerGi& gi() const { return *gi_; }
  void setHeatmapMax(std::uint32_t max_value);  // the count heat maps' top; 0: the frame's maximum
  void setRatioMax(double max_ratio);           // the ratio map's top (above 1; UserError otherwise)
  void setCameraFrame(std::size_t index);
  void setCamera(const Camera& c);
  // Camera path playback: one path frame per rendered frame while playing.
  void setPlaying(bool on) { playing_ = on; }
  bool playing() const { return playing_; }
  std::size_t pathFrame() const { return path_frame_; }
  void requestCounts() { counts_requested_ = true; }
  void startRecording();
  void saveRecording(const std::string& path);  // UserError when nothing was recorded

  const TechniqueInfo& technique() const { return *technique_; }
  const ParamValues& params() const { return params_; }
  std::vector<ViewMode> viewModes() const;
  const std::string& viewMode() const { return view_mode_; }
  std::uint32_t heatmapMax() const { return heatmap_max_; }
  double ratioMax() const { return ratio_max_; }
  // The current view mode's heat map kind, if it is one.
  std::optional<HeatmapKind> heatmapKind() const;
  const HeatmapScale& shownScale() const { return shown_scale_; }  // the scale of the last heat map shown
  std::size_t lightCount() const { return lights_.size(); }
  double animateFraction() const { return animate_fraction_; }
  double animateSpeed() const { return animate_speed_; }
  const CameraPath& cameraPath() const { return cameras_; }
  std::size_t recordedFrames() const { return recording_ ? recorded_.frames.size() : 0; }
  bool recording() const { return recording_; }
  CameraController& camera() { return controller_; }
  const FrameResult& lastFrame() const { return last_; }
  const std::optional<FrameResult>& lastCounts() const { return counts_; }
  const std::deque<double>& frameHistoryMs() const { return history_ms_; }
  unsigned width() const { return renderer_->width(); }
  unsigned height() const { return renderer_->height(); }
  RunContext& context() { return ctx_; }
  const FrameRenderer& renderer() const { return *renderer_; }

 private:
  void rebuildAssigner();
  void rebuildOrRestore(const std::function<void()>& restore);
  bool needsCounts() const;
  void render();

  RunContext& ctx_;
  ViewerSetup setup_;
  std::unique_ptr<FrameRenderer> renderer_;
  std::unique_ptr<LightAssigner> assigner_;
  std::unique_ptr<ViewerGi> gi_;
  const TechniqueInfo* technique_ = nullptr;
  std::map<std::string, std::string> given_;  // parameter values set so far, by key (shared keys carry over)
  ParamValues params_;
  std::vector<gpu::PointLight> lights_;
  std::unique_ptr<LightAnimator> animator_;
  double animate_fraction_ = 0.0, animate_speed_ = 0.25;
  std::string view_mode_ = "shaded";
  std::uint32_t heatmap_max_ = 0;
  double ratio_max_ = 4.0;
  HeatmapScale shown_scale_;
  CameraPath cameras_;
  CameraController controller_;
  std::uint64_t rendered_version_ = ~std::uint64_t(0);
  bool playing_ = false;
  std::size_t path_frame_ = 0;
  bool recording_ = false;
  CameraPath recorded_;
  bool stale_ = true;
  bool counts_requested_ = false;
  FrameResult last_;
  std::optional<FrameResult> counts_;
  std::deque<double> history_ms_;
};

}  // namespace ml
