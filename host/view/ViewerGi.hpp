#pragma once
// The viewer's global illumination: none or voxel cone tracing (the frame's
// GiPass, host/vct/VctGiPass), its settings set by key through the one VCT
// settings table (host/vct/VctSettingsTable.hpp, as `render --gi vct`'s flags
// are), and its two view modes: the indirect light (as render's
// <out>_gi_vct.png) and the voxel volume as cubes (a view kind and a level, as
// render's --voxel-view / --voxel-level), or one plane of it (render's
// --voxel-slice). A refused value (unknown key, bad
// text, a setting checkVctGiSettings rejects, a pass that cannot be built)
// throws UserError and leaves the last working state in place. When --levels
// drops below the shown voxel level, the voxel view shows the coarsest level.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "host/cl/ClRuntime.hpp"
#include "host/scene/Camera.hpp"
#include "host/scene/Scene.hpp"
#include "host/vct/VctGiPass.hpp"
#include "host/vct/VoxelView.hpp"

namespace ml {

class ViewerGi {
 public:
  ViewerGi(ClRuntime& cl, const Aabb& scene_bounds);
  ~ViewerGi();

  void setMode(const std::string& mode);  // none | vct
  void setParam(const std::string& key, const std::string& value);
  void setVoxelView(const std::string& kind);  // albedo | radiance | opacity
  void setVoxelLevel(unsigned level);          // below the levels setting
  void setVoxelSlice(const std::string& slice);  // x|y|z[:position] (VoxelSlice.hpp), or none: cubes

  bool on() const { return pass_ != nullptr; }
  const std::string& mode() const { return mode_; }
  const vct::VctGiSettings& settings() const { return settings_; }
  vct::VoxelViewKind voxelView() const { return voxel_kind_; }
  unsigned voxelLevel() const { return voxel_level_; }
  const std::optional<vct::VoxelSlice>& voxelSlice() const { return voxel_slice_; }
  GiPass* pass() { return pass_.get(); }  // null when none

  // Of the last frame rendered with pass(): displayed RGBA, rows bottom-up.
  std::vector<float> indirectImage() const;
  std::vector<float> voxelImage(const Camera& camera, unsigned width, unsigned height);

 private:
  void rebuild(const vct::VctGiSettings& s);

  ClRuntime& cl_;
  Aabb bounds_;
  std::string mode_ = "none";
  vct::VctGiSettings settings_;
  std::unique_ptr<vct::VctGiPass> pass_;
  std::unique_ptr<vct::VoxelViewPass> voxel_view_;
  vct::VoxelViewKind voxel_kind_ = vct::VoxelViewKind::Radiance;
  unsigned voxel_level_ = 0;
  std::optional<vct::VoxelSlice> voxel_slice_;
};

}  // namespace ml
