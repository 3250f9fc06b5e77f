#pragma once
// Traced indirect references kept on disk, so a sweep over GI settings (or a
// rerun) traces each reference once:
//
//   IndirectImage ref = cachedIndirectReference(scene, lights, camera, w, h, options);
//
// The key is a 64-bit FNV-1a hash of everything that changes the image: the
// tracer's version (kIndirectTracerVersion, raised with any change to
// IndirectReference.cpp's output), the scene's vertices, indices, batches,
// materials and texture bytes, the lights, the camera, the size, the samples,
// the seed, the shadow rays and the bounces. A file is used only when it reads back whole
// with the same key, size and magic; otherwise the reference is traced and the
// file written again (a temporary file renamed into place, so a reader never
// sees half a file). Folder: $MANYLIGHTS_CACHE_DIR/gi-reference, else
// $XDG_CACHE_HOME/manylights/gi-reference, else ~/.cache/manylights/gi-reference;
// MANYLIGHTS_GI_REFERENCE_CACHE=0 traces every time. A folder that cannot be
// written is one warning and no cache, never an error.
#include <cstdint>
#include <string>
#include <vector>

#include "host/reference/IndirectReference.hpp"

namespace ml {

inline constexpr std::uint32_t kIndirectTracerVersion = 2;  // 2: two replicas per pixel (noise estimate)

// The hash the cache keys a reference on (exposed for tests).
std::uint64_t indirectReferenceKey(const Scene& scene, const std::vector<gpu::PointLight>& lights,
                                   const Camera& camera, unsigned width, unsigned height,
                                   const IndirectOptions& options);

struct CachedReference {
  IndirectImage image;
  bool from_cache = false;
  std::string file;  // the cache file, empty when the cache is off
};

CachedReference cachedIndirectReference(const Scene& scene, const std::vector<gpu::PointLight>& lights,
                                        const Camera& camera, unsigned width, unsigned height,
                                        const IndirectOptions& options);

}  // namespace ml
