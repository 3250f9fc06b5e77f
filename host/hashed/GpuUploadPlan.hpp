#pragma once
// What an uploader writes to bring its device copy of a LinklessOctree's GPU
// image (header, offset tables, desc slots, data slots, light index list) up
// to date, whatever the API: GL buffers (HashedAssigner) and OpenCL buffers
// (vct::HashedListsCl) apply the same plan, so the rules live here once.
// Contract:
//  - GpuUploadPlanner::plan() takes the octree's edit records
//    (LinklessOctree::takeEdits, LightSetPool::takeDirty): one planner per
//    device copy, and one device copy per structure.
//  - Everything, from a packed image, after a rebuild (a new octree, whose
//    layout version starts over), a layout change (a table resized: every
//    base moved) or the first plan. Else per table its edited slots and
//    offset entries (all of the table after a rehash or remap in place), the
//    list's tail appended since the last plan and its spans rewritten in
//    place; all of the list after a compaction or when it outgrew its buffer.
//  - Buffers grow and never truncate: grow[a] > 0 asks the writer to
//    reallocate array a to that many words (its content is lost) before the
//    writes, and a grown array is then written whole. The list grows with
//    headroom (appends every update); tables grow exactly (they change size
//    only with the layout). A buffer is never empty (at least 4 words).
//  - Nearby runs go as one write, gap included (the source holds the gap's
//    current words too): a gap of up to 256 bytes costs less than another
//    call (moved lights' octant masks are rewritten a few words apart;
//    default scene, 10% moving, llvmpipe: 0.79 ms for 537 KB against 1.12 ms
//    for 142 KB in exact runs).
//  - A write's `src` points into the structure or into the plan's `image`:
//    valid while neither changes (plans move, never copy).
//  - firstStaleArray(): an uploaded copy read back against the host image
//    word for word (tests: partial uploads leave no stale word).
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "host/hashed/LinklessOctree.hpp"

namespace ml::hashed {

enum class GpuArray : unsigned { Header, Offsets, Desc, Data, List };
inline constexpr unsigned kGpuArrayCount = 5;
using GpuArrayWords = std::array<std::size_t, kGpuArrayCount>;  // per GpuArray, in 32-bit words
const char* gpuArrayName(GpuArray a);

struct GpuWrite {
  GpuArray array;
  std::size_t word, count;  // destination offset and length, in words
  const std::uint32_t* src;
};

struct GpuUploadPlan {
  GpuUploadPlan() = default;
  GpuUploadPlan(GpuUploadPlan&&) = default;
  GpuUploadPlan& operator=(GpuUploadPlan&&) = default;
  GpuUploadPlan(const GpuUploadPlan&) = delete;
  GpuUploadPlan& operator=(const GpuUploadPlan&) = delete;

  bool full = false;
  GpuArrayWords grow{};  // 0: keep the buffer
  std::vector<GpuWrite> writes;
  LinklessOctree::GpuImage image;  // a full plan's source (empty otherwise)
  std::size_t bytes() const;
};

class GpuUploadPlanner {
 public:
  // `capacity`: each array's device buffer now, in words (0: none yet).
  GpuUploadPlan plan(LinklessOctree& lo, bool rebuilt, const GpuArrayWords& capacity);

 private:
  void planAll(LinklessOctree& lo, const GpuArrayWords& capacity, GpuUploadPlan& p);
  void planEdits(LinklessOctree& lo, const GpuArrayWords& capacity, GpuUploadPlan& p);
  std::uint64_t uploaded_layout_ = ~0ull;
};

// Reads `words` words of array a back from the device copy.
using GpuReadBack = std::function<std::vector<std::uint32_t>(GpuArray a, std::size_t words)>;
// The name of the first array whose copy differs from the octree's image, "" if none.
std::string firstStaleArray(const LinklessOctree& lo, const GpuReadBack& read);

}  // namespace ml::hashed
