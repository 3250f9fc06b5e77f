#pragma once
// Lefebvre-Hoppe perfect spatial hashing [LH06] as the thesis uses it (§7.1.4):
//   h(p) = (h0(p) + Phi[h1(p)]) mod m,  h0(p) = p mod m,  h1(p) = p mod r,
// per component, with mx*my*mz hash slots and rx*ry*rz offsets of 3 x 8 bits.
// Contract:
//  - build(): the table holds >= n slots (n <= 255) or 1.01 n, times `slack`,
//    the offset table >= sigma n entries (the thesis's sizes: sigma = 1/6,
//    PshBuildParams' default). One departure:
//    the thesis's tables are cubes (m^3, r^3); here each axis gets a share
//    proportional to the keys' extent on it, so that a layer of nodes along
//    one corridor (keys that vary on one axis only) does not need an offset
//    table the size of the corridor's length cubed. For compact key sets
//    the two coincide.
//  - Offset groups are assigned in decreasing size; each first tries the
//    offsets of its assigned neighbours in Phi (coherence), then seeded
//    random candidates, then (when the table is too full for luck) every
//    offset that puts its first key on a free slot. A group that fits
//    nowhere fails the attempt and the offset table
//    grows geometrically (x2 entries); a group whose keys share h0 can never
//    fit, which is checked before assigning and grows it the same way. The
//    hash table grows 5% every 4 failed assignments, so the build always
//    ends. Same keys + seed -> same tables.
//  - The table is stored exactly as the GPU reads it: kWords 32-bit words
//    per slot, the key in the first two (x | y << 16, z in the low half of
//    the second), 0xFFFFFFFF in the first word for an empty slot; offsets as
//    x | y << 8 | z << 16. lookup() is the GLSL lookup (lookup_hashed.glsl)
//    line for line: a present key reads its payload, an absent key reads
//    nothing (the stored key differs), never another key's payload.
//  - Dynamic edits (thesis §8.2.3): insert() writes in place when the key's
//    slot is empty, else re-offsets the key's whole offset group (one Phi
//    entry) into free slots, else reports Failed and the caller rebuilds the
//    table; erase() marks the slot empty (its Phi entry stays). The hash
//    keeps no record of its edits: a caller that uploads partially reads
//    slot() and groupSlots() around them.
//  - Keys are < 2^15 per axis.
#include <glm/glm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <optional>
#include <stdexcept>
#include <vector>

#include "host/util/SplitMix64.hpp"
#include "host/util/Stopwatch.hpp"
#include "host/util/ThesisSeed.hpp"

namespace ml::hashed {

constexpr std::uint32_t kEmptyKeyWord = 0xFFFFFFFFu;
// Offsets are 8 bits per axis.
constexpr std::uint32_t kOffsetRange = 256;
// Up to this many keys a table gets exactly n slots, beyond 1.01 n (LH06's sizing).
constexpr double kExactSizeMaxKeys = 255;
// Offset table growths after which a build is a bug, not bad luck (each
// doubles the table; the hash table grows meanwhile).
constexpr unsigned kMaxOffsetGrowths = 200;
// Random offset candidates per group before the exhaustive search.
constexpr unsigned kRandomOffsetTries = 64;

struct PshBuildParams {
  std::uint64_t seed = kThesisSeed;
  double slack = 1.0;              // slots >= slack * (1.01) n
  double sigma = 1.0 / 6.0;        // offset entries per key (LH06, the thesis: 1/6)
};

struct PshBuildReport {
  unsigned attempts = 0;           // 1 + failed assignments (each grows the offset table)
  std::uint64_t rejected = 0;      // offset candidates that collided
  double ms = 0.0;
};

template <class Traits>
class PerfectSpatialHash {
 public:
  using Payload = typename Traits::Payload;
  static constexpr unsigned kWords = Traits::kWords;
  struct Entry {
    glm::uvec3 key;
    Payload payload;
  };
  enum class InsertResult { InPlace, Reoffset, Failed };

