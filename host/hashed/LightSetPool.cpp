#include "host/hashed/LightSetPool.hpp"

#include <algorithm>
#include <stdexcept>

namespace ml::hashed {

std::uint64_t LightSetPool::hashOf(const std::uint32_t* p, std::size_t n) {
  std::uint64_t sum = 0;
  for (std::size_t i = 0; i < n; ++i) sum += elementHash(p[i]);
  return hashOfSum(sum, n);
}

void LightSetPool::rebuildIndex(std::size_t capacity) {
  std::size_t cap = 16;
  while (cap < capacity) cap *= 2;
  index_.assign(cap, 0);
  for (std::uint32_t r = 0; r < recs_.size(); ++r)
    if (recs_[r].capacity > 0 && !recs_[r].own) indexInsert(r);
}

void LightSetPool::indexInsert(std::uint32_t rec) {
  const std::size_t mask = index_.size() - 1;
  for (std::size_t i = recs_[rec].hash & mask;; i = (i + 1) & mask)
    if (index_[i] == 0) {
      index_[i] = rec + 1;
      return;
    }
}

std::uint32_t LightSetPool::acquire(const std::vector<std::uint32_t>& set, std::uint64_t h) {
  if (set.empty()) throw std::logic_error("light set pool: empty sets have no range");
  if (!index_.empty()) {
    const std::size_t mask = index_.size() - 1;
    for (std::size_t i = h & mask; index_[i] != 0; i = (i + 1) & mask) {
      Rec& r = recs_[index_[i] - 1];
      if (r.hash == h && r.count == set.size() && std::equal(set.begin(), set.end(), list_.begin() + r.offset)) {
        if (r.refs == 0) garbage_ -= r.words();  // revived
        ++r.refs;
        return r.offset;
      }
    }
  }
  return append(set, h, false);
}

std::uint32_t LightSetPool::acquireOwn(const std::vector<std::uint32_t>& set) {
  if (set.empty()) throw std::logic_error("light set pool: empty sets have no range");
  return append(set, 0, true);
}

namespace {
constexpr std::uint32_t kPadWord = 0;  // past a range's count: never read
}

std::uint32_t LightSetPool::append(const std::vector<std::uint32_t>& set, std::uint64_t h, bool own) {
  const std::uint32_t cap = own ? ownCapacity(set.size()) : std::uint32_t(set.size());
  if (list_.size() + cap + kOwnHead > 0xFFFFFFF0ull) throw std::length_error("light index list exceeds 2^32 entries");
  if (own) list_.push_back(headOf(std::uint32_t(set.size()), cap));
  const std::uint32_t off = std::uint32_t(list_.size());
  list_.insert(list_.end(), set.begin(), set.end());
  list_.resize(list_.size() + (cap - set.size()), kPadWord);
  std::uint32_t id;
  if (!free_recs_.empty()) {
    id = free_recs_.back();
    free_recs_.pop_back();
  } else {
    id = std::uint32_t(recs_.size());
    recs_.emplace_back();
  }
  recs_[id] = Rec{off, std::uint32_t(set.size()), cap, 1, own, h};
  rec_at_.resize(list_.size());
  rec_at_[off] = id;
  if (own) return off;
  if (2 * (recs_.size() - free_recs_.size()) >= index_.size()) rebuildIndex(4 * recs_.size());
  else indexInsert(id);
  return off;
}

void LightSetPool::release(std::uint32_t offset) {
  Rec& r = recs_.at(rec_at_.at(offset));
  if (r.refs == 0 || r.offset != offset) throw std::logic_error("light set released more often than acquired");
  if (--r.refs == 0) garbage_ += r.words();
}

void LightSetPool::clear() {
  list_.clear();
  recs_.clear();
  free_recs_.clear();
  rec_at_.clear();
  index_.clear();
  garbage_ = 0;
  all_dirty_ = true;
  dirty_spans_.clear();
}

const std::vector<std::uint32_t>& LightSetPool::compact() {
  std::vector<std::uint32_t>& remap = remap_;
  remap.resize(list_.size());
  std::vector<std::uint32_t>& list = spare_list_;
  list.clear();
  // Room for the list to grow back to the compaction threshold without
  // reallocating, with a margin so that the two buffers settle at one size
  // (a fresh allocation's pages fault in on first touch, in the update's
  // sequential part).
  if (list.capacity() < 2 * list_.size()) list.reserve(3 * list_.size());
  std::vector<std::uint32_t>& rec_at = spare_rec_at_;
  rec_at.clear();
  if (rec_at.capacity() < 2 * list_.size()) rec_at.reserve(3 * list_.size());
  // Ranges in record order: reading the records is sequential and each
  // range's copy is independent of the last (walking the list from range to
  // range instead chains two cache misses per range).
  for (std::uint32_t id = 0; id < recs_.size(); ++id) {
    Rec& r = recs_[id];
    if (r.capacity == 0) continue;  // a free record
    if (r.refs == 0) {
      r = Rec{};
      free_recs_.push_back(id);
      continue;
    }
    if (r.own) {  // fresh room to grow
      r.count = countOf(r.offset);
      r.capacity = ownCapacity(r.count);
      list.push_back(headOf(r.count, r.capacity));
    }
    const std::uint32_t n = std::uint32_t(list.size());
    list.insert(list.end(), list_.begin() + std::ptrdiff_t(r.offset), list_.begin() + std::ptrdiff_t(r.offset + r.count));
    if (r.own) list.resize(list.size() + (r.capacity - r.count), kPadWord);
    remap[r.offset] = n;
    r.offset = n;
    rec_at.resize(list.size());  // within the reserve
    rec_at[n] = id;
  }
  list_.swap(list);
  rec_at_.swap(rec_at);
  garbage_ = 0;
  all_dirty_ = true;
  dirty_spans_.clear();
  rebuildIndex(4 * (recs_.size() - free_recs_.size()));
  return remap;
}

LightSetPool::Dirty LightSetPool::takeDirty() {
  Dirty d{all_dirty_, all_dirty_ ? 0 : dirty_from_, {}};
  if (!all_dirty_) d.spans.swap(dirty_spans_);
  dirty_spans_.clear();
  all_dirty_ = false;
  dirty_from_ = list_.size();
  return d;
}

}  // namespace ml::hashed
