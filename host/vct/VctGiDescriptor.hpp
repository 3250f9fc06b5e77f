#pragma once
// Voxel cone tracing as a registered GI pass (gl/GiDescriptor.hpp): its
// settings as ParamSpecs (render's --voxels, --cones, ...; bench's --param
// voxels=...; the viewer's gi_param keys and widgets), the factory making a
// VctGiPass, the reference transport it models (--vct-shadows voxel: the
// reference with --gi-shadows ray), its ambient-occlusion image
// (<out>_gi_vct_ao.png) and its voxel view (--voxel-view, --voxel-level,
// --voxel-slice; the viewer's "voxels" view).
//  - vctSettingsOf(): parameters already checked (host/gi giParams) as the
//    pass's settings; the whole-set check is checkVctGiSettings.
#include "gl/GiDescriptor.hpp"
#include "host/vct/VctGiPass.hpp"

namespace ml::vct {

const GiDescriptor& giDescriptor();
VctGiSettings vctSettingsOf(const ParamValues& params);

}  // namespace ml::vct