  PerfectSpatialHash() { reset(glm::uvec3(1), glm::uvec3(1)); }

  static PerfectSpatialHash build(const std::vector<Entry>& entries, const PshBuildParams& params,
                                  PshBuildReport* report = nullptr);

  // --- lookup, exactly as lookup_hashed.glsl ---
  std::uint32_t offsetIndex(const glm::uvec3& p) const {
    const glm::uvec3 o = mod(p, r_, fr_);
    return o.x + r_.x * (o.y + r_.y * o.z);
  }
  std::uint32_t slot(const glm::uvec3& p) const {
    const std::uint32_t phi = offsets_[offsetIndex(p)];
    const glm::uvec3 off(phi & 0xFFu, (phi >> 8) & 0xFFu, (phi >> 16) & 0xFFu);
    const glm::uvec3 h = mod(mod(p, m_, fm_) + off, m_, fm_);
    return h.x + m_.x * (h.y + m_.y * h.z);
  }
  static bool keyMatches(const std::uint32_t* w, const glm::uvec3& p) {
    return w[0] == (p.x | (p.y << 16)) && (w[1] & 0xFFFFu) == p.z;
  }
  std::optional<Payload> lookup(const glm::uvec3& p) const { return lookupAt(slot(p), p); }
  // lookup() in two steps, for callers with many keys: they take the slots
  // of a batch and prefetch them before reading any (each read is a cache
  // miss when the table is cold, as it is between frames).
  std::optional<Payload> lookupAt(std::uint32_t s, const glm::uvec3& p) const {
    const std::uint32_t* w = &table_[std::size_t(s) * kWords];
    if (!keyMatches(w, p)) return std::nullopt;
    return Traits::unpack(w);
  }
  void prefetchSlot(std::uint32_t s) const { __builtin_prefetch(&table_[std::size_t(s) * kWords]); }

  // --- dynamic edits ---
  InsertResult insert(const glm::uvec3& key, const Payload& payload, SplitMix64& rng);
  bool update(const glm::uvec3& key, const Payload& payload);
  bool erase(const glm::uvec3& key);
  // The slots of `key`'s offset group (one Phi entry): what a Reoffset
  // insert moves. Valid after trackGroups(), which insert() calls itself.
  void trackGroups();
  const std::vector<std::uint32_t>& groupSlots(const glm::uvec3& key) const { return members_[offsetIndex(key)]; }

  // --- contents and GPU images ---
  glm::uvec3 m() const { return m_; }  // hash table dimensions
  glm::uvec3 r() const { return r_; }  // offset table dimensions
  std::size_t slots() const { return std::size_t(m_.x) * m_.y * m_.z; }
  std::size_t offsetCount() const { return std::size_t(r_.x) * r_.y * r_.z; }
  std::size_t size() const { return size_; }
  std::size_t bytes() const { return table_.size() * 4 + offsets_.size() * 4; }
  const std::vector<std::uint32_t>& tableWords() const { return table_; }
  const std::vector<std::uint32_t>& offsetWords() const { return offsets_; }
  bool slotEmpty(std::uint32_t s) const { return table_[std::size_t(s) * kWords] == kEmptyKeyWord; }
  glm::uvec3 slotKey(std::uint32_t s) const {
    const std::uint32_t* w = &table_[std::size_t(s) * kWords];
    return {w[0] & 0xFFFFu, w[0] >> 16, w[1] & 0xFFFFu};
  }
  Payload slotPayload(std::uint32_t s) const { return Traits::unpack(&table_[std::size_t(s) * kWords]); }
  std::vector<Entry> entries() const {
    std::vector<Entry> out;
    out.reserve(size_);
    for (std::uint32_t s = 0; s < slots(); ++s)
      if (!slotEmpty(s)) out.push_back({slotKey(s), slotPayload(s)});
    return out;
  }
  // Rewrites every payload (e.g. light index list compaction).
  template <class F>
  void remapPayloads(F&& f) {
    for (std::uint32_t s = 0; s < slots(); ++s)
      if (!slotEmpty(s)) writeSlot(s, slotKey(s), f(slotPayload(s)));
  }

