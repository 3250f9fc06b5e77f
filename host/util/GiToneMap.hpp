#pragma once
// The tone-map of the GI images (render's <out>_gi_*.png, the voxel radiance
// view, the viewer's indirect-light mode): c / (c + key) per channel, key the
// mean luminance of the covered pixels (alpha > 0; 1 when none or all black),
// so the image is legible whatever the lights' intensity. Alpha becomes 1.
#include <vector>

namespace ml {

std::vector<float> giToneMapped(const std::vector<float>& rgba);

}  // namespace ml
