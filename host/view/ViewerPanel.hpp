#pragma once
// The viewer's Dear ImGui panel over a ViewerSession: devices (CL/GL share
// mode; "software GL" on llvmpipe, so frame times are read for what they are),
// technique and every parameter of its descriptor (drawn by ParamType, never
// by name), global illumination (none / vct, the VCT settings table, the
// voxel view), lights (count, animation), view mode (heat maps with a colour bar
// and scale), camera (fly/orbit, path play/scrub, record), screenshot, pass
// timings (table, rolling plot) and on-demand counts. A refused value shows
// as the panel's error line; the session keeps its last working state.
#include <map>
#include <string>

namespace ml {

class ViewerSession;

struct PanelState {
  std::string error;
  std::map<std::string, std::string> edits;  // text being typed into parameter fields, by key
  int light_count = 0;
  std::string record_file = "camera_path.json";
  std::string screenshot_file = "screenshot.png";
  std::string message;  // last file written
};

void drawPanel(ViewerSession& session, PanelState& state);

}  // namespace ml
