#include "host/hashed/HashedAssigner.hpp"

#include <algorithm>

#include "gl/GlCheck.hpp"
#include "gl/GlPassTimer.hpp"
#include "gl/ShaderProgram.hpp"
#include "host/hashed/GpuUploadPlan.hpp"
#include "host/shared/shading_bindings.h"
#include "host/util/Stopwatch.hpp"

namespace ml {

HashedAssigner::HashedAssigner(std::string name, const hashed::HashedConfig& config)
    : name_(std::move(name)), config_(config) {
  hashed::parseNodeSize(config_.node_size);  // a bad --node-size fails before any frame
}

HashedAssigner::~HashedAssigner() {
  for (Buffer* b : {&list_, &header_, &offsets_, &desc_, &data_})
    if (b->id) glDeleteBuffers(1, &b->id);
}

void HashedAssigner::assign(const FrameInputs& in) {
  if (!structure_) structure_ = std::make_unique<hashed::HashedStructure>(config_, scene_);
  if (structure_->built() && !in.lights_changed) return;
  const hashed::UpdateStats& st = structure_->update(in.host_lights);
  if (st.full_rebuild) ++full_rebuilds_;
  else ++incremental_updates_;
  in.host_timings.add(st.full_rebuild ? "hashed-build" : "hashed-update", st.total_ms);
  // GL_TIME_ELAPSED on GPUs (glFinish-bracketed host clock on software GL), not the host clock of the calls.
  GlPassScope timed(in.gl_timer, "hashed-upload");
  upload(st.full_rebuild);
}

bool HashedAssigner::gpuMatchesHost(std::string* why) const {
  if (!structure_ || !structure_->built()) return false;
  const Buffer* buffers[hashed::kGpuArrayCount] = {&header_, &offsets_, &desc_, &data_, &list_};
  const std::string stale = hashed::firstStaleArray(structure_->linkless(), [&](hashed::GpuArray a, std::size_t words) {
    std::vector<std::uint32_t> got(words);
    if (words) glGetNamedBufferSubData(buffers[unsigned(a)]->id, 0, GLsizeiptr(words * 4), got.data());
    return got;
  });
  if (why) *why = stale;
  return stale.empty();
}

// Applies the shared upload plan (GpuUploadPlan.hpp) to the GL buffers.
void HashedAssigner::upload(bool rebuilt) {
  const auto t0 = SteadyClock::now();
  Buffer* buffers[hashed::kGpuArrayCount] = {&header_, &offsets_, &desc_, &data_, &list_};  // GpuArray order
  hashed::GpuArrayWords capacity{};
  for (unsigned i = 0; i < hashed::kGpuArrayCount; ++i) capacity[i] = buffers[i]->capacity / 4;
  const hashed::GpuUploadPlan plan = planner_.plan(structure_->linkless(), rebuilt, capacity);
  for (unsigned i = 0; i < hashed::kGpuArrayCount; ++i) {
    Buffer& b = *buffers[i];
    if (!plan.grow[i]) continue;
    if (b.id) glDeleteBuffers(1, &b.id);
    b.capacity = plan.grow[i] * 4;
    glCreateBuffers(1, &b.id);
    glNamedBufferData(b.id, GLsizeiptr(b.capacity), nullptr, GL_DYNAMIC_DRAW);
  }
  for (const hashed::GpuWrite& w : plan.writes)
    glNamedBufferSubData(buffers[unsigned(w.array)]->id, GLintptr(w.word * 4), GLsizeiptr(w.count * 4), w.src);
  upload_bytes_ = plan.bytes();
  glCheck("uploading the hashed-shading tables");
  upload_ms_ = msSince(t0);
}

void HashedAssigner::bindForShading(const ShaderProgram&) const {
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_HASHED_INDICES, list_.id);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_HASHED_HEADER, header_.id);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_HASHED_OFFSETS, offsets_.id);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_HASHED_DESC, desc_.id);
  glBindBufferBase(GL_SHADER_STORAGE_BUFFER, ML_BINDING_HASHED_DATA, data_.id);
}

