#pragma once
// Hashed shading as a LightAssigner (`--technique hashed-forward|hashed-deferred`).
// Contract:
//  - The first assign() builds the structure on the host (HashedStructure,
//    TBB-parallel); later frames with lights_changed update it incrementally
//    (DynamicLightUpdater); other frames do nothing. No per-frame work reads
//    host memory: shading reads only the GL buffers below.
//  - GL buffers (plain GL: only GLSL reads them): binding 1 light index
//    list, 2 header, 3 offset tables, 4 description slots, 5 light-data slots
//    (layout: LinklessOctree.hpp, lookup_hashed.glsl). After an update only
//    the edited slots, offsets, list entries and the list's new tail are uploaded, unless a
//    table was rehashed to a new size (then everything is): hashed::GpuUploadPlan's rules,
//    which the OpenCL copy of the lists (vct::HashedListsCl) applies too.
//  - The geometry mask needs the scene's triangles: setScene() before the
//    first frame (the descriptor's factory passes the run's scene). The
//    descriptor turns it on by default (`--no-geometry-mask` turns it off);
//    HashedConfig, for scene-less use, leaves it off.
//  - hashedTechnique(): the descriptor (names, parameters, the octree-cell
//    debug view, factory) that the registry lists (HashedTechnique.cpp).
#include <epoxy/gl.h>

#include <memory>
#include <string>

#include "host/assign/LightAssigner.hpp"
#include "host/assign/TechniqueDescriptor.hpp"
#include "host/hashed/GpuUploadPlan.hpp"
#include "host/hashed/HashedStructure.hpp"

namespace ml {

class HashedAssigner final : public LightAssigner {
 public:
  explicit HashedAssigner(std::string name, const hashed::HashedConfig& config);
  ~HashedAssigner() override;
  HashedAssigner(const HashedAssigner&) = delete;
  HashedAssigner& operator=(const HashedAssigner&) = delete;

  void assign(const FrameInputs& in) override;
  std::string lookupShader() const override { return "hashed/lookup_hashed.glsl"; }
  void bindForShading(const ShaderProgram& program) const override;
  std::size_t memoryBytes() const override;
  std::vector<std::pair<std::string, double>> stats() const override;
  // "octree-cell": each pixel's octree node (OctreeCellView.hpp); sky only before the first frame.
  std::vector<float> debugViewRgba(const std::string& view, const DebugViewInputs& frame) override;

  void setScene(const Scene* scene) { scene_ = scene; }
  const hashed::HashedStructure* structure() const { return structure_.get(); }
  hashed::HashedConfig& config() { return config_; }
  // Reads the GL buffers back and compares them word for word with the host
  // tables (tests: partial uploads after updates leave no stale word).
  bool gpuMatchesHost(std::string* why = nullptr) const;
  std::size_t lastUploadBytes() const { return upload_bytes_; }

 private:
  struct Buffer {
    GLuint id = 0;
    std::size_t capacity = 0;  // bytes
  };
  void upload(bool rebuilt);  // rebuilt: the structure was built anew (everything is uploaded)

  std::string name_;
  hashed::HashedConfig config_;
  const Scene* scene_ = nullptr;
  std::unique_ptr<hashed::HashedStructure> structure_;
  Buffer list_, header_, offsets_, desc_, data_;
  hashed::GpuUploadPlanner planner_;  // what each upload writes (shared with the OpenCL copy in host/vct)
  double upload_ms_ = 0.0;
  std::size_t upload_bytes_ = 0;
  std::size_t full_rebuilds_ = 0, incremental_updates_ = 0;
};

const TechniqueDescriptor& hashedTechnique();

}  // namespace ml