 private:
  // p % d per axis by Lemire's fastmod (exact for every 32-bit p): host
  // lookups and builds run these in their inner loops, where 9 divisions
  // per lookup were most of a dynamic update's table work.
  static std::uint64_t fastModConstant(std::uint32_t d) { return ~std::uint64_t(0) / d + 1; }
  static glm::uvec3 mod(const glm::uvec3& p, const glm::uvec3& d, const std::uint64_t* f) {
    glm::uvec3 o;
    for (int a = 0; a < 3; ++a)
      o[a] = std::uint32_t((static_cast<unsigned __int128>(f[a] * p[a]) * d[a]) >> 64);
    return o;
  }
  void reset(const glm::uvec3& m, const glm::uvec3& r) {
    m_ = m;
    r_ = r;
    for (int a = 0; a < 3; ++a) {
      fm_[a] = fastModConstant(m[a]);
      fr_[a] = fastModConstant(r[a]);
    }
    table_.assign(slots() * kWords, 0);
    for (std::size_t s = 0; s < slots(); ++s) table_[s * kWords] = kEmptyKeyWord;
    offsets_.assign(offsetCount(), 0);
    free_.resize(slots());
    free_pos_.resize(slots());
    for (std::uint32_t i = 0; i < free_.size(); ++i) free_[i] = free_pos_[i] = i;
    size_ = 0;
    members_.clear();
  }
  void writeSlot(std::uint32_t s, const glm::uvec3& key, const Payload& payload) {
    if (slotEmpty(s)) {  // take s off the free list (swap with its last entry)
      const std::uint32_t at = free_pos_[s], last = free_.back();
      free_[at] = last;
      free_pos_[last] = at;
      free_.pop_back();
      free_pos_[s] = ~0u;
    }
    std::uint32_t* w = &table_[std::size_t(s) * kWords];
    for (unsigned i = 0; i < kWords; ++i) w[i] = 0;
    w[0] = key.x | (key.y << 16);
    w[1] = key.z;
    Traits::pack(payload, w);
  }
  void clearSlot(std::uint32_t s) {
    if (!slotEmpty(s)) {
      free_pos_[s] = std::uint32_t(free_.size());
      free_.push_back(s);
    }
    std::uint32_t* w = &table_[std::size_t(s) * kWords];
    for (unsigned i = 0; i < kWords; ++i) w[i] = 0;
    w[0] = kEmptyKeyWord;
  }
  static std::uint32_t packOffset(const glm::uvec3& o) { return o.x | (o.y << 8) | (o.z << 16); }
  static glm::uvec3 unpackOffset(std::uint32_t phi) { return {phi & 0xFFu, (phi >> 8) & 0xFFu, (phi >> 16) & 0xFFu}; }
  std::uint32_t slotWith(const glm::uvec3& h0, const glm::uvec3& off) const {
    const glm::uvec3 h = mod(h0 + off, m_, fm_);
    return h.x + m_.x * (h.y + m_.y * h.z);
  }
  // Offset candidates from the 6 neighbours of Phi entry `o` (wrapping).
  template <class F>
  bool tryNeighbours(std::uint32_t o, const std::vector<std::uint8_t>* assigned, F&& fits, glm::uvec3& found) const;
  // Exhaustive search: every offset that puts the group's first key on a
  // free slot (scanned from a random start), checked for the other keys.
  template <class F>
  bool searchFree(const glm::uvec3& h0_first, SplitMix64& rng, F&& fits, glm::uvec3& found) const;
  // True when two of a group's keys share h0: they collide under any offset.
  bool sharesH0(const std::vector<glm::uvec3>& h0) const;
  // An offset that puts every h0 of the group at Phi entry `o` on a free
  // slot (`fits`): its assigned neighbours' offsets, then
  // kRandomOffsetTries random ones, then searchFree().
  template <class F>
  bool findOffset(std::uint32_t o, const std::vector<std::uint8_t>* assigned, const std::vector<glm::uvec3>& h0,
                  SplitMix64& rng, F&& fits, glm::uvec3& found) const;
  enum class Assign { Ok, SharedH0, Failed };
  Assign assignAll(const std::vector<Entry>& entries, SplitMix64& rng, std::uint64_t& rejected);

