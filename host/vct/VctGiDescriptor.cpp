#include "host/vct/VctGiDescriptor.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <string>

#include "host/scene/Scene.hpp"
#include "host/shared/voxel_types.h"
#include "host/util/Error.hpp"
#include "host/vct/VoxelCascade.hpp"
#include "host/vct/VoxelSlice.hpp"
#include "host/vct/VoxelView.hpp"

namespace ml::vct {
namespace {

constexpr unsigned kMaxLevels = 10;  // log2(ML_VOXEL_MAX_EDGE) + 1

// A finite number (the ranges are checkVctGiSettings'); "" when accepted.
std::string numberProblem(const std::string& t) {
  std::size_t used = 0;
  float v = 0;
  try {
    v = std::stof(t, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  return used == t.size() && used > 0 && std::isfinite(v) ? "" : "a number";
}

std::string sliceProblem(const std::string& t) {
  if (t == "none") return "";
  try {
    (void)parseVoxelSlice(t, "--voxel-slice");
  } catch (const UserError&) {
    return std::string(kVoxelSliceSyntax) + " or none (cubes)";
  }
  return "";
}

std::vector<ParamSpec> vctParams() {
  return {
      countParam("voxels", "64", 1, ML_VOXEL_MAX_EDGE, "level-0 voxels per axis (a power of two up to 512)"),
      countParam("levels", "auto", 1, kMaxLevels,
                 "mip levels (1..log2(voxels) + 1); auto: log2(voxels) - 1, the coarsest level four voxels across "
                 "at every --voxels",
                 {"auto"}),
      switchParam("anisotropic", true,
                  "anisotropic voxels (6 directions per voxel; off: one, 0.79x the memory, and on the Cornell box "
                  "1.1-1.5x the error: an isotropic voxel shows one colour from every side)"),
      countParam("cones", "9", 1, kMaxCones, "diffuse cones per pixel (1..32)"),
      textParam("cone-aperture", "45", "diffuse cone aperture in degrees (0..180)", numberProblem),
      textParam("cone-lod-bias", "1.5",
                "mip levels finer than a cone's width that it samples (0..4): more is sharper and slower, 1.25 suits "
                "grids coarse against the scene's detail",
                numberProblem),
      textParam("gi-scale", "0.5", "trace resolution as a fraction of the frame's, (0, 1]", numberProblem),
      switchParam("specular", false, "add a specular cone (reflectance 0.04, aperture 10 degrees)"),
      choiceParam("vct-shadows", "none", {"none", "voxel"},
                  "visibility of the lights in the injected direct light (none, or voxel: marched through level-0 "
                  "opacity)"),
      switchParam("revoxelize", false, "voxelize the scene every frame (moving geometry), not only the first"),
      countParam("vct-cascades", "1", 1, kMaxCascades,
                 "levels of the camera-centred cascade (1: one grid around the scene; L: the scene's grid and L - 1 "
                 "finer grids of --voxels around the camera, each half the extent of the one outside it)"),
      switchParam("vct-fold", false,
                  "mips across the cascade's levels: where a finer level's window lies, the coarser level takes its "
                  "voxels' opacity (needs --vct-cascades 2 or more)"),
  };
}

std::vector<ParamSpec> viewParams() {
  return {
      choiceParam("voxel_view", "radiance", {"albedo", "radiance", "opacity"},
                  "write the voxel volume seen from the camera as cubes as <out>_gi_vct_voxels.exr/.png"),
      countParam("voxel_level", "0", 0, kMaxLevels - 1, "--voxel-view: the level shown (0..--levels - 1)"),
      textParam("voxel_slice", "none",
                std::string("--voxel-view: show the plane ") + kVoxelSliceSyntax +
                    " of the level (nearest voxels) instead of cubes, as <out>_gi_vct_slice.exr/.png",
                sliceProblem),
  };
}

// --levels, auto resolved for --voxels.
unsigned levelsOf(const ParamValues& p) {
  return p.text("levels") == "auto" ? autoLevels(p.count("voxels")) : p.count("levels");
}

bool given(const SettingList& list, const std::string& key) {
  return std::any_of(list.begin(), list.end(), [&](const auto& kv) { return kv.first == key; });
}

// Render's view flags only make sense together; the level must exist.
void checkView(const ParamValues& params, const SettingList& list, const ParamValues& view) {
  if (!given(list, "voxel_view")) {
    if (given(list, "voxel_level")) throw UserError("--voxel-level: only with --voxel-view");
    if (given(list, "voxel_slice")) throw UserError("--voxel-slice: only with --voxel-view (the values shown)");
  }
  checkVoxelLevel(view.count("voxel_level"), levelsOf(params));
}

void fitView(const ParamValues& params, ParamValues& view) {
  const unsigned level = std::min(view.count("voxel_level"), levelsOf(params) - 1);
  view.set("voxel_level", std::to_string(level));
}

GiDescriptor describe() {
  GiDescriptor d;
  d.name = "vct";
  d.summary = "voxel cone tracing added to the frame: one diffuse bounce from a voxel volume";
  d.params = vctParams();
  d.check = [](const ParamValues& p) { checkVctGiSettings(vctSettingsOf(p)); };
  d.make = [](const GiContext& c) -> std::unique_ptr<GiPass> {
    VctGiSettings s = vctSettingsOf(c.params);
    s.bounces = c.bounces;
    return std::make_unique<VctGiPass>(c.cl, s, c.scene.bounds);
  };
  d.max_bounces = kMaxVctBounces;
  d.reference_shadows = [](const ParamValues& p) { return p.text("vct-shadows") == "voxel" ? "ray" : "none"; };
  d.extra_images = {"ao"};
  d.view_name = "voxels";
  d.view_params = viewParams();
  d.check_view = checkView;
  d.fit_view = fitView;
  return d;
}

}  // namespace

const GiDescriptor& giDescriptor() {
  static const GiDescriptor d = describe();
  return d;
}

VctGiSettings vctSettingsOf(const ParamValues& p) {
  VctGiSettings s;
  s.grid.voxels = p.count("voxels");
  s.grid.levels = levelsOf(p);
  s.grid.anisotropic = p.on("anisotropic");
  s.cones = p.count("cones");
  s.aperture_deg = std::stof(p.text("cone-aperture"));
  s.lod_bias = std::stof(p.text("cone-lod-bias"));
  s.gi_scale = std::stof(p.text("gi-scale"));
  s.specular = p.on("specular");
  s.shadows = p.text("vct-shadows");
  s.revoxelize = p.on("revoxelize");
  s.cascades = p.count("vct-cascades");
  s.fold = p.on("vct-fold");
  return s;
}

}  // namespace ml::vct
