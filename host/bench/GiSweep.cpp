#include "host/bench/GiSweep.hpp"

#include <algorithm>

#include "host/util/Error.hpp"

namespace ml {

bool GiDescriptor::owns(const std::string& key) const {
  return std::find(keys.begin(), keys.end(), key) != keys.end();
}

ParamSweep splitGiSweep(ParamSweep& sweep, const GiDescriptor* gi, const std::vector<const GiDescriptor*>& all,
                        const std::string& flag) {
  ParamSweep gi_sweep, rest;
  for (auto& s : sweep) {
    if (gi && gi->owns(s.first)) {
      gi_sweep.push_back(std::move(s));
      continue;
    }
    for (const GiDescriptor* d : all)
      if (d->owns(s.first))
        throw UserError(flag + ": '" + s.first + "' is a --gi " + d->mode + " setting (add --gi " + d->mode + ")");
    rest.push_back(std::move(s));
  }
  sweep = std::move(rest);
  return gi_sweep;
}

std::vector<GiVariant> expandGiVariants(const GiDescriptor* gi, const ParamSweep& sweep, const std::string& flag) {
  if (!gi) return {GiVariant{}};
  std::vector<const ParamSweep::value_type*> axes;
  for (const auto& s : sweep) axes.push_back(&s);
  std::vector<GiVariant> out;
  for (const auto& labels : sweepPoints(axes)) {
    GiVariant v = gi->resolve(labels, flag);
    v.labels = labels;
    out.push_back(std::move(v));
  }
  return out;
}

std::string giRunLabel(const GiVariant& g) {
  if (g.mode == "none") return "";
  return " gi=" + variantLabel(g.mode, g.labels);
}

}  // namespace ml
