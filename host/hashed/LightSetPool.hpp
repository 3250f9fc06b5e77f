#pragma once
// The light index list (thesis Fig. 7.8) with each distinct light set stored
// once: filled leaves with equal sets (common: siblings that could not merge
// because of a third sibling) share one range. Contract:
//  - acquire(set) returns the offset of an identical range, appending the set
//    if it is new, and takes a reference; release(offset) drops one. A range
//    without references is garbage (it is revived if its set comes back)
//    until compact() repacks the live ranges and returns, per old offset, the
//    new one, which callers apply to every data entry. Sets are index list
//    entries in light order, so equal sets are equal ranges.
//  - acquireOwn(set) appends a range that is never shared (not indexed),
//    with room to grow (ownCapacity()), so that its owner may rewrite() its
//    words and resizeOwn() it in place: deepest leaves' entries, whose octant
//    masks change when a light moves and whose sets mostly change by a light
//    or two. Words past a range's count are unspecified. The word before
//    an own range (its head, never read by lookups) holds its count and
//    capacity, 16 bits each: an update reads and writes them beside the
//    range's words, where a side table cost two more cache misses per leaf.
//    Ranges of 65535 words or more keep them in the side table instead
//    (head kBigHead). resizeOwn() and rewrite() of distinct own ranges may
//    run in parallel.
//  - Appends, rewrites and compactions are recorded for partial uploads.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "host/util/SplitMix64.hpp"

namespace ml::hashed {

class LightSetPool {
 public:
  // `hash`: the set's hashOf() (callers compute it in parallel).
  std::uint32_t acquire(const std::vector<std::uint32_t>& set, std::uint64_t hash);
  std::uint32_t acquireOwn(const std::vector<std::uint32_t>& set);
  static std::uint32_t ownCapacity(std::size_t n) { return std::uint32_t(n + std::max<std::size_t>(2, n / 8)); }
  // For a range from acquireOwn().
  std::uint32_t countOf(std::uint32_t offset) const {
    const std::uint32_t h = list_[offset - 1];
    return h != kBigHead ? h & 0xFFFFu : recs_[rec_at_[offset]].count;
  }
  std::uint32_t capacityOf(std::uint32_t offset) const {
    const std::uint32_t h = list_[offset - 1];
    return h != kBigHead ? h >> 16 : recs_[rec_at_[offset]].capacity;
  }
  // Returns the word it rewrote (the head), for noteRewritten().
  std::uint32_t resizeOwn(std::uint32_t offset, std::uint32_t count) {
    std::uint32_t& h = list_[offset - 1];
    if (h != kBigHead) h = (h & 0xFFFF0000u) | count;
    else recs_[rec_at_[offset]].count = count;
    return offset - 1;
  }
  static constexpr std::uint32_t kBigHead = 0xFFFFFFFFu;
  // Overwrites entry `at` of a range from acquireOwn().
  void rewrite(std::size_t at, std::uint32_t word) {
    list_[at] = word;
    noteRewritten(at, at + 1);
  }
  // rewrite() in two halves, for tasks rewriting distinct own ranges in
  // parallel: each writes its words, then one thread notes them all, as
  // spans [first, end) (an in-place edit shifts every word after it).
  std::uint32_t* ownWords(std::uint32_t offset) { return list_.data() + offset; }
  void noteRewritten(std::size_t first, std::size_t end) {
    if (!all_dirty_ && first < dirty_from_)
      dirty_spans_.push_back({std::uint32_t(first), std::uint32_t(std::min(end, dirty_from_))});
  }
  // A set's hash is a function of the sum of its elements' hashes, so that
  // whoever edits a set one element at a time (SceneOctree) can keep the sum
  // and hash it in O(1): hashOf(p, n) == hashOfSum(sum of elementHash(p[i]), n).
  static std::uint64_t elementHash(std::uint32_t light) {
    return SplitMix64::mix((std::uint64_t(light) + 1) * SplitMix64::kGolden);
  }
  static std::uint64_t hashOfSum(std::uint64_t sum, std::size_t n) {
    std::uint64_t h = (sum ^ (std::uint64_t(n) * 0xD6E8FEB86659FD93ull)) * 0xBF58476D1CE4E5B9ull;
    return h ^ (h >> 31);
  }
  static std::uint64_t hashOf(const std::uint32_t* p, std::size_t n);
  void release(std::uint32_t offset);
  void clear();

  const std::vector<std::uint32_t>& list() const { return list_; }
  std::size_t garbageEntries() const { return garbage_; }
  // Compaction pays when garbage outweighs the live ranges (the list may
  // reach twice its live size between compactions, plus one update's
  // appends: DynamicLightUpdater compacts at the start of the next update).
  // Small lists are not worth a pass over the data tables.
  static constexpr std::size_t kCompactMinGarbage = 4096;
  bool wantsCompaction() const { return garbage_ > kCompactMinGarbage && garbage_ > list_.size() / 2; }
  // new_offset[old_offset] for every live range start (other entries
  // unspecified); valid until the next compact(). The buffers are kept
  // between compactions (no fresh pages to fault in on every call).
  const std::vector<std::uint32_t>& compact();

  // First list index appended since the last take (list size if none),
  // the spans [first, end) of words rewritten before it (unsorted, maybe
  // overlapping); `all` after clear() or compact().
  struct Span {
    std::uint32_t first, end;
  };
  struct Dirty {
    bool all = false;
    std::size_t from = 0;
    std::vector<Span> spans;
  };
  Dirty takeDirty();

 private:
  struct Rec {
    // capacity: count unless own; an own range's count is in its head
    // unless the head is kBigHead.
    std::uint32_t offset = 0, count = 0, capacity = 0, refs = 0;
    std::uint32_t words() const { return capacity + (own ? kOwnHead : 0u); }
    bool own = false;  // from acquireOwn(): not in the index
    std::uint64_t hash = 0;
  };
  static constexpr std::uint32_t kOwnHead = 1;
  static std::uint32_t headOf(std::uint32_t count, std::uint32_t capacity) {
    return capacity < 0xFFFFu ? count | capacity << 16 : kBigHead;
  }
  std::uint32_t append(const std::vector<std::uint32_t>& set, std::uint64_t hash, bool own);
  void indexInsert(std::uint32_t rec);
  void rebuildIndex(std::size_t capacity);

  std::vector<std::uint32_t> list_;
  std::vector<std::uint32_t> spare_list_, spare_rec_at_, remap_;  // compact()'s buffers
  std::vector<Rec> recs_;
  std::vector<std::uint32_t> free_recs_;
  std::vector<std::uint32_t> rec_at_;  // list index -> rec id (valid at range starts)
  // Open addressing by hash: rec id + 1, 0 = empty. Recs leave it only when
  // compaction drops them, so it needs no tombstones.
  std::vector<std::uint32_t> index_;
  std::size_t garbage_ = 0;
  bool all_dirty_ = true;
  std::size_t dirty_from_ = 0;
  std::vector<Span> dirty_spans_;
};

}  // namespace ml::hashed
