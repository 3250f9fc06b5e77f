#include "host/vct/VoxelVolume.hpp"

#include <stdexcept>

namespace ml::vct {

VoxelVolume::VoxelVolume(ClRuntime& rt, const VoxelGridSettings& settings, const gpu::VoxelGridParams& params)
    : settings_(settings) {
  checkVoxelGrid(settings_);
  setParams(params);
  accum_ = std::make_unique<SharedBuffer>(rt, accumBytes(settings_), "vct accum");
  radiance_ = std::make_unique<SharedBuffer>(rt, radianceBytes(settings_), "vct radiance");
  if (settings_.anisotropic)
    aniso_ = std::make_unique<SharedBuffer>(rt, anisotropicBytes(settings_), "vct anisotropic");
}

void VoxelVolume::setParams(const gpu::VoxelGridParams& p) {
  if (p.edge != settings_.voxels || p.levels != settings_.levels)
    throw std::invalid_argument("VoxelVolume::setParams: edge and levels must match the volume's settings");
  params_ = p;
}

}  // namespace ml::vct