  glm::uvec3 m_{1}, r_{1};
  std::uint64_t fm_[3] = {0, 0, 0}, fr_[3] = {0, 0, 0};  // fastModConstant(m_), (r_); 0 is d = 1's
  std::vector<std::uint32_t> table_;
  std::vector<std::uint32_t> offsets_;
  std::size_t size_ = 0;
  // Per Phi entry, the slots holding its keys; built on the first dynamic insert.
  std::vector<std::vector<std::uint32_t>> members_;
  // The empty slots, and each slot's position in that list (~0u: occupied).
  std::vector<std::uint32_t> free_, free_pos_;
};

// ---------------------------------------------------------------------------

namespace psh_detail {
// Dimensions with product >= target, each axis's share proportional to the
// keys' extent on it; with `cap`, no axis beyond its extent (an offset table
// wider than the keys' extent only adds empty entries).
inline glm::uvec3 fitDims(double target, const glm::uvec3& extent, bool cap) {
  const glm::dvec3 e(glm::max(extent, glm::uvec3(1)));
  const double scale = std::cbrt(std::max(target, 1.0) / (e.x * e.y * e.z));
  glm::uvec3 d;
  for (int a = 0; a < 3; ++a) d[a] = std::uint32_t(std::max(1.0, std::floor(e[a] * scale)));
  if (cap) d = glm::min(d, glm::uvec3(e));
  while (double(d.x) * d.y * d.z < target) {
    int best = -1;
    double ratio = 0.0;
    for (int a = 0; a < 3; ++a) {
      if (cap && d[a] >= std::uint32_t(e[a])) continue;
      const double q = e[a] / double(d[a]);
      if (q > ratio) ratio = q, best = a;
    }
    if (best < 0) break;
    ++d[best];
  }
  return d;
}
inline glm::uvec3 coprime(glm::uvec3 r, const glm::uvec3& m) {
  for (int a = 0; a < 3; ++a)
    while (std::gcd(r[a], m[a]) != 1) ++r[a];
  return r;
}
inline double volume(const glm::uvec3& d) { return double(d.x) * d.y * d.z; }
}  // namespace psh_detail

template <class Traits>
template <class F>
bool PerfectSpatialHash<Traits>::tryNeighbours(std::uint32_t o, const std::vector<std::uint8_t>* assigned, F&& fits,
                                               glm::uvec3& found) const {
  const glm::uvec3 q(o % r_.x, (o / r_.x) % r_.y, o / (r_.x * r_.y));
  std::uint32_t tried[6];
  int ntried = 0;
  for (int a = 0; a < 3; ++a)
    for (int s = -1; s <= 1; s += 2) {
      glm::uvec3 nq = q;
      nq[a] = (q[a] + r_[a] + std::uint32_t(s)) % r_[a];
      const std::uint32_t no = nq.x + r_.x * (nq.y + r_.y * nq.z);
      if (no == o) continue;
      if (assigned ? !(*assigned)[no] : members_[no].empty()) continue;
      const std::uint32_t phi = offsets_[no];
      if (std::find(tried, tried + ntried, phi) != tried + ntried) continue;
      tried[ntried++] = phi;
      if (fits(unpackOffset(phi))) {
        found = unpackOffset(phi);
        return true;
      }
    }
  return false;
}

template <class Traits>
template <class F>
bool PerfectSpatialHash<Traits>::searchFree(const glm::uvec3& h0, SplitMix64& rng, F&& fits, glm::uvec3& found) const {
  const std::uint32_t n = std::uint32_t(free_.size());
  if (n == 0) return false;
  const std::uint32_t start = rng.below(n);
  for (std::uint32_t i = 0; i < n; ++i) {
    const std::uint32_t s = free_[(start + i) % n];
    const glm::uvec3 h(s % m_.x, (s / m_.x) % m_.y, s / (m_.x * m_.y));
    const glm::uvec3 off = (h + m_ - h0) % m_;
    if (off.x < kOffsetRange && off.y < kOffsetRange && off.z < kOffsetRange && fits(off)) {
      found = off;
      return true;
    }
  }
  return false;
}

template <class Traits>
bool PerfectSpatialHash<Traits>::sharesH0(const std::vector<glm::uvec3>& h0) const {
  std::vector<std::uint32_t> index(h0.size());
  for (std::size_t i = 0; i < h0.size(); ++i) index[i] = h0[i].x + m_.x * (h0[i].y + m_.y * h0[i].z);
  std::sort(index.begin(), index.end());
  return std::adjacent_find(index.begin(), index.end()) != index.end();
}

template <class Traits>
template <class F>
bool PerfectSpatialHash<Traits>::findOffset(std::uint32_t o, const std::vector<std::uint8_t>* assigned,
                                            const std::vector<glm::uvec3>& h0, SplitMix64& rng, F&& fits,
                                            glm::uvec3& off) const {
  if (tryNeighbours(o, assigned, fits, off)) return true;
  const glm::uvec3 range = glm::min(m_, glm::uvec3(kOffsetRange));
  for (unsigned t = 0; t < kRandomOffsetTries; ++t) {
    off = glm::uvec3(rng.below(range.x), rng.below(range.y), rng.below(range.z));
    if (fits(off)) return true;
  }
  return searchFree(h0[0], rng, fits, off);
}

template <class Traits>
typename PerfectSpatialHash<Traits>::Assign PerfectSpatialHash<Traits>::assignAll(const std::vector<Entry>& entries,
                                                                                  SplitMix64& rng,
                                                                                  std::uint64_t& rejected) {
  const std::uint32_t r = std::uint32_t(offsetCount());
  const std::size_t n = entries.size();
  // Group keys by Phi entry (counting sort), then order the groups by size.
  std::vector<std::uint32_t> start(r + 1, 0), order(n);
  for (const auto& e : entries) ++start[offsetIndex(e.key) + 1];
  std::uint32_t max_group = 0;
  for (std::uint32_t o = 0; o < r; ++o) max_group = std::max(max_group, start[o + 1]);
  for (std::uint32_t o = 0; o < r; ++o) start[o + 1] += start[o];
  {
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::uint32_t i = 0; i < n; ++i) order[fill[offsetIndex(entries[i].key)]++] = i;
  }
  std::vector<std::uint32_t> by_size_start(max_group + 2, 0), groups;
  for (std::uint32_t o = 0; o < r; ++o) ++by_size_start[max_group - (start[o + 1] - start[o]) + 1];
  for (std::uint32_t s = 0; s <= max_group; ++s) by_size_start[s + 1] += by_size_start[s];
  groups.resize(r);
  for (std::uint32_t o = 0; o < r; ++o) groups[by_size_start[max_group - (start[o + 1] - start[o])]++] = o;

