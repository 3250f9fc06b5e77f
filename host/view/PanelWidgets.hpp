#pragma once
// Small pieces the viewer's panel sections share: attempt() runs a panel
// action and turns a refused value (UserError) into the panel's error line;
// inputText() is a text field committed on Enter.
#include <imgui.h>

#include <cstdio>
#include <string>

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

// The GI section (ViewerGiPanel.cpp): none / vct, every VCT setting of the
// settings table (drawn by type), the voxel view's kind and level.
class ViewerSession;
void drawGi(ViewerSession& s, PanelState& state);

}  // namespace ml
