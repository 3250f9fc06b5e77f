#include "host/hashed/LightSetPool.hpp"

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace ml::hashed {

std::uint64_t LightSetPool::hashOf(const std::uint32_t* p, std::size_t n) {
  std::uint64_t h = 0x9E3779B97F4A7C15ull ^ n;
  for (std::size_t i = 0; i < n; ++i) {
    h ^= p[i] + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    h *= 0xBF58476D1CE4E5B9ull;
  }
  return h ^ (h >> 31);
}

std::uint32_t LightSetPool::acquire(const std::vector<std::uint32_t>& set) {
  const std::uint64_t h = hashOf(set.data(), set.size());
  const auto [b, e] = by_hash_.equal_range(h);
  for (auto it = b; it != e; ++it) {
    Rec& r = recs_.at(it->second);
    if (r.count == set.size() &&
        std::memcmp(&list_[it->second], set.data(), set.size() * sizeof(std::uint32_t)) == 0) {
      if (r.refs == 0) garbage_ -= r.count;
      ++r.refs;
      return it->second;
    }
  }
  const std::uint32_t off = std::uint32_t(list_.size());
  if (list_.size() + set.size() > 0xFFFFFFF0ull) throw std::length_error("light index list exceeds 2^32 entries");
  list_.insert(list_.end(), set.begin(), set.end());
  recs_[off] = Rec{std::uint32_t(set.size()), 1, h};
  by_hash_.emplace(h, off);
  return off;
}

void LightSetPool::release(std::uint32_t offset) {
  Rec& r = recs_.at(offset);
  if (r.refs == 0) throw std::logic_error("light set released more often than acquired");
  if (--r.refs == 0) garbage_ += r.count;
}

void LightSetPool::clear() {
  list_.clear();
  recs_.clear();
  by_hash_.clear();
  garbage_ = 0;
  all_dirty_ = true;
}

std::unordered_map<std::uint32_t, std::uint32_t> LightSetPool::compact() {
  std::vector<std::pair<std::uint32_t, Rec>> live;
  live.reserve(recs_.size());
  for (const auto& [off, r] : recs_)
    if (r.refs > 0) live.emplace_back(off, r);
  std::sort(live.begin(), live.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::unordered_map<std::uint32_t, std::uint32_t> remap;
  remap.reserve(live.size());
  std::vector<std::uint32_t> list;
  list.reserve(list_.size() - garbage_);
  recs_.clear();
  by_hash_.clear();
  for (const auto& [off, r] : live) {
    const std::uint32_t n = std::uint32_t(list.size());
    list.insert(list.end(), list_.begin() + off, list_.begin() + off + r.count);
    remap.emplace(off, n);
    recs_[n] = r;
    by_hash_.emplace(r.hash, n);
  }
  list_.swap(list);
  garbage_ = 0;
  all_dirty_ = true;
  return remap;
}

LightSetPool::Dirty LightSetPool::takeDirty() {
  Dirty d{all_dirty_, all_dirty_ ? 0 : dirty_from_};
  all_dirty_ = false;
  dirty_from_ = list_.size();
  return d;
}

}  // namespace ml::hashed
