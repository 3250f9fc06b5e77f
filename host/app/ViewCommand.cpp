#include "host/app/ViewCommand.hpp"

#include <cstdlib>
#include <optional>

#include "host/run/InputChecks.hpp"
#include "host/app/InputFlags.hpp"
#include "host/app/RenderCommand.hpp"
#include "host/run/ImageSize.hpp"
#include "host/techniques/Registry.hpp"
#include "host/util/Error.hpp"
#include "host/view/Viewer.hpp"

namespace ml {

CLI::App* addViewCommand(CLI::App& app, ViewArgs& a) {
  auto* cmd = app.add_subcommand("view",
                                 "Interactive viewer: a window with a panel to fly through a scene and switch "
                                 "techniques, parameters, lights and view modes live");
  addInputFlags(*cmd, {kSceneInputFlags | kSuiteFlags | kDeviceFlag, &a.inputs, &a.device});
  cmd->add_option("--technique", a.technique, "one of: " + techniqueNames())->capture_default_str();
  cmd->add_option("--size", a.size, "WIDTHxHEIGHT of the window and the rendered frame")->capture_default_str();
  cmd->add_option("--script", a.script,
                  "JSON list of actions to play (technique, param, lights, view, camera_frame, orbit, fly, wait, "
                  "screenshot, record, ...), then exit; see docs/viewer.md");
  addTechniqueFlags(*cmd, a.params, nullptr);
  cmd->footer("Keys: WASD/QE fly, right drag looks (fly) or left drag turns (orbit), scroll zooms, F1 hides the "
              "panel, Esc quits.");
  return cmd;
}

namespace {

// GLFW here is the X11 build: without $DISPLAY no window can open.
void requireDisplay() {
  const char* display = std::getenv("DISPLAY");
  if (!display || !*display)
    throw UserError("view: DISPLAY is not set: the viewer needs an X display (run it under `xvfb-run -a`, "
                    "or use `render` for images without a window)");
}

}  // namespace

int runView(const ViewArgs& a) {
  ViewerSetup setup;
  parseSize(a.size, "--size", setup.width, setup.height);
  const TechniqueInfo& tech = findTechnique(a.technique);
  for (const auto& [key, value] : a.params) checkParam(key, value, findParam(key, "--param").renderFlag());
  (void)techniqueParams(tech, {a.params.begin(), a.params.end()}, "--param");
  std::optional<ViewerScript> script;
  if (!a.script.empty()) script = ViewerScript::load(a.script);
  const DeviceChoice device = DeviceChoice::resolve(a.device);
  requireDisplay();

  SceneInputs inputs = loadSceneInputs(a.inputs);
  checkLightLimits("--lights", inputs.lights.size(), {&tech}, a.inputs.lights.empty() ? "default" : a.inputs.lights);
  setup.scene = std::move(inputs.scene);
  setup.lights = std::move(inputs.lights);
  setup.cameras = std::move(inputs.cameras);
  setup.lights_label = inputs.lights_label;
  setup.generate_lights = [args = a.inputs](std::uint32_t count) {
    SceneInputArgs with_count = args;  // the same volumes, radius and seed as `render --lights N`
    with_count.lights = std::to_string(count);
    return loadSceneInputs(with_count).lights;
  };
  setup.technique = tech.name;
  setup.params = a.params;
  return runViewer(std::move(setup), device, std::move(script));
}

}  // namespace ml
