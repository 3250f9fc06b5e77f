#pragma once
// What changed in one perfect spatial hash since its GPU copy was last
// uploaded: the slots and offset entries that dynamic edits wrote, or `all`
// (after a build, a rehash or a payload remap: the uploader then sends the
// whole table). The hash itself tracks no GPU state: LinklessOctree notes
// what its edits of each table wrote, the uploader takes them.
#include <cstdint>
#include <vector>

namespace ml::hashed {

struct TableEdits {
  bool all = true;
  std::vector<std::uint32_t> slots, offsets;  // unordered, may repeat

  void slot(std::uint32_t s) {
    if (!all) slots.push_back(s);
  }
  void offset(std::uint32_t o) {
    if (!all) offsets.push_back(o);
  }
  void markAll() {
    all = true;
    slots.clear();
    offsets.clear();
  }
};

}  // namespace ml::hashed
