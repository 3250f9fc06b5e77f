#include "host/gi/Registry.hpp"

#include <deque>
#include <stdexcept>

#include "host/util/Error.hpp"
#include "host/vct/VctGiDescriptor.hpp"

namespace ml {
namespace {

struct Registry {
  std::vector<const GiDescriptor*> descriptors = {
      // One line per GI pass; help, the panel and sweeps list them in this order.
      &vct::giDescriptor(),
  };
  std::deque<GiDescriptor> extra;  // registerGi() copies (stable addresses)
  bool read = false;
};

Registry& registry() {
  static Registry r;
  return r;
}

Registry& built() {
  Registry& r = registry();
  r.read = true;
  return r;
}

// A key two passes share must mean the same to both (a flag has one meaning).
void checkSharedKeys(const GiDescriptor& d, const std::vector<const GiDescriptor*>& others) {
  for (const GiDescriptor* o : others)
    for (const ParamSpec& p : d.params)
      if (const ParamSpec* q = o->param(p.key); q && !q->sameAs(p))
        throw std::logic_error("GI parameter '" + p.key + "' is described differently by " + d.name + " and " +
                               o->name);
}

std::string keysOf(const std::vector<ParamSpec>& specs) {
  std::string s;
  for (const ParamSpec& p : specs) s += (s.empty() ? "" : "|") + p.key;
  return s;
}

// Switches as on|off whatever spelling was given, so records and widgets agree.
std::string canonical(const ParamSpec& spec, const std::string& value) {
  if (spec.type != ParamType::Switch) return value;
  ParamValues v;
  v.set(spec.key, value);
  return v.on(spec.key) ? "on" : "off";
}

}  // namespace

const std::vector<const GiDescriptor*>& giDescriptors() { return built().descriptors; }

void registerGi(const GiDescriptor& descriptor) {
  Registry& r = registry();
  if (r.read) throw std::logic_error("registerGi(" + descriptor.name + ") after the registry was read");
  for (const GiDescriptor* d : r.descriptors)
    if (d->name == descriptor.name) throw std::logic_error("registerGi: '" + d->name + "' is already registered");
  checkSharedKeys(descriptor, r.descriptors);
  r.descriptors.push_back(&r.extra.emplace_back(descriptor));
}

std::string giNames() {
  std::string s;
  for (const GiDescriptor* d : giDescriptors()) s += (s.empty() ? "" : "|") + d->name;
  return s;
}

const GiDescriptor& findGi(const std::string& name, const std::string& flag) {
  for (const GiDescriptor* d : giDescriptors())
    if (d->name == name) return *d;
  throw UserError(flag + ": expected none|" + giNames() + ", got '" + name + "'");
}

const GiDescriptor* giParamOwner(const std::string& key) {
  for (const GiDescriptor* d : giDescriptors())
    if (d->param(key)) return d;
  return nullptr;
}

const GiDescriptor* giViewParamOwner(const std::string& key) {
  for (const GiDescriptor* d : giDescriptors())
    if (d->viewParam(key)) return d;
  return nullptr;
}

namespace {

// `given` over `v`, each value checked and made canonical; `view` picks the
// descriptor's view table instead of its parameters.
ParamValues resolved(const GiDescriptor& d, ParamValues v, const SettingList& given, bool view) {
  for (const auto& [key, value] : given) {
    const ParamSpec* spec = view ? d.viewParam(key) : d.param(key);
    if (!spec)
      throw UserError("unknown --gi " + d.name + (view ? " view '" : " parameter '") + key + "' (" +
                      keysOf(view ? d.view_params : d.params) + ")");
    checkParamValue(*spec, value, spec->renderFlag());
    v.set(key, canonical(*spec, value));
  }
  return v;
}

}  // namespace

ParamValues giParams(const GiDescriptor& d, const SettingList& given) {
  ParamValues v = resolved(d, d.defaults(), given, false);
  if (d.check) d.check(v);
  return v;
}

ParamValues giViewParams(const GiDescriptor& d, const ParamValues& params, const SettingList& given) {
  ParamValues v = resolved(d, d.viewDefaults(), given, true);
  if (d.check_view) d.check_view(params, given, v);
  return v;
}

SettingList giSettingList(const GiDescriptor& d, const ParamValues& params) {
  SettingList s;
  for (const ParamSpec& p : d.params) s.emplace_back(p.key, params.text(p.key));
  return s;
}

std::unique_ptr<GiPass> makeGiPass(const GiDescriptor& d, ClRuntime& cl, const ParamValues& params,
                                   const Scene& scene, unsigned bounces) {
  return d.make(GiContext{cl, params, scene, bounces});
}

}  // namespace ml
