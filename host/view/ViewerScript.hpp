#pragma once
// `view --script F.json`: a fixed list of actions played into a ViewerSession,
// one frame per `wait` step, then the viewer exits (for CI under Xvfb and for
// the README screenshot). The file is a JSON array (or {"actions": [...]}) of
// one-key objects:
//   {"technique": "tiled-forward"}      {"param": {"tile": "16"}}
//   {"lights": 256}                     {"animate": [fraction, speed]}
//   {"view": "heatmap"}                 {"heatmap_max": 40}
//   {"view": "ratio-map"}               {"ratio_max": 2.5}
//   {"view": "octree-cell"}             (a debug view of the current technique)
//   {"play": true}                      (the scene's camera path, one frame per frame)
//   {"camera_frame": 0}                 {"orbit": [yaw_deg, pitch_deg]}
//   {"fly": [forward, right, up]}       {"wait": frames}
//   {"screenshot": "a.png"}             (the rendered frame, no panel)
//   {"screenshot_window": "w.png"}      (the window as shown, panel included)
//   {"panel": false}                    {"counts": true}
//   {"record": "start"}                 {"record_save": "path.json"}
//   {"gi": NAME}                        {"gi_param": {KEY: "VALUE"}}   (a GI pass and its render flags, by key)
//   {"view": "indirect"}                {"view": VIEW}                 (with a GI pass; VIEW: its view_name)
//   {VIEW_KEY: VALUE}                   (a GI pass's view parameter, e.g. {"voxel_level": 1}: a number
//                                        for a count, else a string; host/gi/Registry.hpp)
// Loading checks the file's shape (UserError naming the file and the action's
// index); values are checked when they run, as the panel's are.
#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace ml {

class ViewerSession;

struct ScriptAction {
  std::string verb;
  nlohmann::json value;
  std::string where;  // "script.json: action 3 (lights)" for errors
};

// What the window loop does besides the session's actions.
struct ScriptWindowActions {
  bool panel = true;
  std::string window_screenshot;  // taken after the next frame is drawn, then cleared
};

class ViewerScript {
 public:
  static ViewerScript load(const std::string& path);
  // Runs actions until a wait or the end; false when the script has finished.
  bool step(ViewerSession& session, ScriptWindowActions& window);
  bool empty() const { return actions_.empty(); }

 private:
  void run(const ScriptAction& a, ViewerSession& session, ScriptWindowActions& window);
  std::vector<ScriptAction> actions_;
  std::size_t next_ = 0;
  unsigned waiting_ = 0;
};

}  // namespace ml
