#include "host/bench/GiSweep.hpp"

#include "host/gi/Registry.hpp"
#include "host/util/Error.hpp"

namespace ml {
namespace {

GiVariant resolve(const GiDescriptor& d, const SettingList& given, const std::string& flag) {
  GiVariant v;
  v.mode = d.name;
  ParamValues params;
  try {
    params = giParams(d, given);
  } catch (const UserError& e) {
    throw UserError(flag + " " + paramsText(given) + ": " + e.what());
  }
  v.settings = giSettingList(d, params);
  v.make = [&d, params](ClRuntime& cl, const Scene& scene) { return makeGiPass(d, cl, params, scene); };
  return v;
}

}  // namespace

ParamSweep splitGiSweep(ParamSweep& sweep, const GiDescriptor* gi, const std::vector<const GiDescriptor*>& all,
                        const std::string& flag) {
  ParamSweep gi_sweep, rest;
  for (auto& s : sweep) {
    if (gi && gi->param(s.first)) {
      gi_sweep.push_back(std::move(s));
      continue;
    }
    for (const GiDescriptor* d : all)
      if (d->param(s.first))
        throw UserError(flag + ": '" + s.first + "' is a --gi " + d->name + " setting (add --gi " + d->name + ")");
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
    GiVariant v = resolve(*gi, labels, flag);
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
