// A parameter's panel widget drawn from its ParamSpec (PanelWidgets.hpp).
#include <imgui.h>

#include "host/view/PanelWidgets.hpp"

namespace ml {

void drawParamSpec(PanelState& state, const ParamSpec& p, const std::string& value, const std::string& id,
                   const std::function<void(const std::string&)>& set) {
  const std::string label = p.key + "##" + id;
  if (p.type == ParamType::Switch) {
    bool on = value == "on" || value == "1" || value == "true";
    if (ImGui::Checkbox(label.c_str(), &on)) attempt(state, [&] { set(on ? "on" : "off"); });
  } else if (p.type == ParamType::Choice) {
    if (ImGui::BeginCombo(label.c_str(), value.c_str())) {
      for (const std::string& c : p.choices)
        if (ImGui::Selectable(c.c_str(), c == value)) attempt(state, [&] { set(c); });
      ImGui::EndCombo();
    }
  } else {  // Count and Text: typed, checked against the spec on Enter
    std::string& text = state.edits.try_emplace(id, value).first->second;
    if (inputText(label.c_str(), text)) attempt(state, [&] { set(text); });
  }
  if (ImGui::IsItemHovered())
    ImGui::SetTooltip("%s (%s; render's %s)", p.help.c_str(), p.allowed().c_str(), p.renderFlag().c_str());
}

}  // namespace ml