  std::vector<std::uint8_t> assigned(r, 0);
  std::vector<glm::uvec3> h0;
  // Keys of one group sharing h0 collide under any offset: only a larger
  // offset table separates them. Cheap to see before placing anything.
  for (std::uint32_t o = 0; o < r; ++o) {
    if (start[o + 1] - start[o] < 2) continue;
    h0.clear();
    for (std::uint32_t i = start[o]; i < start[o + 1]; ++i) h0.push_back(entries[order[i]].key % m_);
    if (sharesH0(h0)) return Assign::SharedH0;
  }
  for (const std::uint32_t o : groups) {
    const std::uint32_t b = start[o], e = start[o + 1];
    if (b == e) break;  // the rest are empty groups
    h0.clear();
    for (std::uint32_t i = b; i < e; ++i) h0.push_back(entries[order[i]].key % m_);
    auto fits = [&](const glm::uvec3& off) {
      for (const auto& h : h0)
        if (!slotEmpty(slotWith(h, off))) {
          ++rejected;
          return false;
        }
      return true;
    };
    glm::uvec3 off;
    if (!findOffset(o, &assigned, h0, rng, fits, off)) return Assign::Failed;
    offsets_[o] = packOffset(off);
    assigned[o] = 1;
    for (std::uint32_t i = b; i < e; ++i) {
      const Entry& en = entries[order[i]];
      writeSlot(slotWith(h0[i - b], off), en.key, en.payload);
    }
  }
  size_ = n;
  return Assign::Ok;
}

