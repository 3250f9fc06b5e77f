// What VctGiPass reports to front ends (gl/GiPass.hpp: stats, extraImages,
// view): render's printout and stats JSON fields, the ambient-occlusion
// image, and the voxel view, so no front end needs the pass's type.
#include <cstdio>

#include "host/vct/VctGiPass.hpp"
#include "host/vct/VoxelSlice.hpp"

namespace ml::vct {
namespace {

std::string printed(const char* format, auto... args) {
  char buf[512];
  std::snprintf(buf, sizeof buf, format, args...);
  return buf;
}

nlohmann::ordered_json settingsJson(const VctGiSettings& v) {
  return {{"voxels", v.grid.voxels},  {"levels", v.grid.levels}, {"anisotropic", v.grid.anisotropic},
          {"cones", v.cones},         {"cone_aperture", v.aperture_deg}, {"cone_lod_bias", v.lod_bias}, {"gi_scale", v.gi_scale},
          {"specular", v.specular},   {"vct_shadows", v.shadows}, {"revoxelize", v.revoxelize},
          {"bounces", v.bounces}, {"cascades", v.cascades}};
}

// The hashed lists' builds and uploads (all 0 with brute-force injection).
void addLists(const VctPipeline& p, GiStats& st) {
  std::size_t builds = 0, updates = 0, update_bytes = 0, image_bytes = 0;
  if (p.listBuilds() > 0) {
    builds = p.listBuilds();
    updates = p.listUpdates();
    update_bytes = updates ? p.listUpdateBytes() / updates : 0;
    image_bytes = p.lists().linkless().gpuBytes();
    st.lines.push_back(printed("vct lists: %zu builds, %zu incremental updates uploading %zu bytes each (mean) of %zu",
                               builds, updates, update_bytes, image_bytes));
  }
  st.json["vct_list_builds"] = builds;
  st.json["vct_list_updates"] = updates;
  st.json["vct_list_update_bytes"] = update_bytes;  // uploaded per incremental update, mean
  st.json["vct_list_image_bytes"] = image_bytes;
}

}  // namespace

GiStats VctGiPass::stats() const {
  GiStats st;
  st.data_bytes = pipeline_.bytes();
  st.lines.push_back(printed("gi vct: %zu voxelizations in %zu updates%s; %zu frames reused the volume (unchanged "
                             "lights)",
                             pipeline_.voxelizations(), pipeline_.updates(),
                             s_.revoxelize ? " (--revoxelize: every frame)" : " (static geometry: the first frame only)",
                             reuses_));
  st.json["gi_vct"] = settingsJson(s_);
  st.json["voxel_bytes"] = st.data_bytes;
  st.json["vct_updates"] = pipeline_.updates();
  st.json["vct_voxelizations"] = pipeline_.voxelizations();
  st.json["vct_reused"] = reuses_;  // frames that reused the volume: their vct-inject etc. count 0 ms in the medians
  st.json["vct_scrolls"] = scrolls_;
  st.json["vct_scrolled_voxels"] = scrolled_voxels_;
  if (s_.cascades > 1)
    st.lines.push_back(printed("vct cascade: %u levels; %zu camera moves scrolled a level, %zu level-0 voxels "
                               "voxelized and injected again for them",
                               s_.cascades, scrolls_, scrolled_voxels_));
  addLists(pipeline_, st);
  const std::string bounces = s_.bounces == 1 ? "one bounce" : "two bounces (the second gathered per voxel)";
  st.json["gi_transport"] = s_.shadows == "voxel"
                                ? bounces + ", diffuse; visibility of the lights in the injected direct light "
                                            "through level-0 voxel opacity (--vct-shadows voxel)"
                                : bounces + ", diffuse; no visibility in the injected direct light";
  return st;
}

std::vector<GiImage> VctGiPass::extraImages() const {
  std::vector<float> px;
  for (float v : ambientOcclusion()) px.insert(px.end(), {v, v, v, 1.0f});
  return {{"ao", std::move(px)}};
}

GiViewImage VctGiPass::view(const ParamValues& v, const GiViewInputs& in) {
  const VoxelViewKind kind = parseVoxelView(v.text("voxel_view"));
  const unsigned level = v.count("voxel_level");
  const std::string slice_text = v.text("voxel_slice");
  if (!voxel_view_) voxel_view_ = std::make_unique<VoxelViewPass>();
  GiViewImage out;
  if (slice_text == "none") {
    out.suffix = "voxels";
    out.linear = voxel_view_->render(pipeline_.volume(), kind, level, {in.view, in.proj, in.width, in.height});
  } else {
    out.suffix = "slice";
    out.linear = voxel_view_->renderSlice(pipeline_.volume(), kind, level, parseVoxelSlice(slice_text, "--voxel-slice"),
                                          in.width, in.height);
  }
  out.display = voxelViewDisplay(out.linear, kind);
  out.line = printed("voxel view: %s of level %u (%u voxels per axis)%s%s", voxelViewName(kind), level,
                     s_.grid.voxels >> level, slice_text == "none" ? ", cubes" : ", slice ",
                     slice_text == "none" ? "" : slice_text.c_str());
  return out;
}

}  // namespace ml::vct
