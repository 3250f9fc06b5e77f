#pragma once
// The technique registry: the list of technique descriptors
// (host/assign/TechniqueDescriptor.hpp), one line per technique in
// Registry.cpp, flattened into `--technique` names. Commands read names,
// parameters (flags, help, accepted values) and factories from here and never
// name a technique themselves.
//
// Test binaries add descriptors at start-up with registerTechnique() (from a
// static initializer, before the first lookup); they then show in `render
// --help`, `bench --help` and `techniques` run in that binary (runCli).
//
// This folder sits above host/assign and the technique folders: assign (the
// interface) <- tiled/clustered/hashed (and gl/) <- techniques <- bench, app.
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "host/assign/LightAssigner.hpp"
#include "host/assign/TechniqueDescriptor.hpp"

namespace ml {

const std::vector<const TechniqueDescriptor*>& techniqueDescriptors();
// Appends a descriptor (copied); std::logic_error after the registry was first
// read or for a name already registered.
void registerTechnique(const TechniqueDescriptor& descriptor);

// One `--technique` name of a descriptor.
struct TechniqueInfo {
  std::string name;         // "forward", "deferred", "tiled-forward", ...
  Pipeline pipeline;
  std::string description;  // one line for --help
  std::uint32_t max_lights = UINT32_MAX;
  const TechniqueDescriptor* descriptor = nullptr;
  const TechniqueName* technique_name = nullptr;
  bool built_in = true;  // false: added by registerTechnique() (the `manylights` binary does not know it)
};
const std::vector<TechniqueInfo>& techniques();
// UserError naming `flag` and listing the valid names when `name` is unknown.
const TechniqueInfo& findTechnique(const std::string& name, const std::string& flag = "--technique");
std::string techniqueNames();  // "forward|deferred|..."

// Every parameter key of the registry once, with the families reading it.
// Techniques sharing a key (kernel_shape) must describe it alike
// (std::logic_error otherwise: a programming error, caught by the tests).
struct RegistryParam {
  ParamSpec spec;
  std::vector<std::string> families;
};
const std::vector<RegistryParam>& registryParams();
// UserError naming `flag` and listing the keys when no technique reads `key`.
const ParamSpec& findParam(const std::string& key, const std::string& flag);
// Checks `value` against the key's spec (UserError naming `flag`).
void checkParam(const std::string& key, const std::string& value, const std::string& flag);

// A technique's parameters: its defaults, then those of `given` (key, value)
// it reads, each checked; keys it does not read are skipped.
ParamValues techniqueParams(const TechniqueInfo& t, const std::vector<std::pair<std::string, std::string>>& given,
                            const std::string& flag);
std::unique_ptr<LightAssigner> makeAssigner(const TechniqueInfo& t, ClRuntime& cl, const ParamValues& params,
                                            const Scene* scene);
// Default parameters (tests, tools).
std::unique_ptr<LightAssigner> makeAssigner(const std::string& technique, ClRuntime& cl, const Scene* scene = nullptr);

}  // namespace ml
