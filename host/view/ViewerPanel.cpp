#include "host/view/ViewerPanel.hpp"

#include <imgui.h>

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <cstdio>
#include <vector>

#include "host/util/Error.hpp"
#include "host/util/Heatmap.hpp"
#include "host/view/PanelWidgets.hpp"
#include "host/view/ViewerSession.hpp"

namespace ml {
namespace {

bool isSoftwareGl(const std::string& gl) {
  for (const char* name : {"llvmpipe", "softpipe", "SwiftShader", "software"})
    if (gl.find(name) != std::string::npos) return true;
  return false;
}

void drawDevices(ViewerSession& s) {
  RunContext& ctx = s.context();
  const std::string gl = ctx.gl->describe();
  ImGui::TextWrapped("%s", gl.c_str());
  ImGui::TextWrapped("OpenCL: %s", ctx.cl->info().name.c_str());
  ImGui::Text("CL/GL sharing: %s", shareModeName(ctx.cl->shareMode()).c_str());
  if (isSoftwareGl(gl))
    ImGui::TextColored(ImVec4(1.0f, 0.7f, 0.2f, 1.0f), "software GL: frame times are CPU rasteriser times");
}

void drawParam(ViewerSession& s, PanelState& state, const ParamSpec& p) {
  drawParamSpec(state, p, s.params().text(p.key), p.key, [&](const std::string& v) { s.setParam(p.key, v); });
}

void drawTechnique(ViewerSession& s, PanelState& state) {
  const std::string current = s.technique().name;
  if (ImGui::BeginCombo("technique", current.c_str())) {
    for (const TechniqueInfo& t : techniques())
      if (ImGui::Selectable(t.name.c_str(), t.name == current)) {
        attempt(state, [&] { s.setTechnique(t.name); });
        state.edits.clear();
      }
    ImGui::EndCombo();
  }
  for (const ParamSpec& p : s.technique().descriptor->params) drawParam(s, state, p);
}

void drawLights(ViewerSession& s, PanelState& state) {
  if (state.light_count == 0) state.light_count = int(s.lightCount());
  ImGui::InputInt("lights", &state.light_count, 64, 1024);
  ImGui::SameLine();
  if (ImGui::Button("regenerate"))
    attempt(state, [&] { s.setLightCount(std::uint64_t(std::max(state.light_count, 0))); });
  bool animate = s.animateFraction() > 0.0;
  float fraction = float(animate ? s.animateFraction() : 0.1), speed = float(s.animateSpeed());
  bool changed = ImGui::Checkbox("animate", &animate);
  changed |= ImGui::SliderFloat("moving fraction", &fraction, 0.001f, 1.0f, "%.3f");
  changed |= ImGui::SliderFloat("step (x radius)", &speed, 0.01f, 2.0f, "%.2f");
  if (changed) attempt(state, [&] { s.setAnimation(animate ? fraction : 0.0, speed); });
}

// The heat map's palette along its scale, the bottom, middle and top written under it.
void drawColourBar(const HeatmapScale& scale) {
  ImDrawList* draw = ImGui::GetWindowDrawList();
  const ImVec2 at = ImGui::GetCursorScreenPos();
  const float width = ImGui::GetContentRegionAvail().x, height = 14.0f;
  const int steps = 64;
  for (int i = 0; i < steps; ++i) {
    const Rgb c = heatmapColour(scale.kind, (float(i) + 0.5f) / steps);
    draw->AddRectFilled(ImVec2(at.x + width * i / steps, at.y), ImVec2(at.x + width * (i + 1) / steps, at.y + height),
                        ImGui::ColorConvertFloat4ToU32(ImVec4(c.r, c.g, c.b, 1.0f)));
  }
  ImGui::Dummy(ImVec2(width, height));
  const bool ratio = scale.kind == HeatmapKind::Ratio;
  const double bottom = ratio ? 1.0 : 0.0, mid = ratio ? (1.0 + scale.top) / 2 : std::floor(scale.top / 2);
  const char* format = ratio ? "%.3gx" : "%.0f";
  ImGui::Text(format, bottom);
  ImGui::SameLine(width * 0.5f);
  ImGui::Text(format, mid);
  ImGui::SameLine(std::max(width - 40.0f, width * 0.5f + 30.0f));
  ImGui::Text(format, scale.top);
}

void drawViewMode(ViewerSession& s, PanelState& state) {
  const std::vector<ViewMode> modes = s.viewModes();
  std::string current = s.viewMode();
  for (const ViewMode& m : modes)
    if (m.name == s.viewMode()) current = m.label;
  if (ImGui::BeginCombo("view", current.c_str())) {
    for (const ViewMode& m : modes)
      if (ImGui::Selectable(m.label.c_str(), m.name == s.viewMode())) attempt(state, [&] { s.setViewMode(m.name); });
    ImGui::EndCombo();
  }
  const auto kind = s.heatmapKind();
  if (!kind) return;
  if (*kind == HeatmapKind::Ratio) {
    double top = s.ratioMax();
    if (ImGui::InputDouble("scale top (x)", &top, 0.5, 1.0, "%.2f", ImGuiInputTextFlags_EnterReturnsTrue))
      attempt(state, [&] { s.setRatioMax(top); });
    ImGui::Text("lights evaluated / lights in range");
    const ImVec4 grey(kBoundZeroColour.r, kBoundZeroColour.g, kBoundZeroColour.b, 1.0f);
    ImGui::ColorButton("##bound0", grey, ImGuiColorEditFlags_NoTooltip, ImVec2(12, 12));
    ImGui::SameLine();
    ImGui::Text("no light in range (bound 0)");
  } else {
    int top = int(s.heatmapMax());
    if (ImGui::InputInt("scale top (0: frame max)", &top)) s.setHeatmapMax(std::uint32_t(std::max(top, 0)));
    ImGui::Text(*kind == HeatmapKind::Evaluated ? "lights evaluated per pixel" : "lights in range per pixel");
  }
  drawColourBar(s.shownScale());
}

void drawCamera(ViewerSession& s, PanelState& state) {
  CameraController& cam = s.camera();
  int mode = cam.mode == CameraMode::Fly ? 0 : 1;
  ImGui::RadioButton("fly (WASD QE, right drag)", &mode, 0);
  ImGui::RadioButton("orbit (left drag, scroll)", &mode, 1);
  cam.mode = mode == 0 ? CameraMode::Fly : CameraMode::Orbit;
  ImGui::SliderFloat("fly speed", &cam.speed, 0.05f, 5.0f, "%.2f");
  bool play = s.playing();
  if (ImGui::Checkbox("play path", &play)) s.setPlaying(play);
  int frame = int(s.pathFrame());
  ImGui::SameLine();
  if (ImGui::SliderInt("##frame", &frame, 0, int(s.cameraPath().frames.size()) - 1))
    attempt(state, [&] { s.setCameraFrame(std::size_t(frame)); });
  if (!s.recording()) {
    if (ImGui::Button("record path")) s.startRecording();
  } else {
    ImGui::Text("recording: %zu frames", s.recordedFrames());
    inputText("path file", state.record_file);
    if (ImGui::Button("save path"))
      attempt(state, [&] {
        s.saveRecording(state.record_file);
        state.message = "wrote " + state.record_file;
      });
  }
  inputText("image file", state.screenshot_file);
  if (ImGui::Button("screenshot (.png / .exr)"))
    attempt(state, [&] {
      s.screenshot(state.screenshot_file);
      state.message = "wrote " + state.screenshot_file;
    });
}

void drawTimings(ViewerSession& s) {
  const FrameResult& f = s.lastFrame();
  if (ImGui::BeginTable("passes", 2)) {
    for (std::size_t i = 0; i < f.passes.entries().size(); ++i) {
      const auto& [name, ms] = f.passes.entries()[i];
      ImGui::TableNextColumn();
      ImGui::TextUnformatted(name.c_str());
      ImGui::TableNextColumn();
      ImGui::Text("%8s ms%s", passTimeText(ms).c_str(), f.passes.clockAt(i) == PassClock::Host ? " (host)" : "");
    }
    ImGui::TableNextColumn();
    ImGui::TextUnformatted("sum of passes");
    ImGui::TableNextColumn();
    ImGui::Text("%8s ms", passTimeText(f.passes.total()).c_str());
    ImGui::EndTable();
  }
  const std::vector<float> history(s.frameHistoryMs().begin(), s.frameHistoryMs().end());
  if (!history.empty())
    ImGui::PlotLines("##history", history.data(), int(history.size()), 0, "sum of passes (ms)", 0.0f, FLT_MAX,
                     ImVec2(0, 60));
  if (ImGui::Button("count this frame")) s.requestCounts();
  if (const auto& c = s.lastCounts()) {
    ImGui::Text("light evaluations %llu", static_cast<unsigned long long>(c->light_evaluations));
    ImGui::Text("exact lower bound %llu", static_cast<unsigned long long>(c->lower_bound));
    ImGui::Text("ratio to bound    %.3f", c->lower_bound ? double(c->light_evaluations) / double(c->lower_bound) : 0.0);
  }
}

}  // namespace

void drawPanel(ViewerSession& s, PanelState& state) {
  ImGui::SetNextWindowPos(ImVec2(8, 8), ImGuiCond_FirstUseEver);
  ImGui::SetNextWindowSize(ImVec2(380, 0), ImGuiCond_FirstUseEver);
  ImGui::Begin("manylights");
  drawDevices(s);
  if (ImGui::CollapsingHeader("technique", ImGuiTreeNodeFlags_DefaultOpen)) drawTechnique(s, state);
  if (ImGui::CollapsingHeader("lights", ImGuiTreeNodeFlags_DefaultOpen)) drawLights(s, state);
  if (ImGui::CollapsingHeader("global illumination")) drawGi(s, state);
  if (ImGui::CollapsingHeader("view", ImGuiTreeNodeFlags_DefaultOpen)) drawViewMode(s, state);
  if (ImGui::CollapsingHeader("camera")) drawCamera(s, state);
  if (ImGui::CollapsingHeader("timings", ImGuiTreeNodeFlags_DefaultOpen)) drawTimings(s);
  if (!state.error.empty()) ImGui::TextColored(ImVec4(1.0f, 0.35f, 0.35f, 1.0f), "%s", state.error.c_str());
  if (!state.message.empty()) ImGui::TextUnformatted(state.message.c_str());
  ImGui::End();
}

}  // namespace ml
