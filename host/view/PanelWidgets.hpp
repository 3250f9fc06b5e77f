#pragma once
// Small pieces the viewer's panel sections share: attempt() runs a panel
// action and turns a refused value (UserError) into the panel's error line;
// inputText() is a text field committed on Enter.
#include <imgui.h>

#include <cstdio>
#include <functional>
#include <string>

#include "host/assign/TechniqueDescriptor.hpp"

#include "host/util/Error.hpp"
#include "host/view/ViewerPanel.hpp"

namespace ml {

template <typename F>
void attempt(PanelState& state, F&& action) {
  try {
    action();
    state.error.clear();
  } catch (const UserError& e) {
    state.error = e.what();
  }
}

inline bool inputText(const char* label, std::string& text) {
  char buf[512];
  std::snprintf(buf, sizeof buf, "%s", text.c_str());
  const bool done = ImGui::InputText(label, buf, sizeof buf, ImGuiInputTextFlags_EnterReturnsTrue);
  text = buf;
  return done;
}

// One parameter's widget from its spec (ParamSpecWidget.cpp), for the
// technique's and the GI pass's parameters alike: a switch a checkbox, a
// choice a combo, counts and text a field committed on Enter (its edit kept in
// state.edits under `id`); `set` is attempted with the new text.
void drawParamSpec(PanelState& state, const ParamSpec& p, const std::string& value, const std::string& id,
                   const std::function<void(const std::string&)>& set);

// The GI section (ViewerGiPanel.cpp): none or a registered GI pass, its
// parameters and view parameters, all drawn from its descriptor.
class ViewerSession;
void drawGi(ViewerSession& s, PanelState& state);

}  // namespace ml
