// The panel's GI section (declared in PanelWidgets.hpp): every widget from
// the registry's descriptors (host/gi/Registry.hpp), none named here.
#include <imgui.h>

#include <string>

#include "host/gi/Registry.hpp"
#include "host/view/PanelWidgets.hpp"
#include "host/view/ViewerSession.hpp"

namespace ml {
namespace {

void drawMode(ViewerSession& s, PanelState& state) {
  const std::string current = s.gi().on() ? s.gi().mode() : "none";
  if (ImGui::BeginCombo("gi pass", current.c_str())) {
    if (ImGui::Selectable("none", current == "none")) attempt(state, [&] { s.setGi("none"); });
    for (const GiDescriptor* d : giDescriptors()) {
      if (ImGui::Selectable(d->name.c_str(), d->name == current)) attempt(state, [&] { s.setGi(d->name); });
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", d->summary.c_str());
    }
    ImGui::EndCombo();
  }
}

}  // namespace

void drawGi(ViewerSession& s, PanelState& state) {
  drawMode(s, state);
  const GiDescriptor& d = s.gi().descriptor();
  for (const ParamSpec& p : d.params)
    drawParamSpec(state, p, s.gi().params().text(p.key), "gi:" + d.name + ":" + p.key,
                  [&](const std::string& v) { s.setGiParam(p.key, v); });
  if (!s.gi().on()) return;
  for (const ParamSpec& p : d.view_params)
    drawParamSpec(state, p, s.gi().view().text(p.key), "gi-view:" + d.name + ":" + p.key,
                  [&](const std::string& v) { s.setGiView(p.key, v); });
}

}  // namespace ml
