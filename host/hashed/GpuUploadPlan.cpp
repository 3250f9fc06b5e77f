#include "host/hashed/GpuUploadPlan.hpp"

#include <algorithm>

namespace ml::hashed {
namespace {

using Span = LightSetPool::Span;

constexpr std::size_t kMaxGapWords = 64;  // 256 bytes: see the header
constexpr std::size_t kMinBufferWords = 4;

std::size_t index(GpuArray a) { return static_cast<std::size_t>(a); }

std::size_t allocationWords(GpuArray a, std::size_t need) {
  return std::max(kMinBufferWords, a == GpuArray::List ? need + need / 2 : need);
}

bool mustGrow(GpuArray a, std::size_t need, const GpuArrayWords& capacity) {
  return capacity[index(a)] == 0 || need > capacity[index(a)];
}

// All of `words` at word `at` of array a.
void writeAll(GpuArray a, std::size_t at, const std::vector<std::uint32_t>& words, GpuUploadPlan& p) {
  if (!words.empty()) p.writes.push_back({a, at, words.size(), words.data()});
}

// Elements [first, end) of `words` (elem_words each) at element base `base`
// of array a, one write per run of spans less than kMaxGapWords apart.
void writeSpans(GpuArray a, std::size_t base, unsigned elem_words, const std::vector<std::uint32_t>& words,
                std::vector<Span> spans, GpuUploadPlan& p) {
  std::sort(spans.begin(), spans.end(), [](const Span& x, const Span& y) { return x.first < y.first; });
  const std::uint32_t max_gap = std::uint32_t(std::max<std::size_t>(1, kMaxGapWords / elem_words));  // elements
  for (std::size_t i = 0; i < spans.size();) {
    std::uint32_t end = spans[i].end;
    std::size_t j = i + 1;
    for (; j < spans.size() && spans[j].first < end + max_gap; ++j) end = std::max(end, spans[j].end);
    const std::size_t first = spans[i].first;
    p.writes.push_back({a, (base + first) * elem_words, (end - first) * elem_words, words.data() + first * elem_words});
    i = j;
  }
}

// The same for single elements (a table's edited slots or offset entries).
void writeElements(GpuArray a, std::size_t base, unsigned elem_words, const std::vector<std::uint32_t>& words,
                   const std::vector<std::uint32_t>& idx, GpuUploadPlan& p) {
  std::vector<Span> spans(idx.size());
  for (std::size_t i = 0; i < idx.size(); ++i) spans[i] = {idx[i], idx[i] + 1};
  writeSpans(a, base, elem_words, words, std::move(spans), p);
}

// One table's edits since the last plan: all of it after a rehash or remap,
// else its edited slots and offsets.
template <class Hash>
void writeTable(const Hash& h, const TableEdits& d, GpuArray slots, std::size_t slot_base, std::size_t offset_base,
                GpuUploadPlan& p) {
  constexpr unsigned kw = Hash::kWords;
  if (d.all) {
    writeAll(slots, slot_base * kw, h.tableWords(), p);
    writeAll(GpuArray::Offsets, offset_base, h.offsetWords(), p);
    return;
  }
  writeElements(slots, slot_base, kw, h.tableWords(), d.slots, p);
  writeElements(GpuArray::Offsets, offset_base, 1, h.offsetWords(), d.offsets, p);
}

}  // namespace

const char* gpuArrayName(GpuArray a) {
  switch (a) {
    case GpuArray::Header: return "header";
    case GpuArray::Offsets: return "offset tables";
    case GpuArray::Desc: return "description tables";
    case GpuArray::Data: return "data tables";
    case GpuArray::List: return "light index list";
  }
  return "?";
}

std::size_t GpuUploadPlan::bytes() const {
  std::size_t words = 0;
  for (const GpuWrite& w : writes) words += w.count;
  return words * 4;
}

GpuUploadPlan GpuUploadPlanner::plan(LinklessOctree& lo, bool rebuilt, const GpuArrayWords& capacity) {
  GpuUploadPlan p;
  const GpuArrayWords tables{lo.headerWords().size(), lo.offsetWordCount(), lo.descSlotCount() * DescHash::kWords,
                             lo.dataSlotCount() * DataHash::kWords, 0};
  bool outgrown = false;
  for (GpuArray a : {GpuArray::Header, GpuArray::Offsets, GpuArray::Desc, GpuArray::Data})
    outgrown |= mustGrow(a, tables[index(a)], capacity);
  if (rebuilt || lo.layoutVersion() != uploaded_layout_ || outgrown) planAll(lo, capacity, p);
  else planEdits(lo, capacity, p);
  uploaded_layout_ = lo.layoutVersion();
  return p;
}

void GpuUploadPlanner::planAll(LinklessOctree& lo, const GpuArrayWords& capacity, GpuUploadPlan& p) {
  p.full = true;
  p.image = lo.packGpuImage();
  for (unsigned i = 0; i < lo.layerCount(); ++i) {
    lo.takeEdits(i, false);
    lo.takeEdits(i, true);
  }
  lo.pool().takeDirty();
  const std::vector<std::uint32_t>* arrays[kGpuArrayCount] = {&p.image.header, &p.image.offsets, &p.image.desc,
                                                              &p.image.data, &lo.pool().list()};
  for (unsigned i = 0; i < kGpuArrayCount; ++i) {
    const GpuArray a = static_cast<GpuArray>(i);
    if (mustGrow(a, arrays[i]->size(), capacity)) p.grow[i] = allocationWords(a, arrays[i]->size());
    writeAll(a, 0, *arrays[i], p);
  }
}

void GpuUploadPlanner::planEdits(LinklessOctree& lo, const GpuArrayWords& capacity, GpuUploadPlan& p) {
  for (unsigned i = 0; i < lo.layerCount(); ++i) {
    writeTable(lo.desc(i), lo.takeEdits(i, false), GpuArray::Desc, lo.descSlotBase(i), lo.offsetBase(i, false), p);
    writeTable(lo.data(i), lo.takeEdits(i, true), GpuArray::Data, lo.dataSlotBase(i), lo.offsetBase(i, true), p);
  }
  const std::vector<std::uint32_t>& list = lo.pool().list();
  LightSetPool::Dirty d = lo.pool().takeDirty();
  if (mustGrow(GpuArray::List, list.size(), capacity)) {
    p.grow[index(GpuArray::List)] = allocationWords(GpuArray::List, list.size());
    writeAll(GpuArray::List, 0, list, p);
    return;
  }
  const std::size_t from = d.all ? 0 : std::min(d.from, list.size());
  if (from < list.size()) p.writes.push_back({GpuArray::List, from, list.size() - from, list.data() + from});
  if (!d.all) writeSpans(GpuArray::List, 0, 1, list, std::move(d.spans), p);  // own ranges rewritten in place
}

std::string firstStaleArray(const LinklessOctree& lo, const GpuReadBack& read) {
  const LinklessOctree::GpuImage im = lo.packGpuImage();
  const std::vector<std::uint32_t>* want[kGpuArrayCount] = {&im.header, &im.offsets, &im.desc, &im.data,
                                                            &lo.pool().list()};
  for (unsigned i = 0; i < kGpuArrayCount; ++i) {
    const GpuArray a = static_cast<GpuArray>(i);
    if (read(a, want[i]->size()) != *want[i]) return gpuArrayName(a);
  }
  return "";
}

}  // namespace ml::hashed
