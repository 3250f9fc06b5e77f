#pragma once
// The GI registry: the list of GI pass descriptors (gl/GiDescriptor.hpp), one
// line per pass in Registry.cpp, as host/techniques/Registry is for
// techniques. Front ends read names, parameters, views and factories from
// here and never name a GI pass themselves.
//
// Test binaries add descriptors at start-up with registerGi() (from a static
// initializer, before the first lookup); they then show in `render --help`,
// `bench --help` and the viewer of that binary (runCli).
//
// giParams(): a pass's parameters from (key, value) pairs: its defaults, each
// given value checked against its spec (UserError naming the --KEY flag),
// switches written on|off, then the pass's whole-set check; a key that is not
// the pass's is refused, naming the keys it has.
#include <memory>
#include <string>
#include <vector>

#include "gl/GiDescriptor.hpp"

namespace ml {

const std::vector<const GiDescriptor*>& giDescriptors();
// Appends a descriptor (copied); std::logic_error after the registry was first
// read, for a name already registered, or a key another GI pass describes
// differently (both passes' flags are one flag).
void registerGi(const GiDescriptor& descriptor);

std::string giNames();  // "vct|..." (without none)
// UserError naming `flag` and listing none|names when `name` is unknown ("none" is not a pass).
const GiDescriptor& findGi(const std::string& name, const std::string& flag = "--gi");
// The pass describing `key` as a parameter (or as a view parameter), null if none.
const GiDescriptor* giParamOwner(const std::string& key);
const GiDescriptor* giViewParamOwner(const std::string& key);

ParamValues giParams(const GiDescriptor& d, const SettingList& given);
// The view parameters: defaults, then `given` checked, then check_view.
ParamValues giViewParams(const GiDescriptor& d, const ParamValues& params, const SettingList& given);
// Every parameter in the descriptor's order, as giParams wrote it.
SettingList giSettingList(const GiDescriptor& d, const ParamValues& params);
std::unique_ptr<GiPass> makeGiPass(const GiDescriptor& d, ClRuntime& cl, const ParamValues& params,
                                   const Scene& scene, unsigned bounces = 1);

}  // namespace ml
