// Pieces of the incremental update with their own contracts: the touched-key
// sort equals std::sort + std::unique, and a light set's hash computed from
// the element-hash sum the scene octree keeps equals the pool's hashOf.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "host/hashed/KeySort.hpp"
#include "host/hashed/LightSetPool.hpp"
#include "host/hashed/SceneOctree.hpp"
#include "support/TestDevice.hpp"

namespace ml::hashed {
namespace {

TEST(HashedKeys, RadixSortEqualsSortAndUnique) {
  std::mt19937_64 rng(7);
  std::vector<std::uint64_t> scratch;
  for (const std::size_t n : {0, 1, 5, 511, 512, 513, 4000, 70000}) {
    for (int shape = 0; shape < 4; ++shape) {
      std::vector<std::uint64_t> keys(n);
      for (auto& k : keys) {
        const unsigned depth = unsigned(rng() % 16);
        const glm::uvec3 c(rng() % 65536, rng() % 65536, rng() % 65536);
        switch (shape) {
          case 0: k = nodeKey(depth, c); break;                        // any node key
          case 1: k = nodeKey(5, c & 31u); break;                      // one depth: high digits constant
          case 2: k = nodeKey(depth, glm::uvec3(c.x % 4, 0, 0)); break; // heavy repeats
          default: k = rng(); break;                                   // all 64 bits
        }
      }
      std::vector<std::uint64_t> want = keys;
      std::sort(want.begin(), want.end());
      want.erase(std::unique(want.begin(), want.end()), want.end());
      sortUniqueKeys(keys, scratch);
      EXPECT_EQ(keys, want) << "n " << n << " shape " << shape;
    }
  }
}

TEST(HashedKeys, SetHashFromTheElementSumEqualsHashOf) {
  std::mt19937_64 rng(11);
  for (int i = 0; i < 200; ++i) {
    std::vector<std::uint32_t> set;
    for (std::uint32_t l = 0; l < 5000; ++l)
      if (rng() % 50 == 0) set.push_back(l);
    std::uint64_t sum = 0;
    for (const auto l : set) sum += LightSetPool::elementHash(l);
    EXPECT_EQ(LightSetPool::hashOfSum(sum, set.size()), LightSetPool::hashOf(set.data(), set.size()));
  }
  // Equal sets share one range; different sets of the same size do not.
  LightSetPool pool;
  auto acquire = [&](const std::vector<std::uint32_t>& set) {
    return pool.acquire(set, LightSetPool::hashOf(set.data(), set.size()));
  };
  const std::vector<std::uint32_t> a{1, 2, 3}, b{1, 2, 4};
  const std::uint32_t oa = acquire(a), ob = acquire(b);
  EXPECT_NE(oa, ob);
  EXPECT_EQ(acquire(a), oa);
}

// Own ranges keep their count and capacity in a head word, or in the side
// table from 65535 words on; resizing and compaction keep both right, and
// compaction repacks each range's live words behind a fresh head.
TEST(HashedKeys, OwnRangesKeepCountAndCapacityThroughResizeAndCompaction) {
  const std::uint64_t seed = test::freshSeed();
  SCOPED_TRACE("seed " + std::to_string(seed));
  std::mt19937_64 rng(seed);
  LightSetPool pool;
  struct Own {
    std::uint32_t offset;
    std::vector<std::uint32_t> words;
  };
  std::vector<Own> own;
  for (const std::size_t n : {std::size_t(1), std::size_t(2), std::size_t(7), std::size_t(58253), std::size_t(58254),
                              std::size_t(65535), std::size_t(70001), std::size_t(33)}) {
    std::vector<std::uint32_t> w(n);
    for (auto& x : w) x = std::uint32_t(rng());
    own.push_back({pool.acquireOwn(w), w});
    EXPECT_EQ(pool.countOf(own.back().offset), n);
    EXPECT_EQ(pool.capacityOf(own.back().offset), LightSetPool::ownCapacity(n)) << n;
  }
  const std::vector<std::uint32_t> set{5, 6, 7};
  const std::uint32_t shared = pool.acquire(set, LightSetPool::hashOf(set.data(), set.size()));
  // Shrink some, grow others within their room, rewrite words in place.
  for (auto& o : own) {
    const std::uint32_t cap = pool.capacityOf(o.offset);
    const std::uint32_t n = 1 + std::uint32_t(rng() % cap);
    o.words.resize(n);
    for (auto& x : o.words) x = std::uint32_t(rng());
    pool.resizeOwn(o.offset, n);
    for (std::size_t k = 0; k < o.words.size(); ++k) pool.rewrite(o.offset + k, o.words[k]);
    EXPECT_EQ(pool.countOf(o.offset), o.words.size());
    EXPECT_EQ(pool.capacityOf(o.offset), cap);
  }
  // The shared range becomes garbage; compaction moves every own range.
  pool.release(shared);
  const auto& remap = pool.compact();
  for (auto& o : own) {
    o.offset = remap[o.offset];
    EXPECT_EQ(pool.countOf(o.offset), o.words.size());
    EXPECT_EQ(pool.capacityOf(o.offset), LightSetPool::ownCapacity(o.words.size()));
    const auto& list = pool.list();
    ASSERT_LE(o.offset + o.words.size(), list.size());
    EXPECT_TRUE(std::equal(o.words.begin(), o.words.end(), list.begin() + o.offset)) << o.words.size();
  }
  EXPECT_EQ(pool.garbageEntries(), 0u);
}

}  // namespace
}  // namespace ml::hashed