std::size_t HashedAssigner::memoryBytes() const {
  return structure_ && structure_->built() ? structure_->linkless().gpuBytes() : 0;
}

std::vector<std::pair<std::string, double>> HashedAssigner::stats() const {
  std::vector<std::pair<std::string, double>> s;
  if (!structure_ || !structure_->built()) return s;
  const auto& lo = structure_->linkless();
  const auto& b = structure_->bounds();
  const auto& bs = structure_->lastBuild();
  s.emplace_back("node size", b.cell_size);
  s.emplace_back("octree depth", b.depth);
  s.emplace_back("start depth", b.start_depth);
  s.emplace_back("layers", lo.layerCount());
  std::uint64_t attempts = 0, rejected = 0;
  std::size_t desc_slots = 0, data_slots = 0, offs = 0;
  for (const auto& l : lo.layerStats()) {
    // Appended, not "L" + to_string(..): GCC 12 -O3 warns falsely (stringop-overflow) on that form here.
    std::string p = "L";
    p += std::to_string(l.depth - b.start_depth);
    p += ' ';
    s.emplace_back(p + "branches", double(l.desc_keys));
    s.emplace_back(p + "filled leaves", double(l.data_keys));
    s.emplace_back(p + "desc table", double(l.desc_slots));
    s.emplace_back(p + "data table", double(l.data_slots));
    s.emplace_back(p + "offset tables", double(l.desc_offsets + l.data_offsets));
    s.emplace_back(p + "bytes", double(l.bytes));
    attempts += (l.desc_attempts ? l.desc_attempts - 1 : 0) + (l.data_attempts ? l.data_attempts - 1 : 0);
    rejected += l.rejected_candidates;
    desc_slots += l.desc_slots;
    data_slots += l.data_slots;
    offs += l.desc_offsets + l.data_offsets;
  }
  s.emplace_back("hash failed attempts", double(attempts));
  s.emplace_back("offsets rejected", double(rejected));
  s.emplace_back("hash table slots", double(desc_slots + data_slots));
  s.emplace_back("offset entries", double(offs));
  s.emplace_back("table bytes", double(lo.tableBytes()));
  s.emplace_back("index list entries", double(lo.pool().list().size()));
  s.emplace_back("unshared entries", double(bs.leaf_index_entries));
  s.emplace_back("scene octree nodes", double(bs.scene_nodes));
  if (structure_->mask()) s.emplace_back("geometry cells", double(bs.mask_cells));
  s.emplace_back("build ms", bs.total_ms);
  s.emplace_back("build bounds ms", bs.bounds_ms);
  if (structure_->mask()) s.emplace_back("build geometry mask ms", bs.mask_ms);
  s.emplace_back("build light octrees ms", bs.light_octrees_ms);
  s.emplace_back("build merge ms", bs.merge_ms);
  s.emplace_back("build normalize ms", bs.normalize_ms);
  s.emplace_back("build hashes ms", bs.hash_ms);
  s.emplace_back("full builds", double(full_rebuilds_));
  if (incremental_updates_) {
    const auto& u = structure_->lastUpdate();
    s.emplace_back("updates", double(incremental_updates_));
    s.emplace_back("last update ms", u.total_ms);
    s.emplace_back("update lights moved", double(u.moved + u.added + u.removed));
    s.emplace_back("update slots in place", double(u.sync.in_place + u.sync.updates + u.sync.erases));
    s.emplace_back("update groups re-offset", double(u.sync.reoffsets));
    s.emplace_back("update tables rehashed", double(u.sync.rehashed_tables));
  }
  s.emplace_back("upload ms", upload_ms_);
  s.emplace_back("upload bytes", double(upload_bytes_));
  return s;
}

}  // namespace ml
