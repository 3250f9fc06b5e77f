#include "host/techniques/Registry.hpp"

#include <deque>
#include <stdexcept>

#include "host/assign/BruteForceAssigner.hpp"
#include "host/clustered/ClusteredAssigner.hpp"
#include "host/hashed/HashedAssigner.hpp"
#include "host/tiled/TiledAssigner.hpp"
#include "host/util/Error.hpp"

namespace ml {
namespace {

struct Registry {
  std::vector<const TechniqueDescriptor*> descriptors = {
      // One line per technique; `techniques`, help and bench sweeps list them in this order.
      &bruteForceTechnique(),
      &hashedTechnique(),
      &tiledTechnique(),
      &clusteredTechnique(),
  };
  std::deque<TechniqueDescriptor> extra;  // registerTechnique() copies (stable addresses)
  bool read = false;
  std::vector<TechniqueInfo> infos;
  std::vector<RegistryParam> params;

  void build() {
    read = true;
    const std::size_t built_ins = descriptors.size() - extra.size();  // extras come last
    for (std::size_t i = 0; i < descriptors.size(); ++i) {
      const TechniqueDescriptor* d = descriptors[i];
      const bool built_in = i < built_ins;
      for (const TechniqueName& n : d->names)
        infos.push_back({n.name, n.pipeline, n.description, d->max_lights, d, &n, built_in});
      for (const ParamSpec& p : d->params) addParam(*d, p);
    }
  }
  void addParam(const TechniqueDescriptor& d, const ParamSpec& p) {
    for (RegistryParam& rp : params)
      if (rp.spec.key == p.key) {
        if (!rp.spec.sameAs(p))
          throw std::logic_error("technique parameter '" + p.key + "' is described differently by " + d.family +
                                 " and " + rp.families.front());
        rp.families.push_back(d.family);
        return;
      }
    params.push_back({p, {d.family}});
  }
};

Registry& registry() {
  static Registry r;
  return r;
}

Registry& built() {
  Registry& r = registry();
  if (!r.read) r.build();
  return r;
}

}  // namespace

const std::vector<const TechniqueDescriptor*>& techniqueDescriptors() { return built().descriptors; }

void registerTechnique(const TechniqueDescriptor& descriptor) {
  Registry& r = registry();
  if (r.read) throw std::logic_error("registerTechnique(" + descriptor.family + ") after the registry was read");
  for (const TechniqueDescriptor* d : r.descriptors)
    for (const TechniqueName& a : d->names)
      for (const TechniqueName& b : descriptor.names)
        if (a.name == b.name) throw std::logic_error("registerTechnique: '" + a.name + "' is already registered");
  r.descriptors.push_back(&r.extra.emplace_back(descriptor));
}

const std::vector<TechniqueInfo>& techniques() { return built().infos; }

std::string techniqueNames() {
  std::string s;
  for (const auto& t : techniques()) s += (s.empty() ? "" : "|") + t.name;
  return s;
}

const TechniqueInfo& findTechnique(const std::string& name, const std::string& flag) {
  for (const auto& t : techniques())
    if (t.name == name) return t;
  throw UserError(flag + ": unknown technique '" + name + "' (choose " + techniqueNames() + ")");
}

const std::vector<RegistryParam>& registryParams() { return built().params; }

const ParamSpec& findParam(const std::string& key, const std::string& flag) {
  std::string keys;
  for (const RegistryParam& p : registryParams()) {
    if (p.spec.key == key) return p.spec;
    keys += (keys.empty() ? "" : "|") + p.spec.key;
  }
  throw UserError(flag + ": unknown parameter '" + key + "' (choose " + keys + ")");
}

void checkParam(const std::string& key, const std::string& value, const std::string& flag) {
  checkParamValue(findParam(key, flag), value, flag);
}

ParamValues techniqueParams(const TechniqueInfo& t, const std::vector<std::pair<std::string, std::string>>& given,
                            const std::string& flag) {
  ParamValues v = t.descriptor->defaults();
  for (const auto& [key, value] : given)
    if (const ParamSpec* spec = t.descriptor->param(key)) {
      checkParamValue(*spec, value, flag);
      v.set(key, value);
    }
  return v;
}

std::unique_ptr<LightAssigner> makeAssigner(const TechniqueInfo& t, ClRuntime& cl, const ParamValues& params,
                                            const Scene* scene) {
  return t.descriptor->make(TechniqueContext{cl, *t.technique_name, params, scene});
}

std::unique_ptr<LightAssigner> makeAssigner(const std::string& technique, ClRuntime& cl, const Scene* scene) {
  const TechniqueInfo& t = findTechnique(technique);
  return makeAssigner(t, cl, t.descriptor->defaults(), scene);
}

}  // namespace ml
