#pragma once
// How often a global-illumination pass (gl/GiPass.hpp) did its per-frame scene
// work (e.g. voxel cone tracing's inject, mips and textures) and how often it
// reused the last frame's because nothing it reads had changed. Plain data,
// so that bench records (host/run/RunRecords.hpp) carry it without GL.
#include <cstddef>

namespace ml {

struct GiUpdateCounts {
  std::size_t ran = 0, reused = 0;
};

}  // namespace ml
