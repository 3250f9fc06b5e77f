#pragma once
// How a light-assignment technique describes itself, in its own folder: its
// `--technique` names (each with the pipeline it runs in: forward, or deferred
// over a G-buffer), its parameters (key, type, default, accepted values, help),
// a factory, and optional hooks (debug views; stats and depth come from the
// LightAssigner it makes). The registry (host/techniques/Registry.hpp) is a list
// of descriptors; `render`, `bench`, `compare-reference` and the bench mains
// take flags, help text and validation from it, so adding a technique touches
// its folder, its .cl/.glsl files and one registry line.
//
// One source of truth for what a parameter accepts: a ParamSpec's range is
// what the technique's constructor accepts (e.g. tile 1..kMaxTileSize, the
// culler's limit), so every value of a sweep is checked before the first frame.
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "host/assign/ShaderContract.hpp"

namespace ml {

class ClRuntime;
class LightAssigner;
struct Scene;

enum class ParamType {
  Count,   // an unsigned integer in [min, max], or one of `choices` (words such as "auto")
  Choice,  // one of `choices`
  Switch,  // on|off (also 1|0, true|false); render: --KEY and --no-KEY
  Text,    // anything `check` accepts
};

struct ParamSpec {
  std::string key;  // bench --param KEY=...; render --KEY with '_' as '-' ("tile_depth" -> --tile-depth)
  ParamType type = ParamType::Text;
  std::string default_value;
  std::string help;
  unsigned min = 0, max = 0;         // Count
  std::vector<std::string> choices{};  // Choice; Count: words accepted besides numbers
  // Text: "" when the value is accepted, else what is expected; "" is never
  // accepted, so check("") says what is expected (for help and errors).
  std::function<std::string(const std::string&)> check{};

  std::string renderFlag() const;  // "--tile-depth"
  std::string allowed() const;     // "1..256", "1..1024 or auto", "none|minmax|mask", "on|off"
  // "" when `value` is accepted, else what is expected ("expected 1..256").
  std::string problem(const std::string& value) const;
  // Same key, type, default and accepted values (shared keys must agree across techniques).
  bool sameAs(const ParamSpec& other) const;
};

// UserError "FLAG: KEY=VALUE is not valid (expected ...)" unless accepted.
void checkParamValue(const ParamSpec& spec, const std::string& value, const std::string& flag);

// Parameter values by key, as text, already checked against their specs.
class ParamValues {
 public:
  void set(const std::string& key, const std::string& value);
  bool has(const std::string& key) const;
  const std::string& text(const std::string& key) const;  // std::logic_error for a key never set
  unsigned count(const std::string& key) const;           // Count values; a word (e.g. "auto") reads as 0
  bool on(const std::string& key) const;                   // Switch values
  const std::vector<std::pair<std::string, std::string>>& entries() const { return values_; }

 private:
  std::vector<std::pair<std::string, std::string>> values_;
};

struct TechniqueName {
  std::string name;  // "tiled-forward"
  Pipeline pipeline;
  std::string description;  // one line for `techniques` and --help
};

// A debug view a technique can write after a frame: `render --NAME-view F.png`.
struct DebugViewSpec {
  std::string name;  // "cluster"
  std::string help;
  std::string flag() const { return "--" + name + "-view"; }
};

// What a factory gets: the device, which of the technique's names runs, every
// parameter of the technique (defaults filled in, checked), and the scene
// (geometry-dependent structures, e.g. hashed's geometry mask; may be null).
struct TechniqueContext {
  ClRuntime& cl;
  const TechniqueName& name;
  const ParamValues& params;
  const Scene* scene = nullptr;
};

struct TechniqueDescriptor {
  std::string family;  // "tiled": names the technique in help text
  std::vector<TechniqueName> names;
  std::vector<ParamSpec> params;
  std::function<std::unique_ptr<LightAssigner>(const TechniqueContext&)> make;
  std::vector<DebugViewSpec> debug_views;
  // The most lights the technique addresses (hashed: 24-bit list entries);
  // commands check --lights against it before generating or loading lights.
  std::uint32_t max_lights = UINT32_MAX;

  const ParamSpec* param(const std::string& key) const;  // null if the technique does not read `key`
  ParamValues defaults() const;
};

// Spec builders, so descriptors read as a table.
ParamSpec countParam(std::string key, std::string default_value, unsigned min, unsigned max, std::string help,
                     std::vector<std::string> words = {});
ParamSpec choiceParam(std::string key, std::string default_value, std::vector<std::string> choices,
                      std::string help);
ParamSpec switchParam(std::string key, bool default_value, std::string help);
ParamSpec textParam(std::string key, std::string default_value, std::string help,
                    std::function<std::string(const std::string&)> check);
// The OpenCL kernel shape (auto|cpu|gpu) that tiled and clustered shading share.
ParamSpec kernelShapeParam();

}  // namespace ml