template <class Traits>
PerfectSpatialHash<Traits> PerfectSpatialHash<Traits>::build(const std::vector<Entry>& entries,
                                                             const PshBuildParams& params, PshBuildReport* report) {
  using namespace psh_detail;
  const auto t0 = SteadyClock::now();
  const double n = double(entries.size());
  glm::uvec3 lo(~0u), hi(0u);
  for (const auto& e : entries) {
    lo = glm::min(lo, e.key);
    hi = glm::max(hi, e.key);
  }
  const glm::uvec3 extent = entries.empty() ? glm::uvec3(1) : hi - lo + 1u;
  double m_target = std::max(1.0, (n <= kExactSizeMaxKeys ? n : std::ceil(1.01 * n)) * std::max(1.0, params.slack));
  double r_target = std::max(1.0, n * std::clamp(params.sigma, 1e-3, 1.0));
  glm::uvec3 m = fitDims(m_target, extent, false);
  glm::uvec3 r = coprime(fitDims(r_target, extent, true), m);
  SplitMix64 rng{params.seed};
  PshBuildReport rep;
  PerfectSpatialHash h;
  unsigned failures = 0, growths = 0;
  for (;;) {
    h.reset(m, r);
    const Assign result = h.assignAll(entries, rng, rep.rejected);
    if (result == Assign::Ok) break;
    if (result == Assign::Failed && ++failures % 4 == 0) {
      m_target = volume(m) * 1.05;
      m = fitDims(m_target, extent, false);
    }
    // Grow the offset table geometrically; once it spans the keys' extent
    // (h1 is injective) only a larger hash table can help.
    r_target = std::max(r_target, volume(r)) * 2.0;
    const glm::uvec3 grown = fitDims(r_target, extent, true);
    if (volume(grown) <= volume(r) && result == Assign::SharedH0) {
      m_target = volume(m) * 1.05;
      m = fitDims(m_target, extent, false);
    }
    r = coprime(grown, m);
    if (++growths > kMaxOffsetGrowths)
      throw std::logic_error("perfect spatial hash: construction does not converge");
  }
  rep.attempts = failures + 1;
  rep.ms = msSince(t0);
  if (report) *report = rep;
  return h;
}

template <class Traits>
void PerfectSpatialHash<Traits>::trackGroups() {
  if (!members_.empty()) return;
  members_.assign(offsetCount(), {});
  for (std::uint32_t s = 0; s < slots(); ++s)
    if (!slotEmpty(s)) members_[offsetIndex(slotKey(s))].push_back(s);
}

