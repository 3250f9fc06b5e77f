#pragma once
// `manylights view`: the interactive viewer (host/view/) over the same scene
// inputs, techniques and parameter flags as `render`. Everything a flag or a
// --script file says is checked before a window opens; without an X display
// the one error line names DISPLAY (exit 2).
#include <CLI/CLI.hpp>

#include <map>
#include <string>

#include "host/run/SceneInputs.hpp"

namespace ml {

struct ViewArgs {
  SceneInputArgs inputs;
  std::string technique = "deferred";
  std::string size = "960x540";
  std::string device;
  std::string script;  // JSON actions (host/view/ViewerScript.hpp); the viewer exits when they end
  std::map<std::string, std::string> params;
};

CLI::App* addViewCommand(CLI::App& app, ViewArgs& args);
int runView(const ViewArgs& args);

}  // namespace ml
