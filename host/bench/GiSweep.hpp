#pragma once
// A global-illumination pass as a sweep dimension of `bench`, without
// host/bench naming any GI pass or its settings: the pass's descriptor
// (gl/GiDescriptor.hpp, from host/gi/Registry) lists the keys --param may
// sweep, and host/gi turns one point of the sweep into checked parameters.
//  - splitGiSweep(): the --param keys the GI side owns leave the technique
//    sweep; a GI key without its pass's --gi is refused naming the pass to add.
//  - expandGiVariants(): the product over the GI keys, every point resolved
//    (each value checked, then the whole set) before anything renders;
//    UserError "<flag> key=value,...: <the pass's line naming --KEY>".
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "gl/GiDescriptor.hpp"
#include "host/run/RunRecords.hpp"
#include "host/scene/Scene.hpp"

namespace ml {

class ClRuntime;

// One point of a GI sweep: the pass and all its settings (defaults, then the sweep's).
struct GiVariant {
  std::string mode = "none";
  SettingList settings;  // every setting, as host/gi writes it (switches on|off)
  SettingList labels;    // the swept keys, for the run label
  std::function<std::unique_ptr<GiPass>(ClRuntime&, const Scene&)> make;  // empty: no GI pass
};

// Moves the keys `gi` owns out of `sweep` into the returned GI sweep. `all`
// lists every GI descriptor (to name the pass a key needs when gi is null).
ParamSweep splitGiSweep(ParamSweep& sweep, const GiDescriptor* gi, const std::vector<const GiDescriptor*>& all,
                        const std::string& flag);
// {none} without a GI pass; otherwise one variant per point of `sweep`.
std::vector<GiVariant> expandGiVariants(const GiDescriptor* gi, const ParamSweep& sweep, const std::string& flag);
// "" for none; " gi=vct[voxels=32,cones=9]" (the swept keys) otherwise.
std::string giRunLabel(const GiVariant& g);

}  // namespace ml
