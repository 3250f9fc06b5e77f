#include "gl/GiDescriptor.hpp"

#include <stdexcept>

namespace ml {
namespace {

const ParamSpec* find(const std::vector<ParamSpec>& specs, const std::string& key) {
  for (const ParamSpec& p : specs)
    if (p.key == key) return &p;
  return nullptr;
}

ParamValues defaultsOf(const std::vector<ParamSpec>& specs) {
  ParamValues v;
  for (const ParamSpec& p : specs) v.set(p.key, p.default_value);
  return v;
}

}  // namespace

GiViewImage GiPass::view(const ParamValues&, const GiViewInputs&) {
  throw std::logic_error("GiPass::view: this pass has no views");
}

const ParamSpec* GiDescriptor::param(const std::string& key) const { return find(params, key); }
const ParamSpec* GiDescriptor::viewParam(const std::string& key) const { return find(view_params, key); }
ParamValues GiDescriptor::defaults() const { return defaultsOf(params); }
ParamValues GiDescriptor::viewDefaults() const { return defaultsOf(view_params); }

}  // namespace ml
