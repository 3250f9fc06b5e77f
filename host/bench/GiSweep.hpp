#pragma once
// A global-illumination pass as a sweep dimension of `bench`, without
// host/bench naming any GI pass's settings: the GI side describes itself
// (GiDescriptor: the keys --param may sweep, and how one point of the sweep
// becomes a pass), the way a technique's descriptor lists its parameters.
//  - splitGiSweep(): the --param keys the GI side owns leave the technique
//    sweep; a GI key without a GI mode is refused naming the mode to add.
//  - expandGiVariants(): the product over the GI keys, every point resolved
//    (each value parsed, the settings checked as a whole) before anything
//    renders; UserError naming `flag` and the key.
#include <cstddef>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "gl/GiPass.hpp"
#include "host/bench/BenchTypes.hpp"
#include "host/scene/Scene.hpp"

namespace ml {

class ClRuntime;

using SettingList = std::vector<std::pair<std::string, std::string>>;

// One point of a GI sweep: the mode and all its settings (defaults, then the sweep's).
struct GiVariant {
  std::string mode = "none";
  SettingList settings;  // every setting, as the GI side writes it back
  SettingList labels;    // the swept keys, for the run label
  std::function<std::unique_ptr<GiPass>(ClRuntime&, const Scene&)> make;  // empty: no GI pass
  std::size_t voxel_bytes = 0;
};

struct GiDescriptor {
  std::string mode;               // "vct": what --gi names
  std::vector<std::string> keys;  // the settings --param may sweep
  // The variant of `given` over the defaults; UserError naming `flag` and the key.
  std::function<GiVariant(const SettingList& given, const std::string& flag)> resolve;
  bool owns(const std::string& key) const;
};

// Moves the keys `gi` owns out of `sweep` into the returned GI sweep. `all`
// lists every GI descriptor (to name the mode a key needs when gi is null).
ParamSweep splitGiSweep(ParamSweep& sweep, const GiDescriptor* gi, const std::vector<const GiDescriptor*>& all,
                        const std::string& flag);
// {none} without a GI pass; otherwise one variant per point of `sweep`.
std::vector<GiVariant> expandGiVariants(const GiDescriptor* gi, const ParamSweep& sweep, const std::string& flag);
// "" for none; " gi=vct[voxels=32,cones=9]" (the swept keys) otherwise.
std::string giRunLabel(const GiVariant& g);

}  // namespace ml
