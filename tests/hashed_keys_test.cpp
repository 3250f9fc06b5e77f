// Pieces of the incremental update with their own contracts: the touched-key
// sort equals std::sort + std::unique, and a light set's hash computed from
// the element-hash sum the scene octree keeps equals the pool's hashOf.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>

#include "host/hashed/KeySort.hpp"
#include "host/hashed/LightSetPool.hpp"
#include "host/hashed/SceneOctree.hpp"

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
  const std::vector<std::uint32_t> a{1, 2, 3}, b{1, 2, 4};
  const std::uint32_t oa = pool.acquire(a), ob = pool.acquire(b);
  EXPECT_NE(oa, ob);
  EXPECT_EQ(pool.acquire(a), oa);
  EXPECT_EQ(pool.rangeCount(), 2u);
}

}  // namespace
}  // namespace ml::hashed
