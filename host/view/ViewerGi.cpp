#include "host/view/ViewerGi.hpp"

#include <algorithm>

#include "host/util/Error.hpp"
#include "host/util/GiToneMap.hpp"
#include "host/vct/VctSettingsTable.hpp"

namespace ml {

ViewerGi::ViewerGi(ClRuntime& cl, const Aabb& scene_bounds) : cl_(cl), bounds_(scene_bounds) {}

ViewerGi::~ViewerGi() = default;

// The new pass is built before the old one goes: if it fails, nothing changed.
void ViewerGi::rebuild(const vct::VctGiSettings& s) {
  auto pass = std::make_unique<vct::VctGiPass>(cl_, s, bounds_);
  pass_ = std::move(pass);
  settings_ = s;
  voxel_level_ = std::min(voxel_level_, s.grid.levels - 1);
}

void ViewerGi::setMode(const std::string& mode) {
  if (mode == "none") {
    pass_.reset();
  } else if (mode == "vct") {
    if (!pass_) rebuild(settings_);
  } else {
    throw UserError("gi: expected none|vct, got '" + mode + "'");
  }
  mode_ = mode;
}

void ViewerGi::setParam(const std::string& key, const std::string& value) {
  const vct::VctGiSettings next = vct::withVctSetting(settings_, key, value);
  if (pass_)
    rebuild(next);
  else
    settings_ = next;
  voxel_level_ = std::min(voxel_level_, settings_.grid.levels - 1);
}

void ViewerGi::setVoxelView(const std::string& kind) { voxel_kind_ = vct::parseVoxelView(kind); }

void ViewerGi::setVoxelLevel(unsigned level) {
  vct::checkVoxelLevel(level, settings_.grid.levels);
  voxel_level_ = level;
}

void ViewerGi::setVoxelSlice(const std::string& slice) {
  if (slice == "none")
    voxel_slice_.reset();
  else
    voxel_slice_ = vct::parseVoxelSlice(slice, "--voxel-slice");
}

std::vector<float> ViewerGi::indirectImage() const {
  if (!pass_) throw UserError("view: the indirect light needs gi vct");
  return giToneMapped(pass_->indirectRgba());
}

std::vector<float> ViewerGi::voxelImage(const Camera& camera, unsigned width, unsigned height) {
  if (!pass_) throw UserError("view: the voxels need gi vct");
  if (!voxel_view_) voxel_view_ = std::make_unique<vct::VoxelViewPass>();
  const vct::VoxelVolume& volume = pass_->pipeline().volume();
  if (voxel_slice_)
    return vct::voxelViewDisplay(
        voxel_view_->renderSlice(volume, voxel_kind_, voxel_level_, *voxel_slice_, width, height), voxel_kind_);
  const vct::VoxelViewCamera cam{camera.view(), camera.projection(float(width) / float(height)), width, height};
  return vct::voxelViewDisplay(voxel_view_->render(volume, voxel_kind_, voxel_level_, cam), voxel_kind_);
}

}  // namespace ml