template <class Traits>
typename PerfectSpatialHash<Traits>::InsertResult PerfectSpatialHash<Traits>::insert(const glm::uvec3& key,
                                                                                    const Payload& payload,
                                                                                    SplitMix64& rng) {
  trackGroups();
  const std::uint32_t s = slot(key);
  if (keyMatches(&table_[std::size_t(s) * kWords], key)) {
    update(key, payload);
    return InsertResult::InPlace;
  }
  const std::uint32_t o = offsetIndex(key);
  if (slotEmpty(s)) {
    writeSlot(s, key, payload);
    members_[o].push_back(s);
    ++size_;
    return InsertResult::InPlace;
  }
  // Re-offset the key's group: lift its keys out, find an offset where the
  // group plus the new key land in free slots, else put everything back.
  struct Lifted {
    std::uint32_t slot;
    glm::uvec3 key;
    Payload payload;
  };
  std::vector<Lifted> group;
  for (const std::uint32_t gs : members_[o]) group.push_back({gs, slotKey(gs), slotPayload(gs)});
  group.push_back({~0u, key, payload});
  std::vector<glm::uvec3> h0;
  for (const auto& g : group) h0.push_back(g.key % m_);
  if (sharesH0(h0)) return InsertResult::Failed;
  for (const auto& g : group)
    if (g.slot != ~0u) clearSlot(g.slot);
  auto fits = [&](const glm::uvec3& off) {
    for (const auto& h : h0)
      if (!slotEmpty(slotWith(h, off))) return false;
    return true;
  };
  glm::uvec3 off;
  // members_[o] is still listed, so tryNeighbours skips o itself by index.
  if (!findOffset(o, nullptr, h0, rng, fits, off)) {
    for (const auto& g : group)
      if (g.slot != ~0u) writeSlot(g.slot, g.key, g.payload);
    return InsertResult::Failed;
  }
  offsets_[o] = packOffset(off);
  members_[o].clear();
  for (std::size_t i = 0; i < group.size(); ++i) {
    const std::uint32_t ns = slotWith(h0[i], off);
    writeSlot(ns, group[i].key, group[i].payload);
    members_[o].push_back(ns);
  }
  ++size_;
  return InsertResult::Reoffset;
}

template <class Traits>
bool PerfectSpatialHash<Traits>::update(const glm::uvec3& key, const Payload& payload) {
  const std::uint32_t s = slot(key);
  if (!keyMatches(&table_[std::size_t(s) * kWords], key)) return false;
  writeSlot(s, key, payload);
  return true;
}

template <class Traits>
bool PerfectSpatialHash<Traits>::erase(const glm::uvec3& key) {
  const std::uint32_t s = slot(key);
  if (!keyMatches(&table_[std::size_t(s) * kWords], key)) return false;
  clearSlot(s);
  if (!members_.empty()) {
    auto& mem = members_[offsetIndex(key)];
    mem.erase(std::find(mem.begin(), mem.end(), s));
  }
  --size_;
  return true;
}

// ---------------------------------------------------------------------------
// Payload traits of the two tables of a linkless octree layer.

// Octree description: the leaf and filled masks of a branch's 8 children,
// in the upper half of the key's second word (2 words per slot).
struct DescTraits {
  struct Payload {
    std::uint8_t leaf = 0, filled = 0;
    bool operator==(const Payload&) const = default;
  };
  static constexpr unsigned kWords = 2;
  static void pack(const Payload& p, std::uint32_t* w) {
    w[1] |= (std::uint32_t(p.leaf) << 16) | (std::uint32_t(p.filled) << 24);
  }
  static Payload unpack(const std::uint32_t* w) {
    return {std::uint8_t((w[1] >> 16) & 0xFFu), std::uint8_t(w[1] >> 24)};
  }
};

// Light data of a filled leaf: its range in the light index list (4 words).
struct DataTraits {
  struct Payload {
    std::uint32_t offset = 0, count = 0;
    bool operator==(const Payload&) const = default;
  };
  static constexpr unsigned kWords = 4;
  static void pack(const Payload& p, std::uint32_t* w) {
    w[2] = p.offset;
    w[3] = p.count;
  }
  static Payload unpack(const std::uint32_t* w) { return {w[2], w[3]}; }
};

using DescHash = PerfectSpatialHash<DescTraits>;
using DataHash = PerfectSpatialHash<DataTraits>;

}  // namespace ml::hashed
