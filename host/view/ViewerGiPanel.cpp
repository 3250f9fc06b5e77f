// The panel's GI section (declared in PanelWidgets.hpp).
#include <imgui.h>

#include <algorithm>
#include <string>

#include "host/vct/VctSettingsTable.hpp"
#include "host/vct/VoxelSlice.hpp"
#include "host/view/PanelWidgets.hpp"
#include "host/view/ViewerSession.hpp"

namespace ml {
namespace {

void drawVctSetting(ViewerSession& s, PanelState& state, const vct::VctSetting& v) {
  const std::string value = v.get(s.gi().settings());
  const std::string label = v.key + "##gi";
  if (v.type == vct::VctSettingType::Switch) {
    bool on = value == "on";
    if (ImGui::Checkbox(label.c_str(), &on)) attempt(state, [&] { s.setGiParam(v.key, on ? "on" : "off"); });
  } else if (v.type == vct::VctSettingType::Choice) {
    if (ImGui::BeginCombo(label.c_str(), value.c_str())) {
      for (const std::string& c : v.choices)
        if (ImGui::Selectable(c.c_str(), c == value)) attempt(state, [&] { s.setGiParam(v.key, c); });
      ImGui::EndCombo();
    }
  } else {  // Count and Number: typed, checked on Enter
    auto [it, fresh] = state.edits.try_emplace("gi:" + v.key, value);
    if (inputText(label.c_str(), it->second)) attempt(state, [&] { s.setGiParam(v.key, it->second); });
    (void)fresh;
  }
  if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s (render's %s)", v.help.c_str(), v.flag().c_str());
}

// Cubes, or a plane normal to x, y or z at a position (render's --voxel-slice).
void drawVoxelSlice(ViewerSession& s, PanelState& state) {
  const auto& slice = s.gi().voxelSlice();
  const char* axes[] = {"cubes", "slice x", "slice y", "slice z"};
  int axis = slice ? int(slice->axis) + 1 : 0;
  float position = slice ? slice->position : 0.5f;
  bool changed = ImGui::Combo("voxel shape", &axis, axes, 4);
  if (axis > 0) changed |= ImGui::SliderFloat("slice position", &position, 0.0f, 1.0f);
  if (!changed) return;
  const std::string text = axis == 0 ? "none" : vct::voxelSliceText({unsigned(axis - 1), position});
  attempt(state, [&] { s.setVoxelSlice(text); });
}

void drawVoxelView(ViewerSession& s, PanelState& state) {
  const char* current = vct::voxelViewName(s.gi().voxelView());
  if (ImGui::BeginCombo("voxel view", current)) {
    for (const char* k : {"albedo", "radiance", "opacity"})
      if (ImGui::Selectable(k, std::string(k) == current)) attempt(state, [&] { s.setVoxelView(k); });
    ImGui::EndCombo();
  }
  int level = int(s.gi().voxelLevel());
  if (ImGui::SliderInt("voxel level", &level, 0, int(s.gi().settings().grid.levels) - 1))
    attempt(state, [&] { s.setVoxelLevel(unsigned(std::max(level, 0))); });
  drawVoxelSlice(s, state);
}

}  // namespace

void drawGi(ViewerSession& s, PanelState& state) {
  bool vct = s.gi().on();
  if (ImGui::Checkbox("voxel cone tracing", &vct)) attempt(state, [&] { s.setGi(vct ? "vct" : "none"); });
  for (const vct::VctSetting& v : vct::vctSettings()) drawVctSetting(s, state, v);
  if (vct) drawVoxelView(s, state);
}

}  // namespace ml
