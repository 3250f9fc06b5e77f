#pragma once
// The light index list (thesis Fig. 7.8) with each distinct light set stored
// once: filled leaves with equal sets (common: siblings that could not merge
// because of a third sibling) share one range. Contract:
//  - acquire(set) returns the offset of an identical range, appending the set
//    if it is new, and takes a reference; release(offset) drops one. A range
//    without references is garbage until compact() repacks the live ranges
//    and returns the old -> new offsets, which callers apply to every data
//    entry. Sets are sorted light indices, so equal sets are equal ranges.
//  - Appends and compactions are recorded for partial uploads.
#include <cstdint>
#include <unordered_map>
#include <vector>

namespace ml::hashed {

class LightSetPool {
 public:
  std::uint32_t acquire(const std::vector<std::uint32_t>& set);
  void release(std::uint32_t offset);
  void clear();

  const std::vector<std::uint32_t>& list() const { return list_; }
  std::size_t liveEntries() const { return list_.size() - garbage_; }
  std::size_t garbageEntries() const { return garbage_; }
  std::size_t rangeCount() const { return recs_.size(); }
  // Compaction pays when at least half the list is garbage.
  bool wantsCompaction() const { return garbage_ > 4096 && garbage_ > list_.size() / 2; }
  std::unordered_map<std::uint32_t, std::uint32_t> compact();

  // First list index written since the last take (list size if none);
  // `all` after clear() or compact().
  struct Dirty {
    bool all = false;
    std::size_t from = 0;
  };
  Dirty takeDirty();

 private:
  struct Rec {
    std::uint32_t count = 0;
    std::uint32_t refs = 0;
    std::uint64_t hash = 0;
  };
  static std::uint64_t hashOf(const std::uint32_t* p, std::size_t n);
  std::vector<std::uint32_t> list_;
  std::unordered_map<std::uint32_t, Rec> recs_;               // by offset
  std::unordered_multimap<std::uint64_t, std::uint32_t> by_hash_;  // -> offset
  std::size_t garbage_ = 0;
  bool all_dirty_ = true;
  std::size_t dirty_from_ = 0;
};

}  // namespace ml::hashed
