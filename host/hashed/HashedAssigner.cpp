#include "host/hashed/HashedAssigner.hpp"

#include <algorithm>
#include <chrono>

#include "gl/GlCheck.hpp"
#include "gl/GlPassTimer.hpp"
#include "gl/ShaderProgram.hpp"
#include "host/shared/shading_bindings.h"

namespace ml {
namespace {

using Clock = std::chrono::steady_clock;
double msSince(Clock::time_point t) { return std::chrono::duration<double, std::milli>(Clock::now() - t).count(); }

using Span = hashed::LightSetPool::Span;

// Uploads the given spans [first, end) of elements of `words` (elem_words
// per element) at element base `base`, one call per run of nearby spans:
// `words` is the whole current buffer, so the elements in a gap may go
// along, and a gap of up to 256 bytes costs less than another call: moved
// lights' octant masks are rewritten a few words apart (default scene, 10%
// moving, llvmpipe: 0.79 ms for 537 KB against 1.12 ms for 142 KB in exact
// runs).
std::size_t uploadSpans(GLuint buffer, std::size_t base, unsigned elem_words, const std::vector<std::uint32_t>& words,
                        std::vector<Span> spans) {
  std::sort(spans.begin(), spans.end(), [](const Span& a, const Span& b) { return a.first < b.first; });
  const std::uint32_t max_gap = std::max(1u, 64u / elem_words);  // elements
  std::size_t bytes = 0;
  for (std::size_t i = 0; i < spans.size();) {
    std::uint32_t end = spans[i].end;
    std::size_t j = i + 1;
    for (; j < spans.size() && spans[j].first < end + max_gap; ++j) end = std::max(end, spans[j].end);
    const std::size_t first = spans[i].first, len = std::size_t(end - spans[i].first) * elem_words * 4;
    glNamedBufferSubData(buffer, GLintptr((base + first) * elem_words * 4), GLsizeiptr(len),
                         words.data() + first * elem_words);
    bytes += len;
    i = j;
  }
  return bytes;
}

// The same for single elements (the hash tables' dirty slots and offsets).
std::size_t uploadRuns(GLuint buffer, std::size_t base, unsigned elem_words, const std::vector<std::uint32_t>& words,
                       const std::vector<std::uint32_t>& idx) {
  std::vector<Span> spans(idx.size());
  for (std::size_t i = 0; i < idx.size(); ++i) spans[i] = {idx[i], idx[i] + 1};
  return uploadSpans(buffer, base, elem_words, words, std::move(spans));
}

}  // namespace

HashedAssigner::HashedAssigner(std::string name, const hashed::HashedConfig& config)
    : name_(std::move(name)), config_(config) {
  hashed::parseNodeSize(config_.node_size);  // a bad --node-size fails before any frame
}

HashedAssigner::~HashedAssigner() {
  for (Buffer* b : {&list_, &header_, &offsets_, &desc_, &data_})
    if (b->id) glDeleteBuffers(1, &b->id);
}

void HashedAssigner::ensure(Buffer& b, std::size_t bytes, bool keep_headroom) {
  bytes = std::max<std::size_t>(bytes, 16);
  if (b.id && bytes <= b.capacity) return;
  if (b.id) glDeleteBuffers(1, &b.id);
  b.capacity = keep_headroom ? bytes + bytes / 2 : bytes;
  glCreateBuffers(1, &b.id);
  glNamedBufferData(b.id, GLsizeiptr(b.capacity), nullptr, GL_DYNAMIC_DRAW);
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
  const hashed::LinklessOctree::GpuImage im = structure_->linkless().packGpuImage();
  const auto& list = structure_->linkless().pool().list();
  auto same = [&](const Buffer& b, const std::vector<std::uint32_t>& want, const char* what) {
    std::vector<std::uint32_t> got(want.size());
    if (!want.empty()) glGetNamedBufferSubData(b.id, 0, GLsizeiptr(want.size() * 4), got.data());
    if (got == want) return true;
    if (why) *why = what;
    return false;
  };
  return same(header_, im.header, "header") && same(offsets_, im.offsets, "offset tables") &&
         same(desc_, im.desc, "description tables") && same(data_, im.data, "data tables") &&
         same(list_, list, "light index list");
}

void HashedAssigner::uploadAll() {
  hashed::LinklessOctree& lo = structure_->linkless();
  upload_bytes_ = 0;
  const hashed::LinklessOctree::GpuImage im = structure_->linkless().packGpuImage();
  for (unsigned i = 0; i < lo.layerCount(); ++i) {
    lo.takeEdits(i, false);
    lo.takeEdits(i, true);
  }
  for (auto [buf, v] : {std::pair{&header_, &im.header}, {&offsets_, &im.offsets}, {&desc_, &im.desc}, {&data_, &im.data}}) {
    ensure(*buf, v->size() * 4, false);
    if (!v->empty()) glNamedBufferSubData(buf->id, 0, GLsizeiptr(v->size() * 4), v->data());
    upload_bytes_ += v->size() * 4;
  }
  lo.pool().takeDirty();
  uploadWholeList();
  uploaded_layout_ = lo.layoutVersion();
}

void HashedAssigner::uploadWholeList() {
  const auto& list = structure_->linkless().pool().list();
  ensure(list_, list.size() * 4, true);
  if (!list.empty()) glNamedBufferSubData(list_.id, 0, GLsizeiptr(list.size() * 4), list.data());
  upload_bytes_ += list.size() * 4;
}

// One table's edits since the last upload: the whole table after a rebuild
// or remap, else its edited slots and offsets.
template <class Hash>
void HashedAssigner::uploadTable(const Hash& h, const hashed::TableEdits& d, GLuint slots_buf, std::size_t slot_base,
                                 std::size_t offset_base) {
  constexpr unsigned kw = Hash::kWords;
  if (d.all) {
    glNamedBufferSubData(slots_buf, GLintptr(slot_base * kw * 4), GLsizeiptr(h.tableWords().size() * 4),
                         h.tableWords().data());
    glNamedBufferSubData(offsets_.id, GLintptr(offset_base * 4), GLsizeiptr(h.offsetWords().size() * 4),
                         h.offsetWords().data());
    upload_bytes_ += h.bytes();
    return;
  }
  upload_bytes_ += uploadRuns(slots_buf, slot_base, kw, h.tableWords(), d.slots);
  upload_bytes_ += uploadRuns(offsets_.id, offset_base, 1, h.offsetWords(), d.offsets);
}

void HashedAssigner::upload(bool rebuilt) {
  const auto t0 = Clock::now();
  hashed::LinklessOctree& lo = structure_->linkless();
  // A full rebuild makes a new octree whose layout version starts over, so
  // it can equal the uploaded one while every table changed size.
  if (rebuilt || lo.layoutVersion() != uploaded_layout_) {
    uploadAll();
  } else {
    upload_bytes_ = 0;
    for (unsigned i = 0; i < lo.layerCount(); ++i) {
      uploadTable(lo.desc(i), lo.takeEdits(i, false), desc_.id, lo.descSlotBase(i), lo.offsetBase(i, false));
      uploadTable(lo.data(i), lo.takeEdits(i, true), data_.id, lo.dataSlotBase(i), lo.offsetBase(i, true));
    }
    const auto& list = lo.pool().list();
    auto d = lo.pool().takeDirty();
    const std::size_t from = d.all ? 0 : std::min(d.from, list.size());
    if (list.size() * 4 > list_.capacity) {
      uploadWholeList();
    } else {
      if (from < list.size()) {
        glNamedBufferSubData(list_.id, GLintptr(from * 4), GLsizeiptr((list.size() - from) * 4), list.data() + from);
        upload_bytes_ += (list.size() - from) * 4;
      }
      upload_bytes_ += uploadSpans(list_.id, 0, 1, list, std::move(d.spans));  // own ranges rewritten in place
    }
  }
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
    const std::string p = "L" + std::to_string(l.depth - b.start_depth) + " ";
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
