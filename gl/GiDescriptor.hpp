#pragma once
// How a global-illumination pass describes itself, in its own folder, the way
// a technique does (host/assign/TechniqueDescriptor.hpp, whose ParamSpec it
// shares): its `--gi` name, a summary, its parameters, a factory, whether a
// ray-traced reference can check it, the images it writes besides its
// indirect light, and optional views of its own data. The registry
// (host/gi/Registry.hpp) lists descriptors; `render` (flags, help, files,
// stats), `bench` (sweeps) and the viewer (panel widgets, script keys) take
// everything from here, so a GI pass is a folder plus one registry line.
//
// Parameters: a ParamSpec's range is what the pass accepts key by key;
// `check` refuses what depends on several keys (UserError naming the flag).
// Values reach the factory with the defaults filled in and switches written
// on|off (host/gi/Registry.hpp: giParams).
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "gl/GiPass.hpp"
#include "host/assign/TechniqueDescriptor.hpp"

namespace ml {

class ClRuntime;
struct Scene;

struct GiContext {
  ClRuntime& cl;
  const ParamValues& params;  // every parameter of the pass, checked
  const Scene& scene;
  unsigned bounces = 1;       // --gi-bounces: light bounces to model, 1..the descriptor's max_bounces
};

using SettingList = std::vector<std::pair<std::string, std::string>>;

struct GiDescriptor {
  std::string name;     // `--gi NAME` (e.g. vct); files <out>_gi_NAME.exr/.png
  std::string summary;  // one line for help and the panel
  std::vector<ParamSpec> params;
  std::function<void(const ParamValues&)> check{};  // the whole set; empty: each key alone suffices
  std::function<std::unique_ptr<GiPass>(const GiContext&)> make;
  // The reference's --gi-shadows (none|ray) for the transport the pass models
  // with these parameters; empty: no --gi-reference comparison.
  std::function<std::string(const ParamValues&)> reference_shadows{};
  std::vector<std::string> extra_images{};  // GiPass::extraImages() suffixes: <out>_gi_NAME_<suffix>.png
  unsigned max_bounces = 1;                 // the most --gi-bounces the pass models

  // Views of the pass's data (GiPass::view): the viewer's view mode
  // `view_name` ("" : none) and render's files when a view flag is given.
  std::string view_name{};
  std::vector<ParamSpec> view_params{};  // render --KEY flags, viewer widgets, script keys
  // The given view values against the settings (e.g. a level below the
  // levels); `given`: only the keys the user gave. UserError naming the flag.
  std::function<void(const ParamValues& params, const SettingList& given, const ParamValues& view)> check_view{};
  // After a settings change in the viewer: bring view values back in range.
  std::function<void(const ParamValues& params, ParamValues& view)> fit_view{};

  const ParamSpec* param(const std::string& key) const;  // null if not the pass's
  const ParamSpec* viewParam(const std::string& key) const;
  ParamValues defaults() const;
  ParamValues viewDefaults() const;
};

}  // namespace ml
